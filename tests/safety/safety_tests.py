#!/usr/bin/python3
"""safety_tests.py: end-to-end tests of the issue "safety at every edge" (SPEC.md sections 2
and 8, man/isolint.1, man/isocc.1, man/isosim.1).

Usage: safety_tests.py CASE --bin DIR --source DIR
       safety_tests.py --list

CASE is the name of one function case_<CASE> below; tests/safety/CMakeLists.txt registers
each one as the CTest test safety/<CASE>.  --bin is the directory holding isolint, isocc and
isosim; --source is the source tree (the SARIF schema is looked up in <source>/../shared).
Every case works in its own temporary directory and builds its inputs there.

Exit status: 0 pass, 1 fail (the reasons on stderr), 77 skipped (the SARIF schema of
../shared is absent, or a memory check on a sanitizer build: ISO_SANITIZE_BUILD=1).
Uses only the standard library and, for the schema check, python3-jsonschema.
"""
import argparse
import glob
import json
import os
import pty
import re
import select
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import threading
import time

SKIP = 77
BIN = None
SOURCE = None

KB = 1024
MIB = 1024 * 1024
OUTPUT_LIMIT = 100 * KB      # "stays under 100 kB of text output"
RSS_LIMIT = 200 * MIB        # "peak RSS stays under 200 MiB"


class Failure(Exception):
    pass


class Skip(Exception):
    pass


def check(cond, msg):
    if not cond:
        raise Failure(msg)


def show(data, limit=1500):
    """Bytes as readable text for a failure message, cut to `limit` characters."""
    if isinstance(data, bytes):
        data = data.decode("utf-8", errors="backslashreplace")
    if len(data) > limit:
        data = data[:limit] + f"... [{len(data) - limit} more characters]"
    return data


# ----------------------------------------------------------------------------------------
# Running the tools

def tool(name):
    """Path of a tool; waits (up to 60 s) while another build briefly removes it."""
    path = os.path.join(BIN, name)
    deadline = time.monotonic() + 60
    while not os.access(path, os.X_OK):
        if time.monotonic() > deadline:
            raise Failure(f"{path} does not exist (is the project built?)")
        time.sleep(0.2)
    return path


class Result:
    def __init__(self, cmd, rc, out, err):
        self.cmd, self.rc, self.out, self.err = cmd, rc, out, err

    def what(self):
        return " ".join(a.decode("utf-8", "backslashreplace") if isinstance(a, bytes) else a
                        for a in self.cmd)

    def describe(self):
        return (f"command: {self.what()}\nexit: {self.rc}\nstdout:\n{show(self.out)}\n"
                f"stderr:\n{show(self.err)}")


def _popen_retry(argv, **kw):
    for attempt in range(50):
        try:
            return subprocess.Popen(argv, **kw)
        except OSError as e:  # ETXTBSY / ENOENT while the binary is being relinked
            if attempt == 49:
                raise
            time.sleep(0.2)
            argv = [tool(os.path.basename(argv[0])) if i == 0 else a for i, a in enumerate(argv)]
    raise AssertionError("unreachable")


def run(name, *args, cwd, stdin=subprocess.DEVNULL, timeout=30, env=None):
    """Runs tool `name` with `args` (str or bytes) in `cwd`; returns a Result."""
    argv = [tool(name)] + list(args)
    p = _popen_retry(argv, cwd=cwd, stdin=stdin, stdout=subprocess.PIPE,
                     stderr=subprocess.PIPE, env=env)
    try:
        out, err = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        p.kill()
        out, err = p.communicate()
        raise Failure(f"timed out after {timeout} s: {name} {args}")
    return Result([name] + list(args), p.returncode, out, err)


def run_measured(name, *args, cwd, timeout=30):
    """Runs a tool with stdout/stderr in files; returns (Result, peak RSS in bytes)."""
    argv = [tool(name)] + list(args)
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        p = _popen_retry(argv, cwd=cwd, stdin=subprocess.DEVNULL, stdout=out, stderr=err)
        timer = threading.Timer(timeout, p.kill)
        timer.start()
        try:
            _, status, usage = os.wait4(p.pid, 0)
        finally:
            timer.cancel()
        p.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        res = Result([name] + list(args), p.returncode, out.read(), err.read())
    return res, usage.ru_maxrss * 1024  # Linux: ru_maxrss is in KiB


def write(path, data):
    mode = "wb" if isinstance(data, bytes) else "w"
    kw = {} if isinstance(data, bytes) else {"encoding": "utf-8", "newline": ""}
    with open(path, mode, **kw) as f:
        f.write(data)


def read(path):
    with open(path, "rb") as f:
        return f.read()


def snapshot(folder):
    """Every name in `folder` (recursively) with its bytes or link target: to prove that
    nothing in it changed."""
    snap = {}
    for root, dirs, files in os.walk(folder):
        for n in dirs + files:
            p = os.path.join(root, n)
            rel = os.path.relpath(p, folder)
            if os.path.islink(p):
                snap[rel] = ("link", os.readlink(p))
            elif os.path.isdir(p):
                snap[rel] = ("dir",)
            else:
                snap[rel] = ("file", read(p), stat.S_IMODE(os.stat(p).st_mode))
    return snap


def diff_snapshots(before, after):
    msgs = []
    for k in sorted(set(before) | set(after)):
        if k not in after:
            msgs.append(f"{k} was removed")
        elif k not in before:
            msgs.append(f"{k} was created")
        elif before[k] != after[k]:
            msgs.append(f"{k} was changed")
    return msgs


def tmp_leftovers(folder):
    return sorted(glob.glob(os.path.join(glob.escape(folder), "**", ".*.tmp-*"), recursive=True))


USAGE_LINE = r"(run '{tool} --help')"


def check_usage_error(res, tool_name, what):
    """Exit 2 and stderr exactly one line `TOOL: error: ... (run 'TOOL --help')`."""
    check(res.rc == 2, f"{what}: expected exit 2 (usage error), got {res.rc}\n{res.describe()}")
    err = res.err.decode("utf-8", errors="backslashreplace")
    check(err.endswith("\n") and err.count("\n") == 1,
          f"{what}: stderr must be exactly one line\n{res.describe()}")
    line = err[:-1]
    prefix = f"{tool_name}: error: "
    suffix = f" (run '{tool_name} --help')"
    check(line.startswith(prefix) and line.endswith(suffix)
          and len(line) > len(prefix) + len(suffix),
          f"{what}: stderr is not of the shape `{prefix}... {suffix.strip()}`\n{res.describe()}")
    return line


# ----------------------------------------------------------------------------------------
# Programs

GOOD = "G01 X10 F100\nG00 X0\nM30\n"
LONG = ("; long: 200000 moves of 10 s each, far longer than any test waits\n"
        "R1 = 0\n"
        "Loop:\n"
        "G01 X100 F10\n"
        "G01 X0\n"
        "R1 = R1 + 1\n"
        "IF R1 < 100000 GOTOB Loop\n"
        "M30\n")


def copy_sample(name, dest):
    src = os.path.join(SOURCE, "samples", name)
    check(os.path.isdir(src), f"sample folder {src} is missing")
    shutil.copytree(src, dest)


def print_machine(cwd, dest):
    res = run("isosim", "--print-machine", cwd=cwd)
    check(res.rc == 0, f"isosim --print-machine failed\n{res.describe()}")
    write(os.path.join(cwd, dest), res.out)


# ----------------------------------------------------------------------------------------
# 1. Outputs never destroy inputs

def overwrite_refused(cwd, tool_name, args, option, spelled, input_file):
    """Runs a command whose output `spelled` (given to `option`) is the input `input_file`
    (relative to cwd); checks the refusal and that nothing in cwd changed."""
    before = snapshot(cwd)
    res = run(tool_name, *args, cwd=cwd)
    what = f"`{res.what()}`"
    line = check_usage_error(res, tool_name, what)
    m = re.fullmatch(re.escape(f"{tool_name}: error: {option} {spelled} would overwrite the input ")
                     + r"(.+)" + re.escape(f"; choose another output file (run '{tool_name} --help')"),
                     line)
    check(m, f"{what}: expected `{tool_name}: error: {option} {spelled} would overwrite the input "
             f"{input_file}; choose another output file (run '{tool_name} --help')`, got `{line}`")
    named = m.group(1)
    check(os.path.exists(os.path.join(cwd, named))
          and os.path.samefile(os.path.join(cwd, named), os.path.join(cwd, input_file)),
          f"{what}: the message names the input `{named}`, which is not {input_file}")
    changes = diff_snapshots(before, snapshot(cwd))
    check(not changes, f"{what}: the folder changed: {'; '.join(changes)}")


