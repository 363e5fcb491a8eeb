#!/usr/bin/python3
"""calibrate_tests.py: end-to-end tests of isosim --calibrate against a hidden machine.

Usage: calibrate_tests.py CASE --tool ISOSIM --out-dir DIR
       calibrate_tests.py --list

CASE is the name of one function case_<CASE> below; tests/calibrate/CMakeLists.txt registers
each one as the CTest test calibrate/<CASE>. The "measured" cycle times are those isosim
prints for the programs of this folder on hidden.json (the built-in machine with four keys
changed: HIDDEN below); the calibration starts from the built-in machine (or another one) and
must give the hidden values back within 0.5 %.

Exit status: 0 pass, 1 fail (the reason on stderr). Uses only the standard library.
"""
import json
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
PROGRAMS = ["x_accel.mpf", "y_rapid.mpf", "m23.mpf", "blocks.mpf", "diagonal.mpf", "mixed.mpf"]
# The keys hidden.json changes from the built-in machine, with the built-in values.
HIDDEN = {"axes.X.max_accel": 2000, "axes.Y.max_velocity": 500, "block_time_s": 0,
          "m_sequences.23.duration_s": 0}


class Failure(Exception):
    pass


def check(cond, why):
    if not cond:
        raise Failure(why)


def run(args, cwd, rc=0):
    p = subprocess.run(args, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=120)
    out, err = p.stdout.decode(), p.stderr.decode()
    check(rc is None or p.returncode == rc,
          f"{' '.join(args)}: exit {p.returncode}, expected {rc}\nstdout:\n{out}\nstderr:\n{err}")
    return p.returncode, out, err


def key_value(machine, key):
    """The value of a --set key path in a machine document (an axis by its name)."""
    at = machine
    for part in key.split("."):
        if isinstance(at, list):
            at = next(a for a in at if a["name"] == part)
        else:
            at = at[part]
    return at


def hidden_values():
    with open(os.path.join(HERE, "hidden.json")) as f:
        machine = json.load(f)
    values = {k: key_value(machine, k) for k in HIDDEN}
    for k, builtin in HIDDEN.items():  # the hidden machine differs from the start on every key
        check(abs(values[k] - builtin) > 0.1 * max(abs(values[k]), abs(builtin)),
              f"hidden.json: {k} = {values[k]} is too close to the built-in {builtin}")
    return values


def measured_csv(tool, out_dir, programs=PROGRAMS, name="measured.csv"):
    """The CSV of the programs' cycle times on hidden.json, in out_dir (paths relative to it)."""
    lines = ["# cycle times of the programs on hidden.json", "program,cycle_time_s"]
    for p in programs:
        _, out, _ = run([tool, p, "--summary", "--format", "json", "--machine", "hidden.json"], HERE)
        summary = json.loads(out)
        check(summary["status"] == "ok", f"{p} on hidden.json: {summary}")
        lines.append(f"{os.path.relpath(os.path.join(HERE, p), out_dir)},{summary['cycle_time_s']}")
    path = os.path.join(out_dir, name)
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


def calibrate(tool, out_dir, keys, extra=(), rc=0):
    args = [tool, "--calibrate", "measured.csv", "--format", "json", "-j", "2"]
    for k in keys:
        args += ["--fit", k]
    _, out, err = run(args + list(extra), out_dir, rc)
    return json.loads(out) if rc == 0 else err


def check_fitted(report, expected):
    fitted = {k["key"]: k for k in report["keys"]}
    for key, want in expected.items():
        got = fitted[key]["fitted"]
        check(fitted[key]["determined"], f"{key} reported not determined: {report}")
        check(abs(got - want) <= 0.005 * abs(want), f"{key}: fitted {got}, hidden {want} (more than 0.5 % off)")


