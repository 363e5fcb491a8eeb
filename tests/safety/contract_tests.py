#!/usr/bin/python3
"""contract_tests.py: end-to-end tests that nothing wrong passes silently (SPEC.md section 8,
"Inputs, outputs and bounds"; man/isocc.1, man/isosim.1, man/isolint.1).

Usage: contract_tests.py CASE --bin DIR --source DIR
       contract_tests.py --list

CASE is the name of one function case_<CASE> below; tests/safety/CMakeLists.txt registers
each one as the CTest test contract/<CASE> (label safety).  --bin is the directory holding
isolint, isocc and isosim; --source is the source tree.  Every case works in its own
temporary directory and builds its inputs there.

What is checked:
- every file of a program set stops isocc and isosim when it has an error (a semi-automatic
  program beside the main program, a subprogram calling an unknown name), with isolint's
  diagnostics on stderr, and a file that nothing calls does not; isocc and isosim show
  warnings too, limited by --max-diagnostics as isolint's text is;
- every input is read once: process substitution, /dev/fd/N, pipes on standard input, named
  FIFOs, `-` for all three tools (isolint - is <stdin> and has no siblings);
- a failed write to standard output (/dev/full) is exit 2 with
  "error writing standard output: REASON" in every tool and format;
- size caps: /dev/zero as a program, an image or standard input ends at once with exit 2
  and a message naming the input and the 256 MiB limit, in bounded memory;
- the settings file and the machine file are inputs no output may overwrite.

Exit status: 0 pass, 1 fail (the reasons on stderr), 77 skipped (/dev/full or /dev/zero
missing). On a sanitizer build (ISO_SANITIZE_BUILD=1) the memory bound is not checked.
Uses only the standard library and the helpers of safety_tests.py (same folder).
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import safety_tests as st  # noqa: E402  (run, check, snapshot, overwrite_refused, ...)

from safety_tests import Failure, Skip, check, read, show, write  # noqa: E402

SKIP = 77
MIB = 1024 * 1024
RSS_LIMIT = 600 * MIB     # peak RSS of a tool reading /dev/zero (the cap is 256 MiB)
FAST_LIMIT = 20           # seconds: an input over the cap ends at once, never hangs

PROGRAM = "G01 X10 F100\nG00 X0\nM30\n"
MAIN = "G00 X10\nM30\n"
ROTTO_SYNTAX = 'SEMI "Rotto"\nG00 X=\nM30\n'
W401_LINE = "G90 G91 X1\n"          # one W401 g-conflict warning per line


def sanitizer_build():
    return os.environ.get("ISO_SANITIZE_BUILD") == "1"


# ----------------------------------------------------------------------------------------
# Running the tools (beyond safety_tests.run)

def run(name, *args, cwd, stdin=subprocess.DEVNULL, timeout=30):
    return st.run(name, *args, cwd=cwd, stdin=stdin, timeout=timeout)


def run_full(name, *args, cwd, stdin=None, stdout=None, pass_fds=(), timeout=30):
    """Runs a tool with the given stdin/stdout (files or descriptors; None = a pipe), stderr
    to a file; returns (Result, peak RSS in bytes, seconds).  Kills it after `timeout`."""
    argv = [st.tool(name)] + list(args)
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        start = time.monotonic()
        p = st._popen_retry(argv, cwd=cwd,
                            stdin=subprocess.DEVNULL if stdin is None else stdin,
                            stdout=out if stdout is None else stdout, stderr=err,
                            pass_fds=pass_fds)
        timer = threading.Timer(timeout, p.kill)
        timer.start()
        try:
            _, status, usage = os.wait4(p.pid, 0)
        finally:
            timer.cancel()
        seconds = time.monotonic() - start
        p.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        res = st.Result([name] + list(args), p.returncode, out.read(), err.read())
    if seconds >= timeout:
        raise Failure(f"timed out after {timeout} s (killed)\n{res.describe()}")
    return res, usage.ru_maxrss * 1024, seconds  # Linux: ru_maxrss is in KiB


def expect_rc(res, rc, what=""):
    check(res.rc == rc, f"{what}expected exit {rc}, got {res.rc}\n{res.describe()}")


def cycle_time(res, what=""):
    """The cycle_time_s of a text summary on stdout (status ok); it must be non-zero."""
    out = res.out.decode("utf-8", "backslashreplace")
    check(re.search(r"^status: ok$", out, re.M), f"{what}expected `status: ok`\n{res.describe()}")
    m = re.search(r"^cycle_time_s: (\S+) s \(\d+:\d\d(?::\d\d)?\.\d\)$", out, re.M)
    check(m, f"{what}no `cycle_time_s:` line in the summary\n{res.describe()}")
    t = float(m.group(1))
    check(t > 0, f"{what}cycle time is {t}: the program was not run\n{res.describe()}")
    return t


def summary_status(res):
    m = re.search(rb"^status: (\S+)$", res.out, re.M)
    return m.group(1).decode() if m else None


def expect_program_error(res, diag_re, what):
    """Exit 1 (not 0, 2 or 70), the diagnostic on stderr; for isosim also `status: error`
    (on stdout with --summary, else on stderr and no trace on stdout)."""
    check(res.rc == 1, f"{what}: expected exit 1 (the program has errors), got {res.rc}\n"
                       f"{res.describe()}")
    check(re.search(diag_re, res.err, re.M),
          f"{what}: stderr lacks a diagnostic matching /{diag_re.decode()}/\n{res.describe()}")
    if res.cmd[0] == "isosim" and "--summary" in res.cmd:
        check(summary_status(res) == "error",
              f"{what}: expected `status: error` on stdout\n{res.describe()}")
    elif res.cmd[0] == "isosim":  # a trace on stdout: none; the summary is on stderr
        check(res.out == b"", f"{what}: a trace was printed\n{res.describe()}")
        check(re.search(rb"^status: error$", res.err, re.M),
              f"{what}: expected `status: error` on stderr\n{res.describe()}")


def expect_no_file(d, name, res):
    check(not os.path.exists(os.path.join(d, name)),
          f"{name} was written although the command failed\n{res.describe()}")
    leftovers = st.tmp_leftovers(d)
    check(not leftovers, f"temporary files left behind: {leftovers}\n{res.describe()}")


def program_set_fails(d, diag_re, extra=()):
    """isocc and isosim (with and without --entry Rotto) on main.mpf of folder d: each
    fails with the diagnostic `diag_re` and isocc writes nothing."""
    extra = list(extra)
    res = run("isocc", "main.mpf", *extra, "-o", "out.isob", cwd=d)
    expect_program_error(res, diag_re, f"`{res.what()}`")
    expect_no_file(d, "out.isob", res)
    for entry in ([], ["--entry", "Rotto"]):
        res = run("isosim", "main.mpf", *extra, "--summary", *entry, cwd=d)
        expect_program_error(res, diag_re, f"`{res.what()}`")


def semi_folder(d, semi_body):
    write(os.path.join(d, "main.mpf"), MAIN)
    write(os.path.join(d, "rotto.mpf"), semi_body)


# ----------------------------------------------------------------------------------------
# 1. Every file of the program set counts; diagnostics as isolint shows them

def case_semi_syntax_error(d):
    """A broken semi-automatic program beside the main program stops isocc and isosim."""
    semi_folder(d, ROTTO_SYNTAX)
    program_set_fails(d, rb"^rotto\.mpf:2:7: error: .*\[E100 syntax\]$")


def case_semi_semantic_error(d):
    """An error isolint finds after parsing (E110 unsupported) in the SEMI program."""
    semi_folder(d, 'SEMI "Rotto"\nG00 Q10\nM30\n')
    program_set_fails(d, rb"^rotto\.mpf:2:5: error: .*\[E110 unsupported\]$")
    semi_folder(d, 'SEMI "Rotto"\nG54 X1\nM30\n')
    program_set_fails(d, rb"^rotto\.mpf:2:1: error: .*\[E110 unsupported\]$")


def case_semi_unknown_axis(d):
    """E302 in the SEMI program: an axis of no machine, and one the machine file lacks."""
    semi_folder(d, 'SEMI "Rotto"\nPos[D]=10\nM30\n')
    program_set_fails(d, rb"^rotto\.mpf:2:1: error: .*'D'.*\[E302 axis-unknown\]$")
    axis = ('{"name": "%s", "max_velocity": 500, "max_accel": 2000, '
            '"limit_minus": -1000, "limit_plus": 3000}')
    write(os.path.join(d, "xyz.json"),
          '{"name": "xyz", "axes": [%s]}\n' % ", ".join(axis % a for a in "XYZ"))
    semi_folder(d, 'SEMI "Rotto"\nG00 A90\nM30\n')
    program_set_fails(d, rb"^rotto\.mpf:2:5: error: .*'A'.*\[E302 axis-unknown\]$",
                      ["--machine", "xyz.json"])
    # The same program on the built-in machine (which has A) is fine.
    res = run("isocc", "main.mpf", "-o", "out.isob", cwd=d)
    expect_rc(res, 0, "the built-in machine has an A axis: ")


def case_semi_valid_compiles(d):
    """The near miss: a correct SEMI program beside the main program compiles and runs."""
    semi_folder(d, 'SEMI "Rotto"\nG00 X=20\nM30\n')
    res = run("isocc", "main.mpf", "-o", "out.isob", cwd=d)
    expect_rc(res, 0, f"`{res.what()}`: ")
    check(res.err == b"", f"a clean program set prints nothing\n{res.describe()}")
    check(os.path.isfile(os.path.join(d, "out.isob")), f"no out.isob\n{res.describe()}")
    res = run("isocc", "--verify", "out.isob", cwd=d)
    expect_rc(res, 0, "the image does not verify: ")
    for entry in ([], ["--entry", "Rotto"], ["--entry", "rotto"]):
        res = run("isosim", "main.mpf", "--summary", *entry, cwd=d)
        expect_rc(res, 0, f"`{res.what()}`: ")
        cycle_time(res, f"`{res.what()}`: ")


def case_unrelated_broken_spf(d):
    """A broken .spf that nothing calls is not part of what isocc compiles."""
    write(os.path.join(d, "main.mpf"), MAIN)
    write(os.path.join(d, "altro.spf"), "PROC ALTRO SAVE\nG00 X=\nM17\n")
    res = run("isocc", "main.mpf", "-o", "out.isob", cwd=d)
    expect_rc(res, 0, f"a broken .spf nothing calls stops `{res.what()}`: ")
    check(os.path.isfile(os.path.join(d, "out.isob")), f"no out.isob\n{res.describe()}")
    res = run("isosim", "main.mpf", "--summary", cwd=d)
    expect_rc(res, 0, f"a broken .spf nothing calls stops `{res.what()}`: ")
    cycle_time(res, f"`{res.what()}`: ")


def case_proc_unknown_in_subprogram(d):
    """A called subprogram that calls an unknown name: exit 1 with E210, never 70."""
    write(os.path.join(d, "pallet.spf"), "PROC PALLET SAVE\nNOWHERE\nM17\n")
    write(os.path.join(d, "main.mpf"), "PALLET\nM30\n")
    diag = rb"^pallet\.spf:2:1: error: .*'NOWHERE'.*\[E210 proc-unknown\]$"
    res = run("isocc", "main.mpf", "-o", "out.isob", cwd=d)
    expect_program_error(res, diag, f"`{res.what()}`")
    expect_no_file(d, "out.isob", res)
    res = run("isosim", "main.mpf", "--summary", cwd=d)
    expect_program_error(res, diag, f"`{res.what()}`")
    res = run("isosim", "main.mpf", cwd=d)
    expect_program_error(res, diag, f"`{res.what()}`")


def warnings_program(d):
    """p.mpf with 60 W401 warnings (lines 1..60) and no error."""
    write(os.path.join(d, "p.mpf"), W401_LINE * 60 + "G90\nM30\n")


def warning_lines(res):
    return re.findall(rb"^p\.mpf:(\d+):5: warning: .*\[W401 g-conflict\]$", res.err, re.M)


def check_limited(res, shown, what):
    """stderr shows the first `shown` of the 60 warnings, the `N more` line when some are
    left out, and the count line."""
    lines = warning_lines(res)
    check(lines == [str(i).encode() for i in range(1, shown + 1)],
          f"{what}: expected the W401 warnings of lines 1..{shown}, got {len(lines)}: "
          f"{[int(x) for x in lines][:70]}\n{res.describe()}")
    more = re.findall(rb"^(\d+) more diagnostics in p\.mpf\b.*$", res.err, re.M)
    if shown < 60:
        check(more == [str(60 - shown).encode()],
              f"{what}: expected one line `{60 - shown} more diagnostics in p.mpf`\n"
              f"{res.describe()}")
    else:
        check(not more, f"{what}: all are shown, yet a `more diagnostics` line\n{res.describe()}")
    check(re.search(rb"^1 file checked: 0 errors, 60 warnings, 0 infos$", res.err, re.M),
          f"{what}: no count line `1 file checked: 0 errors, 60 warnings, 0 infos`\n"
          f"{res.describe()}")


def case_diagnostics_default_limit(d):
    """isocc and isosim show a program's warnings as isolint's text does: 50 per file."""
    warnings_program(d)
    lint = run("isolint", "p.mpf", cwd=d)
    expect_rc(lint, 0, "isolint on warnings only: ")
    check(b"10 more diagnostics in p.mpf" in lint.out,
          f"isolint does not print `10 more diagnostics in p.mpf`\n{lint.describe()}")
    res = run("isocc", "p.mpf", "-o", "out.isob", cwd=d)
    expect_rc(res, 0, "warnings do not stop isocc: ")
    check(os.path.isfile(os.path.join(d, "out.isob")), f"no out.isob\n{res.describe()}")
    check_limited(res, 50, f"`{res.what()}`")
    check(res.err == lint.out, f"isocc's diagnostics differ from isolint's text\n"
                               f"isolint:\n{show(lint.out, 600)}\n{res.describe()}")
    res = run("isosim", "p.mpf", "--summary", cwd=d)
    expect_rc(res, 0, "warnings do not stop isosim: ")
    cycle_time(res, f"`{res.what()}`: ")
    check_limited(res, 50, f"`{res.what()}`")
    check(res.err == lint.out, f"isosim's diagnostics differ from isolint's text\n"
                               f"isolint:\n{show(lint.out, 600)}\n{res.describe()}")


def case_diagnostics_max_option(d):
    """--max-diagnostics N limits isocc's and isosim's diagnostics per file; 0 shows all."""
    warnings_program(d)
    for n, shown in (("7", 7), ("1", 1), ("0", 60), ("60", 60), ("100", 60)):
        res = run("isocc", "p.mpf", "-o", "out.isob", "--max-diagnostics", n, cwd=d)
        expect_rc(res, 0, f"`{res.what()}`: ")
        check_limited(res, shown, f"`{res.what()}`")
        res = run("isosim", "p.mpf", "--summary", "--max-diagnostics", n, cwd=d)
        expect_rc(res, 0, f"`{res.what()}`: ")
        check_limited(res, shown, f"`{res.what()}`")
    lint = run("isolint", "p.mpf", "--max-diagnostics", "7", cwd=d)
    res = run("isocc", "p.mpf", "-o", "out.isob", "--max-diagnostics", "7", cwd=d)
    check(res.err == lint.out, f"isocc --max-diagnostics 7 differs from isolint's text\n"
                               f"isolint:\n{show(lint.out, 600)}\n{res.describe()}")


# ----------------------------------------------------------------------------------------
# 2. Every input is read once

def reference(d):
    """p.mpf (and a broken sibling broken.spf) in d; the cycle time of isosim p.mpf."""
    write(os.path.join(d, "p.mpf"), PROGRAM)
    write(os.path.join(d, "broken.spf"), "PROC BROKEN SAVE\nG00 X=\nM17\n")
    res = run("isosim", "p.mpf", "--summary", cwd=d)
    expect_rc(res, 0, "reference run: ")
    return cycle_time(res, "reference run: ")


def feeder(data):
    """A pipe with a thread writing `data` into it; returns the read end's descriptor (the
    caller closes it)."""
    r, w = os.pipe()

    def feed():
        try:
            view = memoryview(data)
            while view:
                view = view[os.write(w, view):]
        except OSError:
            pass
        finally:
            os.close(w)

    threading.Thread(target=feed, daemon=True).start()
    return r


def run_piped(name, *args, cwd, data, timeout=FAST_LIMIT):
    """Runs a tool with `data` written to its standard input through a pipe."""
    argv = [st.tool(name)] + list(args)
    p = st._popen_retry(argv, cwd=cwd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                        stderr=subprocess.PIPE)
    try:
        out, err = p.communicate(input=data, timeout=timeout)
    except subprocess.TimeoutExpired:
        p.kill()
        out, err = p.communicate()
        raise Failure(f"timed out after {timeout} s: {name} {args} with a pipe on stdin")
    return st.Result([name] + list(args), p.returncode, out, err)


def case_process_substitution(d):
    """isosim <(cat p.mpf) and /dev/fd/N: the program is read once and run."""
    ref = reference(d)
    bash = shutil.which("bash")
    if bash:
        argv = [bash, "-c", '"$0" <(cat p.mpf) --summary', st.tool("isosim")]
        p = subprocess.run(argv, cwd=d, stdin=subprocess.DEVNULL, capture_output=True,
                           timeout=FAST_LIMIT)
        res = st.Result(["bash", "-c", "isosim <(cat p.mpf) --summary"], p.returncode,
                        p.stdout, p.stderr)
        expect_rc(res, 0)
        t = cycle_time(res, "isosim <(cat p.mpf): ")
        check(t == ref, f"isosim <(cat p.mpf) gives cycle time {t}, the file gives {ref}\n"
                        f"{res.describe()}")
    r = feeder(read(os.path.join(d, "p.mpf")))
    try:
        res, _, _ = run_full("isosim", f"/dev/fd/{r}", "--summary", cwd=d, pass_fds=(r,),
                             timeout=FAST_LIMIT)
    finally:
        os.close(r)
    expect_rc(res, 0)
    t = cycle_time(res, "isosim /dev/fd/N: ")
    check(t == ref, f"isosim /dev/fd/N gives cycle time {t}, the file gives {ref}\n"
                    f"{res.describe()}")
    r = feeder(read(os.path.join(d, "p.mpf")))
    try:
        res, _, _ = run_full("isocc", f"/dev/fd/{r}", "-o", "fd.isob", cwd=d, pass_fds=(r,),
                             timeout=FAST_LIMIT)
    finally:
        os.close(r)
    expect_rc(res, 0)
    res = run("isosim", "fd.isob", "--summary", cwd=d)
    check(cycle_time(res, "image of /dev/fd/N: ") == ref, f"cycle time differs\n{res.describe()}")


def case_stdin_program(d):
    """`-` is standard input for isosim and isocc; a piped image runs and verifies."""
    ref = reference(d)
    with open(os.path.join(d, "p.mpf"), "rb") as f:
        res = run("isosim", "-", "--summary", cwd=d, stdin=f)
    expect_rc(res, 0)
    t = cycle_time(res, "isosim - < p.mpf: ")
    check(t == ref, f"isosim - gives cycle time {t}, the file gives {ref}\n{res.describe()}")
    res = run_piped("isosim", "-", "--summary", cwd=d, data=read(os.path.join(d, "p.mpf")))
    expect_rc(res, 0)
    t = cycle_time(res, "cat p.mpf | isosim -: ")
    check(t == ref, f"cat p.mpf | isosim - gives cycle time {t}, the file gives {ref}\n"
                    f"{res.describe()}")
    with open(os.path.join(d, "p.mpf"), "rb") as f:
        res = run("isocc", "-", "-o", "out.isob", cwd=d, stdin=f)
    expect_rc(res, 0)
    check(os.path.isfile(os.path.join(d, "out.isob")), f"no out.isob\n{res.describe()}")
    res = run("isocc", "--verify", "out.isob", cwd=d)
    expect_rc(res, 0, "the image of isocc - does not verify: ")
    res = run("isosim", "out.isob", "--summary", cwd=d)
    t = cycle_time(res, "the image of isocc -: ")
    check(t == ref, f"the image of isocc - gives cycle time {t}, the file gives {ref}")


def case_stdin_image(d):
    """An image on standard input: isosim - runs it, isocc --verify - checks it."""
    ref = reference(d)
    res = run("isocc", "p.mpf", "-o", "out.isob", cwd=d)
    expect_rc(res, 0)
    res = run_piped("isosim", "-", "--summary", cwd=d, data=read(os.path.join(d, "out.isob")))
    expect_rc(res, 0)
    t = cycle_time(res, "isosim - < out.isob: ")
    check(t == ref, f"a piped image gives cycle time {t}, the file gives {ref}\n"
                    f"{res.describe()}")
    with open(os.path.join(d, "out.isob"), "rb") as f:
        res = run("isocc", "--verify", "-", cwd=d, stdin=f)
    expect_rc(res, 0)
    # The near miss: a corrupt image on standard input is refused.
    data = bytearray(read(os.path.join(d, "out.isob")))
    data[len(data) // 2] ^= 0xFF
    write(os.path.join(d, "bad.isob"), bytes(data))
    with open(os.path.join(d, "bad.isob"), "rb") as f:
        res = run("isocc", "--verify", "-", cwd=d, stdin=f)
    expect_rc(res, 2, "a corrupt image on standard input: ")


def fifo_run(d, fifo, data, name, *args):
    """Runs a tool on a named FIFO that a thread fills with `data` once."""
    path = os.path.join(d, fifo)
    if os.path.exists(path):
        os.unlink(path)
    os.mkfifo(path)

    def feed():
        try:
            with open(path, "wb") as f:   # blocks until the tool opens it
                f.write(data)
        except OSError:
            pass

    threading.Thread(target=feed, daemon=True).start()
    res, _, _ = run_full(name, *args, cwd=d, timeout=FAST_LIMIT)
    return res


def case_fifo_program(d):
    """A named FIFO as program (isosim, isocc) and as image (isosim): read once, no hang."""
    ref = reference(d)
    src = read(os.path.join(d, "p.mpf"))
    res = fifo_run(d, "prog.fifo", src, "isosim", "prog.fifo", "--summary")
    expect_rc(res, 0)
    t = cycle_time(res, "isosim FIFO: ")
    check(t == ref, f"isosim on a FIFO gives cycle time {t}, the file gives {ref}")
    res = fifo_run(d, "prog.fifo", src, "isocc", "prog.fifo", "-o", "fifo.isob")
    expect_rc(res, 0)
    res = run("isocc", "--verify", "fifo.isob", cwd=d)
    expect_rc(res, 0, "the image of a FIFO does not verify: ")
    res = fifo_run(d, "image.fifo", read(os.path.join(d, "fifo.isob")),
                   "isosim", "image.fifo", "--summary")
    expect_rc(res, 0)
    t = cycle_time(res, "isosim on an image FIFO: ")
    check(t == ref, f"an image on a FIFO gives cycle time {t}, the file gives {ref}")
    res = fifo_run(d, "image.fifo", read(os.path.join(d, "fifo.isob")),
                   "isocc", "--verify", "image.fifo")
    expect_rc(res, 0)


def case_isolint_stdin(d):
    """isolint - checks standard input as <stdin>, without the files of the current folder."""
    write(os.path.join(d, "broken.spf"), "PROC BROKEN SAVE\nG00 X=\nM17\n")
    write(os.path.join(d, "helper.spf"), "PROC HELPER SAVE\nG00 X1\nM17\n")
    res = run_piped("isolint", "-", cwd=d, data=b"G00 X=\nM30\n")
    expect_rc(res, 1, "isolint - with an error: ")
    check(re.search(rb"^<stdin>:1:7: error: .*\[E100 syntax\]$", res.out, re.M),
          f"isolint -: no diagnostic `<stdin>:1:7: error: ... [E100 syntax]`\n{res.describe()}")
    check(b"broken.spf" not in res.out + res.err,
          f"isolint - reports a file of the current folder\n{res.describe()}")
    res = run_piped("isolint", "-", cwd=d, data=PROGRAM.encode())
    expect_rc(res, 0, "isolint - with a clean program: ")
    check(b"broken.spf" not in res.out + res.err,
          f"isolint - reports a file of the current folder\n{res.describe()}")
    check(re.search(rb"^1 file checked: 0 errors, 0 warnings, 0 infos$", res.out, re.M),
          f"isolint -: expected `1 file checked: 0 errors, 0 warnings, 0 infos`\n"
          f"{res.describe()}")
    # Standard input has no siblings: HELPER of helper.spf is not in its program set.
    res = run_piped("isolint", "-", cwd=d, data=b"HELPER\nM30\n")
    expect_rc(res, 1, "isolint - calling a subprogram of the current folder: ")
    check(re.search(rb"^<stdin>:1:1: error: .*'HELPER'.*\[E210 proc-unknown\]$", res.out, re.M),
          f"isolint -: expected E210 for HELPER (no siblings)\n{res.describe()}")


# ----------------------------------------------------------------------------------------
# 3. Write errors on standard output

WRITE_ERROR = b"error writing standard output: No space left on device"


def full_stdout(d, name, *args):
    if not os.path.exists("/dev/full"):
        raise Skip("/dev/full does not exist")
    with open("/dev/full", "wb") as full:
        res, _, _ = run_full(name, *args, cwd=d, stdout=full)
    what = f"`{res.what()} > /dev/full`"
    check(res.rc == 2, f"{what}: expected exit 2, got {res.rc}\n{res.describe()}")
    check(WRITE_ERROR in res.err,
          f"{what}: stderr lacks `{WRITE_ERROR.decode()}`\n{res.describe()}")


def case_write_error_isosim(d):
    write(os.path.join(d, "p.mpf"), PROGRAM)
    full_stdout(d, "isosim", "p.mpf")
    full_stdout(d, "isosim", "p.mpf", "--format", "csv", "-o", "-")
    full_stdout(d, "isosim", "p.mpf", "--summary")
    full_stdout(d, "isosim", "p.mpf", "--summary", "--format", "json")
    full_stdout(d, "isosim", "p.mpf", "--format", "json", "-o", "-")
    full_stdout(d, "isosim", "p.mpf", "--format", "json")
    full_stdout(d, "isosim", "--print-machine")


def case_write_error_isolint(d):
    write(os.path.join(d, "p.mpf"), PROGRAM)
    write(os.path.join(d, "bad.mpf"), "G00 X=\nM30\n")
    for f in ("p.mpf", "bad.mpf"):
        full_stdout(d, "isolint", f)
        full_stdout(d, "isolint", "--format", "json", f)
        full_stdout(d, "isolint", "--format", "sarif", f)


def case_write_error_isocc(d):
    write(os.path.join(d, "p.mpf"), PROGRAM)
    res = run("isocc", "p.mpf", "-o", "out.isob", cwd=d)
    expect_rc(res, 0)
    full_stdout(d, "isocc", "--disasm", "out.isob")
    full_stdout(d, "isocc", "p.mpf", "-o", "-")


# ----------------------------------------------------------------------------------------
# 5. Size caps

def capped(d, input_name, name, *args, stdin=None):
    """The tool ends at once (exit 2) with a message naming the input and 256 MiB, in
    bounded memory."""
    if not os.path.exists("/dev/zero"):
        raise Skip("/dev/zero does not exist")
    limit = 120 if sanitizer_build() else FAST_LIMIT
    res, rss, seconds = run_full(name, *args, cwd=d, stdin=stdin, timeout=limit)
    what = f"`{res.what()}`" + (" < /dev/zero" if stdin is not None else "")
    check(res.rc == 2, f"{what}: expected exit 2, got {res.rc}\n{res.describe()}")
    check(input_name.encode() in res.err and b"256 MiB" in res.err,
          f"{what}: stderr does not name `{input_name}` and `256 MiB`\n{res.describe()}")
    check(res.out == b"", f"{what}: prints on stdout\n{res.describe()}")
    if not sanitizer_build():
        check(rss < RSS_LIMIT, f"{what}: peak RSS {rss / MIB:.0f} MiB, over "
                               f"{RSS_LIMIT // MIB} MiB\n{res.describe()}")
    return res


def case_size_cap_isolint(d):
    capped(d, "/dev/zero", "isolint", "/dev/zero")


def case_size_cap_isocc(d):
    res = capped(d, "/dev/zero", "isocc", "/dev/zero", "-o", "z.isob")
    expect_no_file(d, "z.isob", res)


def case_size_cap_isosim(d):
    capped(d, "/dev/zero", "isosim", "/dev/zero", "--summary")


def case_size_cap_image(d):
    capped(d, "/dev/zero", "isocc", "--verify", "/dev/zero")


def case_size_cap_stdin(d):
    with open("/dev/zero", "rb") as z:
        capped(d, "<stdin>", "isosim", "-", stdin=z)


# ----------------------------------------------------------------------------------------
# 8. The settings file and the machine file are inputs

def case_settings_file_not_output(d):
    write(os.path.join(d, "p.mpf"), PROGRAM)
    write(os.path.join(d, "isotools.toml"), 'disable = ["W402"]\n')
    write(os.path.join(d, "c.toml"), 'disable = ["W402"]\n')
    res = run("isosim", "p.mpf", "--summary", cwd=d)
    expect_rc(res, 0, "the settings file is valid: ")
    st.overwrite_refused(d, "isosim", ["p.mpf", "-o", "isotools.toml"], "-o", "isotools.toml",
                         "isotools.toml")
    st.overwrite_refused(d, "isocc", ["p.mpf", "-o", "isotools.toml"], "-o", "isotools.toml",
                         "isotools.toml")
    st.overwrite_refused(d, "isocc", ["--config", "c.toml", "p.mpf", "-o", "c.toml"], "-o",
                         "c.toml", "c.toml")
    st.overwrite_refused(d, "isosim", ["--config", "c.toml", "p.mpf", "-o", "c.toml"], "-o",
                         "c.toml", "c.toml")


def case_machine_file_not_output(d):
    write(os.path.join(d, "p.mpf"), PROGRAM)
    st.print_machine(d, "m.json")
    check(read(os.path.join(d, "m.json")).strip().startswith(b"{"),
          "isosim --print-machine did not print a machine file")
    st.overwrite_refused(d, "isosim", ["--machine", "m.json", "p.mpf", "-o", "m.json"], "-o",
                         "m.json", "m.json")
    st.overwrite_refused(d, "isocc", ["--machine", "m.json", "p.mpf", "-o", "./m.json"], "-o",
                         "./m.json", "m.json")


# ----------------------------------------------------------------------------------------

CASES = {name[len("case_"):]: fn for name, fn in sorted(globals().items())
         if name.startswith("case_") and callable(fn)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("case", nargs="?")
    ap.add_argument("--bin")
    ap.add_argument("--source")
    ap.add_argument("--list", action="store_true")
    a = ap.parse_args()
    if a.list:
        print("\n".join(CASES))
        return 0
    if a.case not in CASES or not a.bin or not a.source:
        ap.error(f"give one CASE of {', '.join(CASES)}, --bin and --source")
    st.BIN = os.path.abspath(a.bin)
    st.SOURCE = os.path.abspath(a.source)
    with tempfile.TemporaryDirectory(prefix=f"contract-{a.case}-") as d:
        d = os.path.realpath(d)
        try:
            CASES[a.case](d)
        except Skip as e:
            print(f"SKIP contract/{a.case}: {e}")
            return SKIP
        except Failure as e:
            print(f"FAIL contract/{a.case}:\n{e}", file=sys.stderr)
            return 1
    print(f"ok   contract/{a.case}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