def setup_program_set(d):
    """d/set/: the drilling sample (a .mpf and a sibling .spf), a machine file, a symlink
    to the main program, and an image of it."""
    copy_sample("drilling_when", os.path.join(d, "set"))
    print_machine(d, "machine.json")
    os.symlink("foratura_piastra.mpf", os.path.join(d, "set", "link.mpf"))
    res = run("isocc", "set/foratura_piastra.mpf", "-o", "prog.isob", cwd=d)
    check(res.rc == 0, f"isocc failed on the sample\n{res.describe()}")
    os.symlink("prog.isob", os.path.join(d, "link.isob"))


def spellings(d):
    """(spelling, the input file it names) for the files of the program set."""
    absmpf = os.path.join(d, "set", "foratura_piastra.mpf")
    return [
        ("set/foratura_piastra.mpf", "set/foratura_piastra.mpf"),
        ("./set/foratura_piastra.mpf", "set/foratura_piastra.mpf"),
        ("set/../set/./foratura_piastra.mpf", "set/foratura_piastra.mpf"),
        ("set//foratura_piastra.mpf", "set/foratura_piastra.mpf"),
        (absmpf, "set/foratura_piastra.mpf"),
        ("set/link.mpf", "set/foratura_piastra.mpf"),
        ("set/foratura.spf", "set/foratura.spf"),
        ("./set/../set/foratura.spf", "set/foratura.spf"),
        (os.path.join(d, "set", "foratura.spf"), "set/foratura.spf"),
        ("machine.json", "machine.json"),
        ("./machine.json", "machine.json"),
        (os.path.join(d, "machine.json"), "machine.json"),
    ]


def case_isocc_output_is_input(d):
    setup_program_set(d)
    for spelled, target in spellings(d):
        overwrite_refused(d, "isocc",
                          ["set/foratura_piastra.mpf", "--machine", "machine.json", "-o", spelled],
                          "-o", spelled, target)
    # The input named as a directory: its files are inputs too.
    overwrite_refused(d, "isocc", ["set", "-o", "set/foratura.spf"], "-o", "set/foratura.spf",
                      "set/foratura.spf")


def case_isosim_output_is_input(d):
    setup_program_set(d)
    for spelled, target in spellings(d):
        overwrite_refused(d, "isosim",
                          ["set/foratura_piastra.mpf", "--machine", "machine.json", "-o", spelled],
                          "-o", spelled, target)
    for spelled in ("prog.isob", "./prog.isob", os.path.join(d, "prog.isob"), "link.isob",
                    "set/../prog.isob"):
        overwrite_refused(d, "isosim", ["prog.isob", "-o", spelled], "-o", spelled, "prog.isob")


def case_isosim_plot_is_input(d):
    setup_program_set(d)
    for spelled, target in spellings(d):
        overwrite_refused(d, "isosim",
                          ["set/foratura_piastra.mpf", "--machine", "machine.json", "--summary",
                           "--plot", spelled],
                          "--plot", spelled, target)
    for spelled in ("prog.isob", "./prog.isob", os.path.join(d, "prog.isob"), "link.isob"):
        overwrite_refused(d, "isosim", ["prog.isob", "-o", "t.csv", "--plot", spelled],
                          "--plot", spelled, "prog.isob")


def case_isosim_views_are_not_inputs(d):
    """--timeline and --report are outputs like -o and --plot: never an input of the set."""
    setup_program_set(d)
    for option in ("--timeline", "--report"):
        for spelled, target in spellings(d):
            overwrite_refused(d, "isosim",
                              ["set/foratura_piastra.mpf", "--machine", "machine.json", "--summary",
                               option, spelled],
                              option, spelled, target)
        for spelled in ("prog.isob", "./prog.isob", "link.isob"):
            overwrite_refused(d, "isosim", ["prog.isob", "--summary", option, spelled],
                              option, spelled, "prog.isob")


def case_isosim_compare_output_is_input(d):
    """isosim NEW --compare OLD -o FILE: FILE is neither program (nor the machine file)."""
    setup_program_set(d)
    write(os.path.join(d, "old.mpf"), GOOD)
    for spelled, target in (("old.mpf", "old.mpf"), ("./old.mpf", "old.mpf"),
                            (os.path.join(d, "old.mpf"), "old.mpf"),
                            ("set/foratura_piastra.mpf", "set/foratura_piastra.mpf"),
                            ("set/link.mpf", "set/foratura_piastra.mpf"),
                            ("machine.json", "machine.json")):
        overwrite_refused(d, "isosim", ["set/foratura_piastra.mpf", "--machine", "machine.json",
                                        "--compare", "old.mpf", "-o", spelled],
                          "-o", spelled, target)
    overwrite_refused(d, "isosim", ["old.mpf", "--compare", "prog.isob", "-o", "link.isob"],
                      "-o", "link.isob", "prog.isob")


def case_isosim_views_same_file(d):
    write(os.path.join(d, "p.mpf"), GOOD)
    write(os.path.join(d, "a.out"), "precious\n")
    for args in (["-o", "a.out", "--timeline", "./a.out"], ["--plot", "a.out", "--report", "a.out"],
                 ["--summary", "--timeline", "a.out", "--report", os.path.join(d, "a.out")],
                 ["-o", "new.csv", "--report", "sub/../new.csv"]):
        os.makedirs(os.path.join(d, "sub"), exist_ok=True)
        before = snapshot(d)
        res = run("isosim", "p.mpf", *args, cwd=d)
        what = f"`{res.what()}`"
        line = check_usage_error(res, "isosim", what)
        check("name the same file" in line, f"{what}: expected a message that two outputs name the same file, got `{line}`")
        changes = diff_snapshots(before, snapshot(d))
        check(not changes, f"{what}: the folder changed: {'; '.join(changes)}")


def case_isosim_timeline_bounded(d):
    """A run of 400,000 lines: the timeline keeps at most 100,000 events, counts the others,
    and its main track still adds up to the cycle time."""
    write(os.path.join(d, "many.mpf"), "R1 = 0\nLoop:\nR1 = R1 + 1\nIF R1 < 200000 GOTOB Loop\nM30\n")
    res = run("isosim", "many.mpf", "--summary", "--format", "json", "--timeline", "t.json", cwd=d)
    check(res.rc == 0, f"isosim failed\n{res.describe()}")
    size = os.path.getsize(os.path.join(d, "t.json"))
    check(size < 32 * MIB, f"the timeline of 400,000 lines is {size / MIB:.1f} MiB, expected < 32 MiB")
    with open(os.path.join(d, "t.json"), encoding="utf-8") as f:
        doc = json.load(f)
    od = doc["otherData"]
    check(od["dropped"] > 0 and od["events"] <= 100_001, f"events {od['events']}, dropped {od['dropped']}")
    main = [e for e in doc["traceEvents"] if e["ph"] == "X" and e["tid"] == 1]
    cyc = round(json.loads(res.out)["cycle_time_s"] * 1_000_000)
    check(sum(e["dur"] for e in main) == cyc, f"main slices add up to {sum(e['dur'] for e in main)}, not {cyc}")
    check(main[-1]["name"].endswith("more lines (not recorded)"), f"last main slice: {main[-1]}")


def case_sigint_keeps_timeline_and_report(d):
    interrupted_run(d, signal.SIGINT, ["--summary", "--timeline", "long.json", "--report", "long.html"],
                    "long.json", also=["long.html"])


def case_new_view_files_follow_umask(d):
    write(os.path.join(d, "p.mpf"), GOOD)
    old = os.umask(0o022)
    try:
        res = run("isosim", "p.mpf", "--summary", "--timeline", "t.json", "--report", "r.html", cwd=d)
        check(res.rc == 0, f"`{res.what()}` failed\n{res.describe()}")
        for name in ("t.json", "r.html"):
            mode = stat.S_IMODE(os.stat(os.path.join(d, name)).st_mode)
            check(mode == 0o644, f"`{res.what()}` with umask 022: new {name} has mode {mode:o}, expected 644")
        check(not tmp_leftovers(d), f"temporary files left behind: {tmp_leftovers(d)}")
    finally:
        os.umask(old)


def case_isosim_output_and_plot_same_file(d):
    write(os.path.join(d, "p.mpf"), GOOD)
    write(os.path.join(d, "a.csv"), "precious\n")
    for o, plot in (("a.csv", "./a.csv"), ("a.csv", "a.csv"), ("a.csv", os.path.join(d, "a.csv")),
                    ("new.csv", "sub/../new.csv")):
        os.makedirs(os.path.join(d, "sub"), exist_ok=True)
        before = snapshot(d)
        res = run("isosim", "p.mpf", "-o", o, "--plot", plot, cwd=d)
        what = f"`{res.what()}`"
        line = check_usage_error(res, "isosim", what)
        check("name the same file" in line,
              f"{what}: expected a message that -o and --plot name the same file, got `{line}`")
        changes = diff_snapshots(before, snapshot(d))
        check(not changes, f"{what}: the folder changed: {'; '.join(changes)}")


