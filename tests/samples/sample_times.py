#!/usr/bin/python3
"""sample_times.py: the cycle time of a sample program set against the time computed by hand
from the timing model of isosim(1) (trapezoidal profiles, M durations of the machine file,
block_time_s), as its README shows it.

Usage: sample_times.py CASE --bin DIR --source DIR

CASE is the name of one function case_<CASE> below; tests/samples/CMakeLists.txt registers
it as the CTest test samples/<CASE>.  --bin is the directory holding isolint and isosim;
--source is the source tree.  Each case runs `isosim PROGRAM --summary --format json` (the
set's isotools.toml names its machine file) and compares cycle_time_s with the hand-computed
expression written out below, to 1e-9 relative, then the other fields of the summary.

Exit status: 0 pass, 1 fail (the reasons on stderr).  Standard library only.
"""
import argparse
import json
import math
import os
import subprocess
import sys

BIN = None
SOURCE = None


class Failure(Exception):
    pass


def trap(d, v, a):
    """A move of length d from rest to rest at velocity limit v and acceleration a."""
    return d / v + v / a if d >= v * v / a else 2 * math.sqrt(d / a)


def run(args, cwd):
    p = subprocess.run(args, cwd=cwd, capture_output=True, timeout=60)
    return p.returncode, p.stdout.decode("utf-8", "replace"), p.stderr.decode("utf-8", "replace")


def summary_of(rel_program):
    """The JSON summary of isosim on a sample main program, run from the source tree."""
    rc, out, err = run([os.path.join(BIN, "isosim"), rel_program, "--summary", "--format", "json"],
                       SOURCE)
    if rc != 0:
        raise Failure(f"isosim {rel_program} --summary --format json: exit {rc}\n{out}{err}")
    try:
        return json.loads(out)
    except ValueError as e:
        raise Failure(f"isosim printed no JSON summary ({e}):\n{out}{err}")


def lint_clean(rel_dir):
    """isolint on the whole set: exit 0 and not one diagnostic (samples/README.md)."""
    rc, out, err = run([os.path.join(BIN, "isolint"), rel_dir, "--format", "json"], SOURCE)
    fails = []
    try:
        doc = json.loads(out)
    except ValueError:
        return [f"isolint {rel_dir} --format json: exit {rc}, no JSON:\n{out}{err}"]
    if rc != 0 or doc.get("diagnostics"):
        shown = "\n".join(f"  {d['file']}:{d['line']}: {d['code']} {d['message']}"
                          for d in doc.get("diagnostics", []))
        fails.append(f"isolint {rel_dir}: exit {rc}, the set does not lint clean:\n{shown}{err}")
    return fails


def compare(summary, expected_time, fields):
    fails = []
    got = summary.get("cycle_time_s")
    if not isinstance(got, (int, float)) or abs(got - expected_time) > 1e-9 * expected_time:
        fails.append(f"cycle_time_s: {got!r}, computed by hand {expected_time!r}")
    for key, want in fields.items():
        if summary.get(key) != want:
            fails.append(f"{key}: {summary.get(key)!r}, expected {want!r}")
    return fails


def case_z32_flow():
    """samples/z32_flow/staffa_forata.mpf: forward GO, four GO ranges, an origin, a tool change
    and a GOP call (samples/z32_flow/README.md computes the same terms)."""
    B = 0.01                                   # block_time_s, charged at every statement
    X = Y = (500, 2500)                        # max_velocity, max_accel of X and Y
    Z = (250, 2500)                            # and of Z
    # one pass of the range N50..N70, entered at program Z2 (machine Z-48)
    hole = (B + trap(16, 5, Z[1])              # N50 G01 Z-14 F5: 16 mm at 5 mm/s
            + B + 0.5                          # N60 G04 F0.5
            + B + trap(16, *Z))                # N70 G00 Z2: 16 mm rapid
    expected = (
        B                                      # N10 G90 G60 G17
        + B                                    # N20 GON100 (N50..N70 are skipped)
        + B                                    # N100 O1: origin X100 Y40 Z-50
        + B + 4.0                              # N110 T1 M6: M6 sequence 4 s
        + B + 1.0 + 0.2                        # N120 S1500 M3 M8
        + B + max(trap(120, *X), trap(50, *Y))   # N130 G00 X20 Y10: machine X120 Y50
        + B + trap(148, *Z)                    # N140 G00 Z2: machine Z100 -> -48
        + B + hole                             # N150 GON50-N70 (hole 1)
        + B + trap(64, *X)                     # N160 G00 X84
        + B + hole                             # N170 GON50-N70 (hole 2)
        + B + trap(36, *Y)                     # N180 G00 Y46
        + B + hole                             # N190 GON50-N70 (hole 3)
        + B + trap(64, *X)                     # N200 G00 X20
        + B + hole                             # N210 GON50-N70 (hole 4)
        + B + 0.2                              # N220 M9
        + B + trap(48, *Z) + 0.5               # N230 G00 Z50 M5: the move, then M5
        + B                                    # N240 O0
        + B                                    # N250 GOPSCARICO
        + B                                    #   G90 G60
        + B + trap(100, *Z)                    #   G00 Z100: machine Z0 -> 100
        + B + max(trap(120, *X), trap(314, *Y))  # G00 X0 Y400: from X120 Y86
        + B                                    #   M17
        + B                                    # N260 M30
    )
    # the README's figure, so that the expression above and the README cannot drift apart
    fails = [] if abs(expected - 25.33) < 1e-9 else [f"hand computation {expected!r} is not 25.33"]
    # the spindle turns from the start of M3 (N120) to the start of M5 (N230)
    m3 = 5 * B + 4.0
    m5 = (m3 + 1.2 + B + trap(120, *X) + B + trap(148, *Z) + 4 * (B + hole)
          + B + trap(64, *X) + B + trap(36, *Y) + B + trap(64, *X) + B + 0.2 + B + trap(48, *Z))
    fails += lint_clean("samples/z32_flow")
    try:
        s = summary_of("samples/z32_flow/staffa_forata.mpf")
    except Failure as e:
        raise Failure("\n".join(fails + [str(e)]))
    fails += compare(s, expected, {
        "status": "ok",
        "final_position": {"X": 0, "Y": 400, "Z": 100},   # machine coordinates
        "blocks": 35,        # 19 lines of the main program, 12 of the four ranges, 4 of SCARICO
        "tool_changes": 1,
        "tool": 1,
        "origin": 0,
    })
    on = s.get("spindle_on_s")
    if not isinstance(on, (int, float)) or abs(on - (m5 - m3)) > 1e-9 * (m5 - m3):
        fails.append(f"spindle_on_s: {on!r}, computed by hand {m5 - m3!r}")
    if fails:
        raise Failure("\n".join(fails))


CASES = {name[len("case_"):]: f for name, f in globals().items() if name.startswith("case_")}


def main():
    global BIN, SOURCE
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("case", choices=sorted(CASES))
    ap.add_argument("--bin", required=True, help="the directory of isolint and isosim")
    ap.add_argument("--source", required=True, help="the source tree (samples/)")
    a = ap.parse_args()
    BIN, SOURCE = os.path.abspath(a.bin), os.path.abspath(a.source)
    try:
        CASES[a.case]()
    except Failure as e:
        sys.exit(f"FAIL samples/{a.case}:\n{e}")
    print(f"ok   samples/{a.case}")


if __name__ == "__main__":
    main()