def case_roundtrip(tool, out_dir):
    """From the built-in machine, the four hidden values back within 0.5 %, no warning."""
    hidden = hidden_values()
    measured_csv(tool, out_dir)
    report = calibrate(tool, out_dir, list(HIDDEN), ["-o", "fitted.json"])
    check_fitted(report, hidden)
    check(report["converged"] and report["warnings"] == [], f"warnings: {report['warnings']}")
    check(report["rms_s"] <= 1e-5, f"rms {report['rms_s']} s")
    for k in report["keys"]:
        check(k["start"] == HIDDEN[k["key"]], f"{k['key']} started at {k['start']}, not the built-in value")
    # the fitted machine file: valid, the fitted values, the rest of the built-in machine
    with open(os.path.join(out_dir, "fitted.json")) as f:
        fitted = json.load(f)
    for k in report["keys"]:
        check(key_value(fitted, k["key"]) == k["fitted"], f"fitted.json: {k['key']} is not {k['fitted']}")
    check(key_value(fitted, "axes.Z.max_accel") == 2000 and key_value(fitted, "axes.X.max_velocity") == 500,
          "fitted.json changed a key that was not fitted")
    # the model times of the report are those isosim gives on the fitted machine file
    for row in report["rows"]:
        _, out, _ = run([tool, row["program"], "--summary", "--format", "json", "--machine", "fitted.json"],
                        out_dir)
        check(json.loads(out)["cycle_time_s"] == row["model_s"], f"{row['program']}: {out} against {row}")


def case_far_start(tool, out_dir):
    """From a machine far from the hidden one (X 4x weaker, Y 2.5x slower, the times 10 times too
    long). (A Y faster than the hidden one would not do: no Y rapid reaches 1500 mm/s, so no
    cycle time depends on it there.)"""
    hidden = hidden_values()
    measured_csv(tool, out_dir)
    report = calibrate(tool, out_dir, ["axes.X.max_accel,axes.Y.max_velocity", "block_time_s",
                                       "m_sequences.23.duration_s"],
                       ["--set", "axes.X.max_accel=750", "--set", "axes.Y.max_velocity=140",
                        "--set", "block_time_s=0.04", "--set", "m_sequences.23.duration_s=12"])
    check_fitted(report, hidden)
    check(report["converged"], f"not converged: {report}")


def case_undetermined(tool, out_dir):
    """A key no program depends on (Z never moves) is left at its start with a warning; the
    others are still fitted."""
    hidden = hidden_values()
    measured_csv(tool, out_dir)
    report = calibrate(tool, out_dir, list(HIDDEN) + ["axes.Z.max_accel"])
    check_fitted(report, hidden)
    z = next(k for k in report["keys"] if k["key"] == "axes.Z.max_accel")
    check(not z["determined"] and z["fitted"] == 2000, f"Z: {z}")
    check(report["warnings"] == ["axes.Z.max_accel is not determined by these programs (no cycle time depends "
                                 "on it): left at 2000"], f"warnings: {report['warnings']}")


def case_together(tool, out_dir):
    """Programs in which M23 always comes with the same number of blocks cannot tell
    block_time_s from the M23 duration: both are left at their start, both named."""
    measured_csv(tool, out_dir, ["m23.mpf"])
    report = calibrate(tool, out_dir, ["block_time_s", "m_sequences.23.duration_s"])
    check(all(not k["determined"] and k["fitted"] == 0 for k in report["keys"]), f"{report['keys']}")
    check(len(report["warnings"]) == 2 and all("only together with" in w for w in report["warnings"]),
          f"warnings: {report['warnings']}")


def case_output_not_input(tool, out_dir):
    """-o onto an input (the starting machine file) is refused before anything runs."""
    measured_csv(tool, out_dir)
    shutil.copy(os.path.join(HERE, "hidden.json"), os.path.join(out_dir, "start.json"))
    with open(os.path.join(out_dir, "start.json"), "rb") as f:
        before = f.read()
    err = calibrate(tool, out_dir, ["block_time_s"], ["--machine", "start.json", "-o", "start.json"], rc=2)
    check("would overwrite the input start.json" in err, f"stderr: {err}")
    with open(os.path.join(out_dir, "start.json"), "rb") as f:
        check(f.read() == before, "start.json changed")
    err = calibrate(tool, out_dir, ["block_time_s"], ["-o", "measured.csv"], rc=2)
    check("would overwrite the input measured.csv" in err, f"stderr: {err}")


def main(argv):
    cases = {n[5:]: f for n, f in globals().items() if n.startswith("case_")}
    if argv[1:] == ["--list"]:
        print("\n".join(sorted(cases)))
        return 0
    name, tool, out_dir = argv[1], None, None
    for i, a in enumerate(argv):
        if a == "--tool":
            tool = os.path.abspath(argv[i + 1])
        elif a == "--out-dir":
            out_dir = os.path.join(os.path.abspath(argv[i + 1]), name)
    shutil.rmtree(out_dir, ignore_errors=True)
    os.makedirs(out_dir)
    try:
        cases[name](tool, out_dir)
    except Failure as e:
        print(f"calibrate/{name}: FAIL: {e}", file=sys.stderr)
        return 1
    print(f"calibrate/{name}: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