def case_isosim_output_dash_is_stdout(d):
    write(os.path.join(d, "p.mpf"), GOOD)
    plain = run("isosim", "p.mpf", cwd=d)
    check(plain.rc == 0, f"isosim failed\n{plain.describe()}")
    dash = run("isosim", "p.mpf", "-o", "-", cwd=d)
    check(dash.rc == 0, f"`isosim p.mpf -o -` failed\n{dash.describe()}")
    check(not os.path.exists(os.path.join(d, "-")), "`isosim p.mpf -o -` created a file named '-'")
    check(dash.out.startswith(b"t,X,"), f"`isosim p.mpf -o -`: no CSV trace on stdout\n{dash.describe()}")
    check(dash.out == plain.out,
          "`isosim p.mpf -o -` does not print the same trace as `isosim p.mpf` on a pipe\n"
          f"with -o -:\n{show(dash.out)}\nwithout:\n{show(plain.out)}")


def case_isocc_output_dash_is_stdout(d):
    write(os.path.join(d, "p.mpf"), GOOD)
    res = run("isocc", "p.mpf", "-o", "p.isob", cwd=d)
    check(res.rc == 0, f"isocc failed\n{res.describe()}")
    dash = run("isocc", "p.mpf", "-o", "-", cwd=d)
    check(dash.rc == 0, f"`isocc p.mpf -o -` failed\n{dash.describe()}")
    check(not os.path.exists(os.path.join(d, "-")),
          "`isocc p.mpf -o -` created a file named '-' instead of writing to standard output")
    check(dash.out == read(os.path.join(d, "p.isob")),
          f"`isocc p.mpf -o -`: stdout ({len(dash.out)} bytes) is not the image that "
          f"`isocc p.mpf -o p.isob` writes ({len(read(os.path.join(d, 'p.isob')))} bytes)")


# ----------------------------------------------------------------------------------------
# 2. Atomic outputs

def signal_and_wait(p, sig, what):
    """Sends `sig` to the still running process `p` and returns its (stdout, stderr); fails
    when it had already ended or is still running 20 s later."""
    check(p.poll() is None, f"{what} ended (exit {p.returncode}) before the signal was sent")
    p.send_signal(sig)
    try:
        return p.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        raise Failure(f"{what}: still running 20 s after {signal.Signals(sig).name}")


def interrupted_run(d, sig, args, target, also=()):
    """Interrupts isosim with `sig` while it writes `target` (and the files `also`)."""
    write(os.path.join(d, "long.mpf"), LONG)
    olds = {}
    for name in [target] + list(also):
        olds[name] = b"previous contents of " + name.encode() + b"\n" * 3
        write(os.path.join(d, name), olds[name])
        os.chmod(os.path.join(d, name), 0o640)
    argv = [tool("isosim"), "long.mpf", "--dt", "0.0001"] + args
    p = _popen_retry(argv, cwd=d, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                     stderr=subprocess.PIPE)
    what = "`isosim long.mpf --dt 0.0001 " + " ".join(args) + "`"
    try:
        pattern = os.path.join(glob.escape(d), "." + target + ".tmp-*")
        deadline = time.monotonic() + 10
        while not glob.glob(pattern):
            if p.poll() is not None:
                raise Failure(f"{what} ended (exit {p.returncode}) before its temporary file "
                              f".{target}.tmp-XXXXXX appeared: {show(p.stderr.read())}")
            check(time.monotonic() < deadline,
                  f"{what}: no temporary file .{target}.tmp-XXXXXX appeared in 10 s; "
                  f"files: {sorted(os.listdir(d))}")
            time.sleep(0.01)
        time.sleep(0.6)
        out, err = signal_and_wait(p, sig, what)
    finally:
        if p.poll() is None:
            p.kill()
            p.communicate()
    res = Result(argv, p.returncode, out, err)
    expected_rc = 128 + sig
    check(res.rc == expected_rc,
          f"{what}, {signal.Signals(sig).name} after 0.6 s: expected exit {expected_rc}, "
          f"got {res.rc}\n{res.describe()}")
    for name, old in olds.items():
        check(read(os.path.join(d, name)) == old,
              f"{what}, interrupted: {name} is no longer byte-identical to its previous contents")
        check(stat.S_IMODE(os.stat(os.path.join(d, name)).st_mode) == 0o640,
              f"{what}, interrupted: {name} lost its permission bits")
    left = tmp_leftovers(d)
    check(not left, f"{what}, interrupted: temporary files left behind: {left}")
    check(res.err.rstrip(b"\n").endswith(b"isosim: interrupted; no output file was changed"),
          f"{what}, interrupted: stderr does not end with "
          f"`isosim: interrupted; no output file was changed`\n{res.describe()}")


def case_sigint_keeps_output(d):
    interrupted_run(d, signal.SIGINT, ["-o", "long.csv"], "long.csv")


def case_sigterm_keeps_output(d):
    interrupted_run(d, signal.SIGTERM, ["-o", "long.csv"], "long.csv")


def case_sigint_keeps_plot(d):
    interrupted_run(d, signal.SIGINT, ["--summary", "--plot", "long.svg"], "long.svg")


def case_sigterm_keeps_plot(d):
    interrupted_run(d, signal.SIGTERM, ["--summary", "--plot", "long.svg"], "long.svg")


def case_sigint_keeps_output_and_plot(d):
    interrupted_run(d, signal.SIGINT, ["-o", "long.json", "--plot", "long.svg"], "long.json",
                    also=["long.svg"])


FIXABLE = b"G01 X123.4567891 F100\nM30\n"   # E101: its fix rounds the number
FIXED = b"G01 X123.456789 F100\nM30\n"


def interrupted_fix(d, sig):
    """Interrupts `isolint --fix` while it rewrites thousands of files: every file is then
    either fixed or byte-identical to what it was, none is half-written, no temporary file is
    left, the exit status is 128 + the signal and stderr says so."""
    count = 20000
    names = [f"p{i:05d}.mpf" for i in range(count)]
    for name in names:
        write(os.path.join(d, name), FIXABLE)
    argv = [tool("isolint"), "--fix", "-j1", "."]
    p = _popen_retry(argv, cwd=d, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                     stderr=subprocess.PIPE)
    what = f"`isolint --fix -j1 .` on {count} files"
    try:
        first = os.path.join(d, names[0])
        deadline = time.monotonic() + 20
        while read(first) == FIXABLE:  # files are fixed in order: wait for the first one
            if p.poll() is not None:
                raise Failure(f"{what} ended (exit {p.returncode}) before it fixed {names[0]}: "
                              f"{show(p.stderr.read())}")
            check(time.monotonic() < deadline, f"{what}: {names[0]} not fixed after 20 s")
            time.sleep(0.002)
        out, err = signal_and_wait(p, sig, what)
    finally:
        if p.poll() is None:
            p.kill()
            p.communicate()
    res = Result(argv, p.returncode, out, err)
    check(res.rc == 128 + sig, f"{what}, {signal.Signals(sig).name}: expected exit {128 + sig}, "
          f"got {res.rc}\n{res.describe()}")
    contents = [read(os.path.join(d, name)) for name in names]
    odd = [n for n, c in zip(names, contents) if c not in (FIXABLE, FIXED)]
    check(not odd, f"{what}, interrupted: files neither fixed nor as they were: {odd[:5]}")
    fixed = sum(c == FIXED for c in contents)
    check(0 < fixed < count, f"{what}, interrupted: {fixed} of {count} files fixed; expected "
          "the signal to land while it was fixing")
    left = tmp_leftovers(d)
    check(not left, f"{what}, interrupted: temporary files left behind: {left[:5]}")
    check(res.err.rstrip(b"\n").endswith(
              b"isolint: interrupted; each file is fixed or as it was, none half-written"),
          f"{what}, interrupted: stderr does not end with the interruption message\n{res.describe()}")


def case_isolint_fix_sigint(d):
    interrupted_fix(d, signal.SIGINT)


def case_isolint_fix_sigterm(d):
    interrupted_fix(d, signal.SIGTERM)


