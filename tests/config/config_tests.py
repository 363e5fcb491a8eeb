#!/usr/bin/python3
"""config_tests.py: end-to-end tests of settings files (isotools.toml) and machine files as
inputs of isolint, isocc and isosim.

Usage: config_tests.py CASE --bin DIR
CASE is the name of one function case_<CASE> below (tests/config/CMakeLists.txt registers each
as the CTest test config/<CASE>); --bin is the directory holding the three tools. Every case
works in its own temporary directory. Exit status: 0 pass, 1 fail (reasons on stderr), 77
skipped. Uses only the standard library.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import threading

BIN = None
MIB = 1024 * 1024
TOOLS = ("isolint", "isocc", "isosim")


class Failure(Exception):
    pass


def check(cond, msg):
    if not cond:
        raise Failure(msg)


def run(name, *args, cwd, timeout=60):
    """Runs a tool; returns (exit code, stdout, stderr as text, peak RSS in bytes)."""
    argv = [os.path.join(BIN, name)] + list(args)
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        p = subprocess.Popen(argv, cwd=cwd, stdin=subprocess.DEVNULL, stdout=out, stderr=err)
        timer = threading.Timer(timeout, p.kill)
        timer.start()
        try:
            _, status, usage = os.wait4(p.pid, 0)
        finally:
            timer.cancel()
        rc = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        return rc, out.read().decode("utf-8", "replace"), err.read().decode("utf-8", "replace"), \
            usage.ru_maxrss * 1024


def args_for(name, program, *extra):
    if name == "isocc":
        return [program, "-o", program + ".isob", *extra]
    if name == "isosim":
        return [program, "--summary", *extra]
    return [program, *extra]


def write(path, data):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)


def expect_error(rc, err, what, cmd):
    check(rc == 2, f"{cmd}: exit {rc}, expected 2; stderr:\n{err[:2000]}")
    check(what in err, f"{cmd}: stderr lacks {what!r}:\n{err[:2000]}")


def case_deep_settings_above(d):
    """A 100 KB isotools.toml of one dotted key with 50,001 parts, found in a parent folder,
    is exit 2 with the place of the 65th level in every tool (it used to overflow the stack)."""
    write(os.path.join(d, "isotools.toml"), ".".join(["a"] * 50001) + " = 1\n")
    write(os.path.join(d, "progs", "p.mpf"), "G01 X1 F100\nM30\n")
    for name in TOOLS:
        rc, _, err, _ = run(name, *args_for(name, "p.mpf"), cwd=os.path.join(d, "progs"))
        expect_error(rc, err, "isotools.toml:1:128: error: tables, arrays or dotted keys nested deeper than 64 levels",
                     name)


def case_deep_machine(d):
    """A machine file nested 100,000 deep is exit 2, with the cap, in every tool."""
    write(os.path.join(d, "m.json"), '{"axes": ' + "[" * 100000 + "]" * 100000 + "}")
    write(os.path.join(d, "p.mpf"), "M30\n")
    for name in TOOLS:
        rc, _, err, _ = run(name, *args_for(name, "p.mpf", "--machine", "m.json"), cwd=d)
        expect_error(rc, err, "m.json: error: invalid machine file at /: arrays and objects nested deeper than 64 levels",
                     name)


def case_devices_bounded(d):
    """/dev/zero and /dev/urandom as --config or --machine end at once with the size cap, in
    bounded memory."""
    write(os.path.join(d, "p.mpf"), "M30\n")
    sanitized = os.environ.get("ISO_SANITIZE_BUILD") == "1"
    for name in TOOLS:
        for option, kind in (("--config", "settings"), ("--machine", "machine")):
            for dev in ("/dev/zero", "/dev/urandom"):
                rc, _, err, rss = run(name, *args_for(name, "p.mpf", option, dev), cwd=d)
                expect_error(rc, err, f"{dev}: error: the {kind} file is larger than 16 MiB", f"{name} {option} {dev}")
                check(sanitized or rss < 150 * MIB, f"{name} {option} {dev}: peak RSS {rss // MIB} MiB")


def case_missing_and_binary(d):
    """A --config that does not exist is an input error of the usual shape; a settings file
    with a NUL byte or bytes that are not UTF-8 is an error that gives the offset."""
    write(os.path.join(d, "p.mpf"), "M30\n")
    write(os.path.join(d, "nul.toml"), b'dialect = "z32"\n\x00')
    write(os.path.join(d, "latin1.toml"), b"# caf\xe9\n")
    for name in TOOLS:
        rc, _, err, _ = run(name, *args_for(name, "p.mpf", "--config", "nope.toml"), cwd=d)
        check(err == "nope.toml: error: cannot open the settings file: no such file or directory\n",
              f"{name}: {err!r}")
        check(rc == 2, f"{name}: exit {rc}")
        rc, _, err, _ = run(name, *args_for(name, "p.mpf", "--config", "nul.toml"), cwd=d)
        expect_error(rc, err, "nul.toml: error: not a text file: a NUL byte at offset 16", name)
        rc, _, err, _ = run(name, *args_for(name, "p.mpf", "--config", "latin1.toml"), cwd=d)
        expect_error(rc, err, "latin1.toml: error: not a text file: byte 0xe9 at offset 5 is not UTF-8", name)


def case_typos(d):
    """Unknown options, rules and keys name the one meant when it is a typo away, and only
    then."""
    write(os.path.join(d, "p.mpf"), "M30\n")
    cases = [
        ("isosim", ["p.mpf", "--max-tme", "5"], "did you mean '--max-time'?"),
        ("isocc", ["p.mpf", "-o", "p.isob", "--strp"], "did you mean '--strip'?"),
        ("isolint", ["p.mpf", "--disable", "feed-unst"], "did you mean 'feed-unset'?"),
    ]
    for name, args, want in cases:
        rc, _, err, _ = run(name, *args, cwd=d)
        expect_error(rc, err, want, name)
    rc, _, err, _ = run("isolint", "p.mpf", "--colour", "never", cwd=d)
    expect_error(rc, err, "did you mean '--color'?", "--colour")
    rc, _, err, _ = run("isolint", "p.mpf", "--frobnicate", cwd=d)
    check(rc == 2 and "did you mean" not in err, f"--frobnicate: {err!r}")  # nothing is near
    write(os.path.join(d, "s", "isotools.toml"), 'machnie = "m.json"\n')
    write(os.path.join(d, "s", "p.mpf"), "M30\n")
    rc, _, err, _ = run("isolint", "p.mpf", cwd=os.path.join(d, "s"))
    expect_error(rc, err, "unknown key 'machnie'; did you mean 'machine'?", "settings key")


def main():
    global BIN
    ap = argparse.ArgumentParser()
    ap.add_argument("case")
    ap.add_argument("--bin", required=True)
    a = ap.parse_args()
    BIN = a.bin
    fn = globals().get("case_" + a.case)
    if fn is None:
        print(f"no case {a.case}", file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory() as d:
        try:
            fn(d)
        except Failure as e:
            print(f"FAIL {a.case}: {e}", file=sys.stderr)
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