def case_normal_run_replaces_output(d):
    write(os.path.join(d, "p.mpf"), GOOD)
    ref = run("isosim", "p.mpf", cwd=d)
    check(ref.rc == 0 and ref.out.startswith(b"t,X"), f"isosim failed\n{ref.describe()}")
    ref_isob = run("isocc", "p.mpf", "-o", "ref.isob", cwd=d)
    check(ref_isob.rc == 0, f"isocc failed\n{ref_isob.describe()}")
    ref_svg = run("isosim", "p.mpf", "--summary", "--plot", "ref.svg", cwd=d)
    check(ref_svg.rc == 0, f"isosim --plot failed\n{ref_svg.describe()}")
    expected = {"t.csv": ref.out, "p.isob": read(os.path.join(d, "ref.isob")),
                "p.svg": read(os.path.join(d, "ref.svg"))}
    junk = b"OLD CONTENTS " * 20000  # longer than any new output: no tail may survive
    for name, mode in (("t.csv", 0o640), ("p.isob", 0o604), ("p.svg", 0o660)):
        path = os.path.join(d, name)
        write(path, junk)
        os.chmod(path, mode)
    cmds = [("isosim", ["p.mpf", "-o", "t.csv"]), ("isocc", ["p.mpf", "-o", "p.isob"]),
            ("isosim", ["p.mpf", "--summary", "--plot", "p.svg"])]
    for (tool_name, args), (name, mode) in zip(cmds, (("t.csv", 0o640), ("p.isob", 0o604),
                                                    ("p.svg", 0o660))):
        res = run(tool_name, *args, cwd=d)
        check(res.rc == 0, f"`{res.what()}` failed\n{res.describe()}")
        got = read(os.path.join(d, name))
        check(got == expected[name],
              f"`{res.what()}`: {name} ({len(got)} bytes) is not exactly the new output "
              f"({len(expected[name])} bytes); starts with {show(got[:80])!r}")
        got_mode = stat.S_IMODE(os.stat(os.path.join(d, name)).st_mode)
        check(got_mode == mode,
              f"`{res.what()}`: {name} had mode {mode:o}, now {got_mode:o}")
    left = tmp_leftovers(d)
    check(not left, f"temporary files left behind after normal runs: {left}")


def case_new_output_mode_follows_umask(d):
    """A new output file gets the mode a plain creation would give (0666 & ~umask), not the
    0600 of a temporary file."""
    write(os.path.join(d, "p.mpf"), GOOD)
    old = os.umask(0o022)
    try:
        for tool_name, args, name in (("isosim", ["p.mpf", "-o", "new.csv"], "new.csv"),
                                      ("isocc", ["p.mpf", "-o", "new.isob"], "new.isob"),
                                      ("isosim", ["p.mpf", "--summary", "--plot", "new.svg"],
                                       "new.svg")):
            res = run(tool_name, *args, cwd=d)
            check(res.rc == 0, f"`{res.what()}` failed\n{res.describe()}")
            mode = stat.S_IMODE(os.stat(os.path.join(d, name)).st_mode)
            check(mode == 0o644, f"`{res.what()}` with umask 022: new {name} has mode {mode:o}, "
                                 "expected 644")
    finally:
        os.umask(old)


# ----------------------------------------------------------------------------------------
# 3. Bounded output

DIAG_HEAD = re.compile(rb"^\S.*?:\d+:\d+: (error|warning|info): ", re.M)


def count_line(out):
    lines = out.rstrip(b"\n").split(b"\n")
    return lines[-1].decode("utf-8", "backslashreplace") if lines else ""


def case_many_diagnostics_bounded(d):
    write(os.path.join(d, "many.mpf"), "R0 = 1\n" * 5000 + "M30\n")
    res = run("isolint", "many.mpf", cwd=d)
    check(res.rc == 1, f"expected exit 1\n{res.describe()}")
    check(len(res.out) < OUTPUT_LIMIT,
          f"`isolint many.mpf` (5000 errors) printed {len(res.out)} bytes, expected < {OUTPUT_LIMIT}")
    shown = len(DIAG_HEAD.findall(res.out))
    check(shown == 50, f"`isolint many.mpf`: {shown} diagnostics shown, expected 50 (the default)")
    check(b"\n4950 more diagnostics in many.mpf (--max-diagnostics 0 shows all)\n" in res.out,
          "`isolint many.mpf`: no line `4950 more diagnostics in many.mpf (--max-diagnostics 0 "
          f"shows all)`; end of the output:\n{show(res.out[-600:])}")
    check(count_line(res.out) == "1 file checked: 5000 errors, 0 warnings, 0 infos",
          f"`isolint many.mpf`: the count line is `{count_line(res.out)}`, expected "
          "`1 file checked: 5000 errors, 0 warnings, 0 infos`")


def case_max_diagnostics_zero_shows_all(d):
    write(os.path.join(d, "a.mpf"), "R0 = 1\n" * 120 + "M30\n")
    res = run("isolint", "--max-diagnostics", "0", "a.mpf", cwd=d)
    check(res.rc == 1, f"expected exit 1\n{res.describe()}")
    shown = len(DIAG_HEAD.findall(res.out))
    check(shown == 120, f"`isolint --max-diagnostics 0 a.mpf`: {shown} diagnostics shown, expected 120")
    check(b"more diagnostics" not in res.out,
          "`isolint --max-diagnostics 0`: a `more diagnostics` line is printed")
    check(count_line(res.out) == "1 file checked: 120 errors, 0 warnings, 0 infos",
          f"count line `{count_line(res.out)}`")


def case_max_diagnostics_n_text(d):
    write(os.path.join(d, "a.mpf"), "R0 = 1\n" * 30 + "M30\n")
    write(os.path.join(d, "b.mpf"), "G01 X1\n" + "R0 = 1\n" * 20 + "M30\n")
    res = run("isolint", "--max-diagnostics", "7", "a.mpf", "b.mpf", cwd=d)
    check(res.rc == 1, f"expected exit 1\n{res.describe()}")
    a = len(re.findall(rb"^a\.mpf:\d+:\d+: ", res.out, re.M))
    b = len(re.findall(rb"^b\.mpf:\d+:\d+: ", res.out, re.M))
    check((a, b) == (7, 7), f"`isolint --max-diagnostics 7 a.mpf b.mpf`: shown {a} and {b}, "
                            f"expected 7 per file\n{res.describe()}")
    for line in (b"23 more diagnostics in a.mpf (--max-diagnostics 0 shows all)",
                 b"14 more diagnostics in b.mpf (--max-diagnostics 0 shows all)"):
        check(b"\n" + line + b"\n" in res.out, f"missing line `{line.decode()}`\n{res.describe()}")
    check(count_line(res.out) == "2 files checked: 50 errors, 1 warning, 0 infos",
          f"count line `{count_line(res.out)}`, expected `2 files checked: 50 errors, 1 warning, "
          "0 infos`")
    one = run("isolint", "--max-diagnostics", "1", "--disable", "W402", "b.mpf", cwd=d)
    check(one.rc == 1, f"the exit status must not depend on --max-diagnostics\n{one.describe()}")


def case_max_diagnostics_json(d):
    write(os.path.join(d, "a.mpf"), "R0 = 1\n" * 30 + "M30\n")
    write(os.path.join(d, "b.mpf"), "G01 X1\n" + "R0 = 1\n" * 20 + "M30\n")
    res = run("isolint", "--format", "json", "--max-diagnostics", "7", "a.mpf", "b.mpf", cwd=d)
    check(res.rc == 1, f"expected exit 1\n{res.describe()}")
    log = json.loads(res.out.decode("utf-8"))
    per = {}
    for diag in log["diagnostics"]:
        per[diag["file"]] = per.get(diag["file"], 0) + 1
    check(per == {"a.mpf": 7, "b.mpf": 7},
          f"json --max-diagnostics 7: diagnostics per file {per}, expected 7 each")
    counts = (log.get("files"), log.get("errors"), log.get("warnings"))
    check(counts == (2, 50, 1), f"json --max-diagnostics 7: files/errors/warnings {counts}, "
                                "expected (2, 50, 1): the counts count every diagnostic")
    full = run("isolint", "--format", "json", "a.mpf", "b.mpf", cwd=d)
    n = len(json.loads(full.out.decode("utf-8"))["diagnostics"])
    check(n == 51, f"json without --max-diagnostics shows {n} diagnostics, expected all 51")


def large_program(lines):
    """A CAM-style program of about `lines` lines of 15 bytes, with errors all over it: rapid moves,
    then G18 and a feed set once (after the first 1000 statements, whose state the second thread
    starts from: a wrong guess, so the split must be checked again), labels and backward jumps,
    IF blocks, WHENs, `$` continuations, incremental arcs, CRLF line ends in places, an N number
    used twice, a jump to no label."""
    out = ["; generated\r\n", "G90\n"] + [f"G0 X{i % 10}\n" for i in range(1100)] + ["G18 F=250\n"]
    k = 0
    while len(out) < lines:
        k += 1
        out += [f"N{10 * k} G1 X{k % 97} Z{k % 89}\n", f"L{k}: G0 Z5\r\n",
                f"IF R1 > {k % 50}\n", "  G1 X1 Z2\n", "ELSE\n", "  M23\n", "ENDIF\n",
                f"IF R1 > 1000 GOTOB L{k}\n", "WHEN $aa_iw[X] > 5 DO $aa_out[3] = 1\n",
                f"G1 X{k % 31 + 6} $\n", "  Z3\n", "G91\n", "G2 X2 Z0 CR=5\n", "G90\n"]
        if k % 5000 == 0:
            out += ["R0 = 1\n", "G3 X1 Y1 CR=1\n"]  # an error; Y is not in the XZ plane
    out += ["L7: G0 X0\n", "N10 G0 X0\n", "GOTOF NOWHERE\n", "M30\n"]
    return "".join(out)


def case_large_file_two_threads_same_output(d):
    # A file of 1 MiB or more checked alone is checked by two threads (isolint(1), -j): the
    # output must be that of one thread, byte for byte, in every format.
    text = large_program(150000)
    check(len(text) > (1 << 20), f"the program has {len(text)} bytes, expected more than 1 MiB")
    write(os.path.join(d, "cam.mpf"), text)
    outputs = {}
    for fmt in ("text", "json", "sarif"):
        one = run("isolint", "-j", "1", "--format", fmt, "--max-diagnostics", "0", "cam.mpf", cwd=d)
        outputs[fmt] = one.out
        two = run("isolint", "-j", "2", "--format", fmt, "--max-diagnostics", "0", "cam.mpf", cwd=d)
        check(one.rc == 1 and two.rc == 1, f"expected exit 1 twice\n{one.describe()}\n{two.describe()}")
        check(two.out == one.out, f"--format {fmt}: -j 2 printed other diagnostics than -j 1:\n"
                                  f"-j 1:\n{show(one.out[-800:])}\n-j 2:\n{show(two.out[-800:])}")
    for code in (b"E203", b"W411", b"E202", b"E301"):
        check(code in outputs["text"], f"no {code.decode()} in the output of a program that has one")
    check(b"W402" not in outputs["text"], "a W402 (no feed) in a program whose feed is set at the top")


def wide_line_file(d):
    # 20,000 words of 5 and 6 characters, separated by spaces: 130,000 bytes on one line;
    # every word repeats the axis X, so every word is a diagnostic of its own.
    words = ["X1.25" if i % 2 else "X10.25" for i in range(20000)]
    text = " ".join(words) + "\nM30\n"
    write(os.path.join(d, "wide.mpf"), text)
    return len(text)


def case_wide_line_output(d):
    size = wide_line_file(d)
    check(125000 <= size <= 135000, f"the wide line has {size} bytes")
    res = run("isolint", "wide.mpf", cwd=d)
    check(res.rc == 1, f"expected exit 1\n{res.describe()}")
    check(len(res.out) < OUTPUT_LIMIT,
          f"`isolint wide.mpf` (one line of 130 kB) printed {len(res.out)} bytes, "
          f"expected < {OUTPUT_LIMIT}")
    text = res.out.decode("utf-8")
    check("\u2026" in text, "`isolint wide.mpf`: no \u2026 where the source line is cut")
    for line in text.split("\n"):
        if line.startswith("  ") and not re.match(r"^  \S+:\d+:\d+: note: ", line):
            check(len(line) <= 2 + 120,
                  f"`isolint wide.mpf`: a source or caret line of {len(line)} columns, expected a "
                  f"window of about 100: {show(line, 300)}")


def memory_case(d, name, make):
    if os.environ.get("ISO_SANITIZE_BUILD") == "1":
        raise Skip("memory check skipped: the tools are built with sanitizers")
    make(d)
    res, rss = run_measured("isolint", name, cwd=d)
    check(res.rc in (0, 1), f"`isolint {name}` failed\n{res.describe()}")
    check(rss < RSS_LIMIT, f"`isolint {name}`: peak RSS {rss / MIB:.1f} MiB, expected < 200 MiB")
    check(len(res.out) < OUTPUT_LIMIT,
          f"`isolint {name}` printed {len(res.out)} bytes, expected < {OUTPUT_LIMIT}")


def case_wide_line_memory(d):
    memory_case(d, "wide.mpf", wide_line_file)


def cr_only_file(d):
    write(os.path.join(d, "cr.mpf"), b"\r".join([b"R0 = 1"] * 4000))


def case_cr_only_output(d):
    cr_only_file(d)
    res = run("isolint", "cr.mpf", cwd=d)
    check(res.rc == 1, f"expected exit 1\n{res.describe()}")
    check(len(res.out) < OUTPUT_LIMIT,
          f"`isolint cr.mpf` (4000 lines joined by CR) printed {len(res.out)} bytes, "
          f"expected < {OUTPUT_LIMIT}")
    check(b"\r" not in res.out, "`isolint cr.mpf` sends a raw CR byte to the terminal")


def case_cr_only_memory(d):
    memory_case(d, "cr.mpf", cr_only_file)


# ----------------------------------------------------------------------------------------
# 4. Hostile text

def is_utf8(data):
    try:
        data.decode("utf-8")
        return True
    except UnicodeDecodeError:
        return False


ESC_PROGRAM = b"R0 = 1 ; \x1b[31mred\nG01 X10\x1b[0m F100\nM30\n"


def case_escape_control_in_source(d):
    write(os.path.join(d, "esc.mpf"), ESC_PROGRAM)
    for extra in ([], ["--color", "never"], ["--color", "always"]):
        res = run("isolint", *extra, "esc.mpf", cwd=d)
        what = "`isolint " + " ".join(extra + ["esc.mpf"]) + "`"
        check(res.rc == 1, f"{what}: expected exit 1\n{res.describe()}")
        check(b"; \\x1b[31mred" in res.out,
              f"{what}: the comment's ESC is not shown as \\x1b\n{res.describe()}")
        check(b"X10\\x1b[0m" in res.out, f"{what}: the ESC in the block is not shown as \\x1b\n"
                                         f"{res.describe()}")
        check(b"\x1b[31mred" not in res.out and b"X10\x1b[0m" not in res.out,
              f"{what}: an ESC byte of the source reaches the output raw")
        if not extra or extra[1] == "never":
            check(b"\x1b" not in res.out, f"{what}: a raw ESC byte in the uncoloured output")


def case_escape_control_in_isocc_isosim(d):
    write(os.path.join(d, "esc.mpf"), ESC_PROGRAM)
    for tool_name, args in (("isocc", ["esc.mpf", "-o", "esc.isob"]), ("isosim", ["esc.mpf"])):
        res = run(tool_name, *args, cwd=d)
        what = f"`{res.what()}`"
        check(res.rc == 1, f"{what}: expected exit 1\n{res.describe()}")
        check(b"\\x1b[31mred" in res.err, f"{what}: the ESC is not shown as \\x1b\n{res.describe()}")
        check(b"\x1b" not in res.err and b"\x1b" not in res.out,
              f"{what}: a raw ESC byte in the output\n{res.describe()}")


def case_escape_file_names_text(d):
    names = [b"n\x1b[1m.mpf", b"a\xe8.mpf"]
    for n in names:
        write(os.path.join(d.encode(), n), "R0 = 1\nM30\n")
    res = run("isolint", *names, cwd=d)
    check(res.rc == 1, f"expected exit 1\n{res.describe()}")
    check(b"\x1b" not in res.out, f"a raw ESC byte of a file name in the text output\n{res.describe()}")
    check(is_utf8(res.out), f"the text output is not valid UTF-8\n{res.describe()}")
    for shown in (b"n\\x1b[1m.mpf:1:1: error: ", b"a\\xe8.mpf:1:1: error: "):
        check(b"\n" + shown in b"\n" + res.out,
              f"expected a diagnostic starting `{shown.decode()}`\n{res.describe()}")
    # The same for a name on standard error (an input that does not exist).
    res = run("isolint", b"gone\x1b[2J\xe8.mpf", cwd=d)
    check(res.rc == 2, f"a missing input: expected exit 2\n{res.describe()}")
    check(b"\x1b" not in res.err and is_utf8(res.err),
          f"a missing input's name reaches stderr raw\n{res.describe()}")
    check(b"gone\\x1b[2J\\xe8.mpf: error: " in res.err, f"the escaped name is not on stderr\n"
                                                        f"{res.describe()}")


def latin1_log(d, fmt):
    name = b"a\xe8.mpf"
    write(os.path.join(d.encode(), name), "R0 = 1\nM30\n")
    res = run("isolint", "--format", fmt, name, cwd=d)
    check(res.rc == 1, f"`isolint --format {fmt}` on a file named a<0xE8>.mpf: expected exit 1 "
                       f"(one error), got {res.rc}\n{res.describe()}")
    try:
        text = res.out.decode("utf-8")
    except UnicodeDecodeError as e:
        raise Failure(f"`isolint --format {fmt}`: the output is not valid UTF-8: {e}")
    try:
        return json.loads(text), res
    except ValueError as e:
        raise Failure(f"`isolint --format {fmt}`: the output is not JSON: {e}\n{res.describe()}")


def case_latin1_name_json(d):
    log, res = latin1_log(d, "json")
    files = [x["file"] for x in log["diagnostics"]]
    check(files == ["a\\xe8.mpf"],
          f"json: the file name should read a\\xe8.mpf (\\xe8 as 4 characters), got {files}")


def case_latin1_name_sarif(d):
    log, res = latin1_log(d, "sarif")
    uris = [loc["physicalLocation"]["artifactLocation"]["uri"]
            for r in log["runs"][0]["results"] for loc in r["locations"]]
    # \xe8 as 4 characters, or its RFC 3986 percent-encoding (%E8): a SARIF uri must be a
    # URI reference, where the byte is written %E8.
    check(len(uris) == 1 and uris[0] in ("a\\xe8.mpf", "a%E8.mpf", "a%e8.mpf"),
          f"sarif: the file's uri should be a\\xe8.mpf (or a%E8.mpf), got {uris}")


def case_binary_file_one_diagnostic(d):
    data = b"G01 X10 F100\n\x00\x00\x01\x02\x03binary\x00\nR0 = 1\nG07 X1\nWHILE R1 < 3\n" * 50
    write(os.path.join(d, "bin.mpf"), data)
    res = run("isolint", "bin.mpf", cwd=d)
    check(res.rc == 1, f"expected exit 1\n{res.describe()}")
    heads = [l for l in res.out.split(b"\n") if l and not l.startswith(b" ")
             and b" checked: " not in l]
    check(len(heads) == 1 and b"[E100" in heads[0] and b"binary file" in heads[0],
          f"expected exactly one E100 diagnostic saying `binary file`\n{res.describe()}")
    check(b"\x00" not in res.out, "a NUL byte in the output")
    res = run("isolint", "--format", "json", "bin.mpf", cwd=d)
    diags = json.loads(res.out.decode("utf-8"))["diagnostics"]
    check(len(diags) == 1 and diags[0]["code"] == "E100" and "binary file" in diags[0]["message"],
          f"json: expected exactly one E100 diagnostic mentioning `binary file`, got {diags}")


def case_image_file_one_diagnostic(d):
    write(os.path.join(d, "p.mpf"), GOOD)
    res = run("isocc", "p.mpf", "-o", "p.isob", cwd=d)
    check(res.rc == 0, f"isocc failed\n{res.describe()}")
    shutil.copy(os.path.join(d, "p.isob"), os.path.join(d, "image.mpf"))
    for name in ("p.isob", "image.mpf"):
        res = run("isolint", "--format", "json", name, cwd=d)
        check(res.rc == 1, f"`isolint {name}` (an image): expected exit 1\n{res.describe()}")
        diags = json.loads(res.out.decode("utf-8"))["diagnostics"]
        check(len(diags) == 1 and diags[0]["code"] == "E100"
              and "isocc --disasm" in diags[0]["message"],
              f"`isolint {name}` (an image): expected exactly one E100 diagnostic mentioning "
              f"`isocc --disasm`, got {diags}")
        res = run("isolint", name, cwd=d)
        heads = [l for l in res.out.split(b"\n") if l and not l.startswith(b" ")
                 and b" checked: " not in l]
        check(len(heads) == 1 and b"[E100" in heads[0] and b"isocc --disasm" in heads[0],
              f"`isolint {name}` (an image): expected exactly one E100 diagnostic mentioning "
              f"isocc --disasm in the text output\n{res.describe()}")


def case_utf8_comment_as_is(d):
    write(os.path.join(d, "it.mpf"), "R0 = 1 ; caffè già\nM30\n")
    res = run("isolint", "it.mpf", cwd=d)
    check(res.rc == 1, f"expected exit 1\n{res.describe()}")
    check("; caffè già".encode() in res.out,
          f"the Italian comment is not shown as it is\n{res.describe()}")
    check(b"\\x" not in res.out, f"valid UTF-8 was escaped\n{res.describe()}")


# ----------------------------------------------------------------------------------------
# 5. Partial failure

PARTIAL_GOOD = "G01 X10\nG90 G91 G00 X5\nM30\n"      # two warnings
PARTIAL_BAD = "R0 = 1\nGOTOF Nowhere\nM30\n"         # two errors


def partial_setup(d):
    write(os.path.join(d, "good.mpf"), PARTIAL_GOOD)
    write(os.path.join(d, "bad.mpf"), PARTIAL_BAD)


def case_partial_failure_text(d):
    partial_setup(d)
    ref = run("isolint", "good.mpf", "bad.mpf", cwd=d)
    check(ref.rc == 1 and len(DIAG_HEAD.findall(ref.out)) == 4,
          f"expected 4 diagnostics, exit 1\n{ref.describe()}")
    res = run("isolint", "good.mpf", "missing.mpf", "bad.mpf", cwd=d)
    check(res.rc == 2, f"expected exit 2\n{res.describe()}")
    check(res.out == ref.out,
          "`isolint good.mpf missing.mpf bad.mpf` does not report both existing files in full "
          f"(as `isolint good.mpf bad.mpf`)\nwith the missing file:\n{show(res.out)}\n"
          f"without:\n{show(ref.out)}")
    check(b"missing.mpf: error: no such file or directory" in res.err.split(b"\n"),
          f"stderr has no line `missing.mpf: error: no such file or directory`\n{res.describe()}")


def case_partial_failure_json(d):
    partial_setup(d)
    ref = run("isolint", "--format", "json", "good.mpf", "bad.mpf", cwd=d)
    ref_log = json.loads(ref.out.decode("utf-8"))
    res = run("isolint", "--format", "json", "good.mpf", "missing.mpf", "bad.mpf", cwd=d)
    check(res.rc == 2, f"expected exit 2\n{res.describe()}")
    log = json.loads(res.out.decode("utf-8"))
    check(log["diagnostics"] == ref_log["diagnostics"] and len(log["diagnostics"]) == 4,
          f"json: the diagnostics of good.mpf and bad.mpf are not reported in full: "
          f"{log['diagnostics']}")
    errs = log.get("input_errors")
    check(isinstance(errs, list) and len(errs) == 1 and errs[0].get("file") == "missing.mpf"
          and isinstance(errs[0].get("message"), str) and errs[0]["message"]
          and set(errs[0]) == {"file", "message"},
          f"json: expected input_errors [{{\"file\": \"missing.mpf\", \"message\": ...}}], got {errs}")
    keys = list(log)
    check(keys.index("input_errors") == keys.index("diagnostics") + 1,
          f"json: input_errors should follow diagnostics; keys {keys}")
    check((log.get("files"), log.get("errors"), log.get("warnings")) == (2, 2, 2),
          f"json counts: files {log.get('files')}, errors {log.get('errors')}, "
          f"warnings {log.get('warnings')}; expected 2, 2, 2")
    check(b"missing.mpf: error: no such file or directory" in res.err.split(b"\n"),
          f"stderr has no line `missing.mpf: error: no such file or directory`\n{res.describe()}")


def sarif_partial(d):
    partial_setup(d)
    ref = run("isolint", "--format", "sarif", "good.mpf", "bad.mpf", cwd=d)
    res = run("isolint", "--format", "sarif", "good.mpf", "missing.mpf", "bad.mpf", cwd=d)
    check(res.rc == 2, f"expected exit 2\n{res.describe()}")
    return json.loads(ref.out.decode("utf-8")), json.loads(res.out.decode("utf-8")), ref, res


def case_partial_failure_sarif(d):
    ref_log, log, ref, res = sarif_partial(d)
    run0 = log["runs"][0]
    check(run0.get("results") == ref_log["runs"][0].get("results")
          and len(run0.get("results", [])) == 4,
          "sarif: the results of good.mpf and bad.mpf are not reported in full")
    inv = run0.get("invocations")
    check(isinstance(inv, list) and len(inv) == 1,
          f"sarif: expected one invocations entry, got {inv}")
    check(inv[0].get("executionSuccessful") is False,
          f"sarif: invocations[0].executionSuccessful is {inv[0].get('executionSuccessful')!r}, "
          "expected false")
    notes = inv[0].get("toolExecutionNotifications") or []
    check(len(notes) == 1 and notes[0].get("level") == "error"
          and "missing.mpf" in json.dumps(notes[0]),
          f"sarif: expected one toolExecutionNotifications entry (level error) naming "
          f"missing.mpf, got {notes}")
    ref_inv = ref_log["runs"][0].get("invocations")
    check(ref_inv is None or ref_inv[0].get("executionSuccessful") is True,
          f"sarif without a missing input: executionSuccessful is not true: {ref_inv}")
    check(b"missing.mpf: error: no such file or directory" in res.err.split(b"\n"),
          f"stderr has no line `missing.mpf: error: no such file or directory`\n{res.describe()}")


def case_partial_failure_sarif_schema(d):
    schema_path = os.path.normpath(os.path.join(SOURCE, "..", "shared", "schemas",
                                                "sarif-2.1.0.json"))
    if not os.path.isfile(schema_path):
        raise Skip(f"{schema_path} is absent")
    try:
        import jsonschema
    except ImportError:
        raise Failure(f"the Python module jsonschema is missing for {sys.executable} "
                      "(apt-get install python3-jsonschema)")
    with open(schema_path, encoding="utf-8") as f:
        schema = json.load(f)
    cls = jsonschema.validators.validator_for(schema)
    cls.check_schema(schema)
    validator = cls(schema, format_checker=jsonschema.FormatChecker())
    ref_log, log, _, _ = sarif_partial(d)
    for what, doc in (("good.mpf missing.mpf bad.mpf", log), ("good.mpf bad.mpf", ref_log)):
        errors = sorted(validator.iter_errors(doc), key=lambda e: list(e.absolute_path))
        check(not errors, f"`isolint --format sarif {what}` is not valid SARIF 2.1.0:\n" +
              "\n".join(f"  at /{'/'.join(str(x) for x in e.absolute_path)}: {e.message}"
                        for e in errors[:20]))


# ----------------------------------------------------------------------------------------
# 6. isocc shows what stops it

def case_isocc_shows_suppressed_error(d):
    write(os.path.join(d, "p.mpf"), "R0 = 1 ; isolint: disable=E301\nG01 X10 F100\nM30\n")
    lint = run("isolint", "p.mpf", cwd=d)
    check(lint.rc == 0, f"isolint should pass (the error is suppressed inline)\n{lint.describe()}")
    check(not DIAG_HEAD.findall(lint.out), f"isolint shows a diagnostic\n{lint.describe()}")
    res = run("isocc", "p.mpf", "-o", "p.isob", cwd=d)
    check(res.rc == 1, f"isocc should refuse to compile R0 (exit 1)\n{res.describe()}")
    check(re.search(rb"^p\.mpf:1:1: error: .*\[E301 r-index\]$", res.err, re.M),
          f"isocc does not print the E301 diagnostic\n{res.describe()}")
    check(re.search(rb"^ +p\.mpf:1:\d+: note: .*still prevents compiling", res.err, re.M),
          f"isocc does not add a note saying the error `still prevents compiling`\n{res.describe()}")
    check(not os.path.exists(os.path.join(d, "p.isob")), "isocc wrote an image anyway")
    check(not tmp_leftovers(d), f"temporary files left behind: {tmp_leftovers(d)}")


# ----------------------------------------------------------------------------------------
# 7. One command-line style

def case_cli_unknown_option(d):
    write(os.path.join(d, "p.mpf"), GOOD)
    for tool_name, args in (("isolint", ["--no-such-option", "p.mpf"]),
                            ("isocc", ["--no-such-option", "p.mpf", "-o", "p.isob"]),
                            ("isosim", ["--no-such-option", "p.mpf"]),
                            ("isolint", ["-Z", "p.mpf"])):
        res = run(tool_name, *args, cwd=d)
        check_usage_error(res, tool_name, f"`{res.what()}`")
        check(res.out == b"", f"`{res.what()}` printed on stdout\n{res.describe()}")
    check(not os.path.exists(os.path.join(d, "p.isob")), "isocc wrote an image on a usage error")


def case_cli_bad_value(d):
    write(os.path.join(d, "p.mpf"), GOOD)
    for tool_name, args in (("isolint", ["--format", "xml", "p.mpf"]),
                            ("isolint", ["--max-diagnostics", "-3", "p.mpf"]),
                            ("isolint", ["--max-diagnostics", "lots", "p.mpf"]),
                            ("isolint", ["--color", "sometimes", "p.mpf"]),
                            ("isolint", ["-j", "0", "p.mpf"]),
                            ("isosim", ["--dt", "abc", "p.mpf"]),
                            ("isosim", ["--dt", "0", "p.mpf"]),
                            ("isosim", ["--max-steps", "-1", "p.mpf"]),
                            ("isosim", ["--format", "xml", "p.mpf"]),
                            ("isosim", ["--dialect", "fanuc", "p.mpf"]),
                            ("isocc", ["--dialect", "fanuc", "p.mpf", "-o", "p.isob"]),
                            ("isocc", ["--color", "sometimes", "p.mpf", "-o", "p.isob"])):
        res = run(tool_name, *args, cwd=d)
        check_usage_error(res, tool_name, f"`{res.what()}`")
    check(not os.path.exists(os.path.join(d, "p.isob")), "isocc wrote an image on a usage error")


def case_cli_no_input(d):
    for tool_name, args in (("isolint", []), ("isocc", []), ("isosim", []),
                            ("isocc", ["-o", "p.isob"]), ("isolint", ["--format", "json"])):
        res = run(tool_name, *args, cwd=d)
        check_usage_error(res, tool_name, f"`{res.what()}`")


def case_cli_empty_folder(d):
    os.mkdir(os.path.join(d, "empty"))
    for tool_name, args in (("isolint", ["empty"]), ("isocc", ["empty", "-o", "p.isob"]),
                            ("isosim", ["empty"])):
        res = run(tool_name, *args, cwd=d)
        check_usage_error(res, tool_name, f"`{res.what()}` (an empty folder)")
    check(not os.path.exists(os.path.join(d, "p.isob")), "isocc wrote an image for an empty folder")


def case_cli_disable_comma_list(d):
    write(os.path.join(d, "f.mpf"), "G90 G91 X10\nG01 X10\nG90 X0\nM30\n")
    res = run("isolint", "f.mpf", cwd=d)
    codes = re.findall(rb"\[(W40[12]) ", res.out)
    check(sorted(set(codes)) == [b"W401", b"W402"], f"the program should give W401 and W402\n"
                                                    f"{res.describe()}")
    for args in (["--disable", "W402,W401"], ["--disable", "w402,g-conflict"],
                 ["--disable", "W402", "--disable", "feed-unset,W401"]):
        res = run("isolint", *args, "f.mpf", cwd=d)
        check(res.rc == 0, f"`{res.what()}`: expected exit 0\n{res.describe()}")
        check(not DIAG_HEAD.findall(res.out), f"`{res.what()}` still reports\n{res.describe()}")
        check(count_line(res.out) == "1 file checked: 0 errors, 0 warnings, 0 infos",
              f"`{res.what()}`: count line `{count_line(res.out)}`")


def case_cli_disable_unknown_code(d):
    write(os.path.join(d, "f.mpf"), GOOD)
    for args in (["--disable", "W402,W999"], ["--disable", "W999"],
                 ["--disable", "feed-unset,no-such-rule"]):
        res = run("isolint", *args, "f.mpf", cwd=d)
        line = check_usage_error(res, "isolint", f"`{res.what()}`")
        bad = args[1].split(",")[-1]
        check(bad in line, f"`{res.what()}`: the message does not name `{bad}`: `{line}`")
        check(res.out == b"", f"`{res.what()}` printed on stdout\n{res.describe()}")


def case_inline_unknown_suppression(d):
    write(os.path.join(d, "f.mpf"), "G01 X10 F100 ; isolint: disable=W999\nM30\n")
    res = run("isolint", "f.mpf", cwd=d)
    check(res.rc == 0, f"a warning alone: expected exit 0\n{res.describe()}")
    check(re.search(rb"^f\.mpf:1:\d+: warning: .*W999.*\[W419 suppression-unknown\]$", res.out, re.M),
          f"expected warning W419 suppression-unknown naming W999\n{res.describe()}")
    res = run("isolint", "--format", "json", "f.mpf", cwd=d)
    diags = json.loads(res.out.decode("utf-8"))["diagnostics"]
    check([(x["code"], x["name"], x["severity"]) for x in diags]
          == [("W419", "suppression-unknown", "warning")],
          f"json: expected one W419 warning, got {diags}")


# ----------------------------------------------------------------------------------------
# 8. isosim on a terminal

def run_on_pty(args, cwd, timeout=20):
    master, slave = pty.openpty()
    argv = [tool("isosim")] + args
    try:
        p = _popen_retry(argv, cwd=cwd, stdin=subprocess.DEVNULL, stdout=slave,
                         stderr=subprocess.PIPE)
    finally:
        os.close(slave)
    chunks = []
    deadline = time.monotonic() + timeout
    try:
        while time.monotonic() < deadline:
            r, _, _ = select.select([master], [], [], 0.2)
            if r:
                try:
                    data = os.read(master, 65536)
                except OSError:  # EIO: the slave side is closed
                    break
                if not data:
                    break
                chunks.append(data)
            elif p.poll() is not None:
                # drain what is left
                while select.select([master], [], [], 0)[0]:
                    try:
                        data = os.read(master, 65536)
                    except OSError:
                        data = b""
                    if not data:
                        break
                    chunks.append(data)
                break
        err = p.communicate(timeout=max(1, deadline - time.monotonic()))[1]
    finally:
        os.close(master)
        if p.poll() is None:
            p.kill()
            p.communicate()
    out = b"".join(chunks).replace(b"\r\n", b"\n")
    return Result(["isosim"] + args, p.returncode, out, err)


def case_isosim_terminal_summary(d):
    write(os.path.join(d, "p.mpf"), GOOD)
    res = run_on_pty(["p.mpf"], d)
    check(res.rc == 0, f"isosim on a terminal: expected exit 0\n{res.describe()}")
    both = res.out + b"\n" + res.err
    check(b"cycle_time_s:" in both, f"isosim on a terminal: no summary (cycle_time_s:)\n"
                                    f"{res.describe()}")
    check(not re.search(rb"^t,X", both, re.M), f"isosim on a terminal prints the CSV header\n"
                                               f"{res.describe()}")
    check(not re.search(rb"^0\.01,", both, re.M), f"isosim on a terminal prints CSV rows\n"
                                                  f"{res.describe()}")
    hints = [l for l in res.err.split(b"\n") if b"-o FILE" in l]
    check(len(hints) == 1, f"isosim on a terminal: expected one hint line with `-o FILE` on "
                           f"stderr\n{res.describe()}")


# A loop whose run time the progress-line case sets from a short timed run of it.
def looping_program(turns):
    """A program of `turns` turns of a four-line loop: its run time grows with `turns`."""
    return f"G64 G01 F100\nL: X10\nX0\nR1 = R1 + 1\nIF R1 < {turns} GOTOB L\nM30\n"


LOOP_ARGS = ["p.mpf", "--summary", "--max-steps", "1000000000", "--max-time", "1e12"]


def turns_for_seconds(d, seconds):
    """The loop turns that keep isosim busy about `seconds` on this build and machine (a
    sanitizer build runs ten times slower than a release one), from a short timed run."""
    probe = 200000
    write(os.path.join(d, "p.mpf"), looping_program(probe))
    start = time.monotonic()
    res = run("isosim", *LOOP_ARGS, "--quiet", cwd=d)
    took = time.monotonic() - start
    check(res.rc == 0, f"the timing run failed\n{res.describe()}")
    return max(probe, min(200000000, int(probe * seconds / max(took, 1e-3))))


def run_stderr_on_pty(args, cwd, timeout=60):
    """isosim with standard error a terminal and standard output a pipe: (rc, out, terminal)."""
    master, slave = pty.openpty()
    try:
        p = _popen_retry([tool("isosim")] + args, cwd=cwd, stdin=subprocess.DEVNULL,
                         stdout=subprocess.PIPE, stderr=slave)
    finally:
        os.close(slave)
    chunks = []
    deadline = time.monotonic() + timeout
    try:
        while time.monotonic() < deadline:
            r, _, _ = select.select([master], [], [], 0.2)
            if not r:
                if p.poll() is not None:
                    break
                continue
            try:
                data = os.read(master, 65536)
            except OSError:  # EIO: the slave side is closed
                break
            if not data:
                break
            chunks.append(data)
        out = p.communicate(timeout=max(1, deadline - time.monotonic()))[0]
    finally:
        os.close(master)
        if p.poll() is None:
            p.kill()
            p.communicate()
    return p.returncode, out, b"".join(chunks)


def case_isosim_progress_line(d):
    # each run lasts about 3 s, well past the first second after which the line is shown
    write(os.path.join(d, "p.mpf"), looping_program(turns_for_seconds(d, 3)))
    rc, out, term = run_stderr_on_pty(LOOP_ARGS, d)
    check(rc == 0 and b"status: ok" in out, f"a long run: exit {rc}\n{show(out)}\n{show(term)}")
    lines = re.findall(rb"\risosim: running\.\.\. t=(\d+(?::\d\d)?:\d\d\.\d) simulated, (\d+) blocks, "
                       rb"(\d+) lines, (\d+(?:\.\d)?)x real time\x1b\[K", term)
    check(lines, f"a run of over a second: no progress line on the terminal\n{show(term)}")
    blocks = [int(b) for _, b, _, _ in lines]
    executed = [int(n) for _, _, n, _ in lines]
    check(blocks == sorted(blocks) and executed == sorted(executed)
          and all(b <= n for b, n in zip(blocks, executed)),
          f"the progress line's counts do not grow, or blocks exceed lines\n{show(term)}")
    check(term.endswith(b"\r\x1b[K"), f"the progress line is not erased at the end\n{show(term)}")
    check(b"running" not in out, f"the progress line went to standard output\n{show(out)}")
    # --quiet: none; a pipe: none
    rc, out, term = run_stderr_on_pty(LOOP_ARGS + ["--quiet"], d)
    check(rc == 0 and b"status: ok" in out, f"--quiet: exit {rc}\n{show(out)}")
    check(b"running" not in term, f"--quiet shows a progress line\n{show(term)}")
    res = run("isosim", *LOOP_ARGS, cwd=d)
    check(res.rc == 0 and b"running" not in res.err, f"a pipe shows a progress line\n{res.describe()}")


def case_isosim_pipe_csv(d):
    write(os.path.join(d, "p.mpf"), GOOD)
    res = run("isosim", "p.mpf", cwd=d)
    check(res.rc == 0, f"expected exit 0\n{res.describe()}")
    check(res.out.startswith(b"t,X,Y,Z,A,B,C,U,V,W\n0,0,0,0,0,0,0,0,0,0\n"),
          f"isosim on a pipe: stdout is not the CSV trace\n{res.describe()}")
    check(b"cycle_time_s:" in res.err, f"isosim on a pipe: no summary on stderr\n{res.describe()}")
    check(b"-o FILE" not in res.err, f"isosim on a pipe: the terminal hint is printed\n"
                                     f"{res.describe()}")
    ref = run("isosim", "p.mpf", "-o", "t.csv", cwd=d)
    check(ref.rc == 0, f"isosim -o failed\n{ref.describe()}")
    check(res.out == read(os.path.join(d, "t.csv")),
          "isosim on a pipe: stdout differs from the trace written with -o t.csv")
    rows = res.out.decode().strip().split("\n")
    check(len(rows) > 10 and all(len(r.split(",")) == 10 for r in rows),
          f"isosim on a pipe: malformed CSV\n{show(res.out)}")


# ----------------------------------------------------------------------------------------

CASES = {name[len("case_"):]: fn for name, fn in sorted(globals().items())
         if name.startswith("case_") and callable(fn)}


def main(cases=None, group="safety", description=None):
    """Runs one case of `cases` (this file's CASES by default), named `group`/CASE in the output;
    other test scripts call it with their own cases."""
    global BIN, SOURCE
    cases = CASES if cases is None else cases
    ap = argparse.ArgumentParser(description=(description or __doc__).splitlines()[0])
    ap.add_argument("case", nargs="?")
    ap.add_argument("--bin")
    ap.add_argument("--source")
    ap.add_argument("--list", action="store_true")
    a = ap.parse_args()
    if a.list:
        print("\n".join(cases))
        return 0
    if a.case not in cases or not a.bin or not a.source:
        ap.error(f"give one CASE of {', '.join(cases)}, --bin and --source")
    BIN = os.path.abspath(a.bin)
    SOURCE = os.path.abspath(a.source)
    with tempfile.TemporaryDirectory(prefix=f"{group}-{a.case}-") as d:
        d = os.path.realpath(d)
        try:
            cases[a.case](d)
        except Skip as e:
            print(f"SKIP {group}/{a.case}: {e}")
            return SKIP
        except Failure as e:
            print(f"FAIL {group}/{a.case}:\n{e}", file=sys.stderr)
            return 1
    print(f"ok   {group}/{a.case}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
