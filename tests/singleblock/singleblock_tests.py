#!/usr/bin/python3
"""singleblock_tests.py: end-to-end tests of isosim --single-block on a real terminal (tmux).

Usage: singleblock_tests.py CASE --bin DIR --source DIR
       singleblock_tests.py --list

CASE is the name of one function case_<CASE> below; tests/singleblock/CMakeLists.txt
registers each one as the CTest test singleblock/<CASE>.  --bin is the directory holding
isolint, isocc and isosim; --source is the source tree. Every case works in its own temporary
directory and its own tmux server (a socket of its own, killed at the end); a case that needs
tmux and cannot find it is skipped (exit 77). Times are hand-computed from machine_json.

Exit status: 0 pass, 1 fail (the reasons on stderr), 77 skipped. Uses only the standard
library and the helpers of ../safety/safety_tests.py.
"""
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "safety"))
import safety_tests as st  # noqa: E402
from safety_tests import check, write  # noqa: E402


def machine_json():
    """X: 50 mm/s, 1000 mm/s^2: a move of d >= 2.5 mm takes d/50 + 0.05 s."""
    return json.dumps({"name": "single", "dialect": "sidac",
                       "axes": [{"name": "X", "max_velocity": 50, "max_accel": 1000,
                                 "limit_minus": -100, "limit_plus": 100}]})


class Terminal:
    """A command on a tmux pane of its own server; `screen` is what the pane shows."""

    def __init__(self, d, command):
        self.tmux = shutil.which("tmux")
        if not self.tmux:
            raise st.Skip("tmux is not installed")
        self.socket = os.path.join(d, "tmux.sock")
        # the command's exit status stays on the pane after it ends
        shell = f"{command}; echo \"[exit $?]\"; sleep 60"
        self._tmux("-f", "/dev/null", "new-session", "-d", "-x", "200", "-y", "50",
                   "-c", d, "sh", "-c", shell)

    def _tmux(self, *args):
        p = subprocess.run([self.tmux, "-S", self.socket] + list(args), stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, timeout=20)
        check(p.returncode == 0, f"tmux {' '.join(args)} failed: {st.show(p.stderr)}")
        return p.stdout.decode("utf-8", "backslashreplace")

    def screen(self):
        return self._tmux("capture-pane", "-p", "-J", "-S", "-")

    def keys(self, *keys):
        self._tmux("send-keys", *keys)

    def wait_for(self, pattern, what, timeout=20):
        """The screen once `pattern` (a regular expression) is on it."""
        deadline = time.monotonic() + timeout
        while True:
            text = self.screen()
            if re.search(pattern, text, re.M):
                return text
            if time.monotonic() > deadline:
                raise st.Failure(f"{what}: {pattern!r} not on the terminal after {timeout} s:\n"
                                 f"{st.show(text, 4000)}")
            time.sleep(0.1)

    def close(self):
        subprocess.run([self.tmux, "-S", self.socket, "kill-server"], stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL, timeout=20)


def isosim(*args):
    return " ".join(shlex.quote(a) for a in [st.tool("isosim")] + list(args))


def block_lines(text):
    """The block lines on the screen, without the prompt and the command typed after it."""
    return [re.sub(r"  >( .*)?$", "", ln) for ln in text.splitlines() if ln.startswith("t=")]


def sample(d):
    """samples/drilling_when copied to d; the main program's path."""
    for name in ("foratura_piastra.mpf", "foratura.spf"):
        shutil.copy(os.path.join(st.SOURCE, "samples", "drilling_when", name), d)
    return os.path.join(d, "foratura_piastra.mpf")


def summary_cycle_time(d, program):
    res = st.run("isosim", program, "--summary", "--format", "json", cwd=d)
    check(res.rc == 0, f"isosim --summary\n{res.describe()}")
    return json.loads(res.out)["cycle_time_s"]


def case_sample_first_blocks(d):
    """The sample: the first block waits; Enter advances one block at a time; c runs the rest
    with the same cycle time as --summary; exit 0."""
    program = sample(d)
    term = Terminal(d, isosim("--single-block", "foratura_piastra.mpf"))
    try:
        first = "t=0.000 s  foratura_piastra.mpf:13  R40 = -190          ; quota di sicurezza, " \
                "10 mm sopra la piastra  X=0 Y=0 Z=0"
        text = term.wait_for("^t=.*  >", "the first block and its prompt")
        check(block_lines(text) == [first], f"the first block:\n{st.show(text)}")
        time.sleep(0.3)  # it waits: no second block without Enter
        check(len(block_lines(term.screen())) == 1, f"ran on without Enter:\n{term.screen()}")
        term.keys("Enter")
        text = term.wait_for(r"^t=.*:14 .*  >", "Enter: the second block and its prompt")
        check(block_lines(text)[1].startswith("t=0.000 s  foratura_piastra.mpf:14  R41 = -198"),
              f"the second block:\n{st.show(text)}")
        for n in (15, 16, 20, 21):
            term.keys("Enter")
            term.wait_for(rf"^t=.*:{n} .*  >", f"Enter: the block of line {n}")
        # two assignments on one line are one block (line 20), the comment lines none
        text = term.screen()
        check([ln.split()[2] for ln in block_lines(text)] ==
              [f"foratura_piastra.mpf:{n}" for n in (13, 14, 15, 16, 20, 21)],
              f"the blocks:\n{st.show(text)}")
        check(block_lines(text)[4] == "t=0.000 s  foratura_piastra.mpf:20  R101 = 120 R111 = 80  X=0 Y=0 Z=0",
              f"the fifth block:\n{st.show(text)}")
        term.keys("c", "Enter")
        text = term.wait_for(r"^\[exit \d+\]", "c: the end")
        expected = summary_cycle_time(d, program)
        m = re.search(r"^cycle_time_s: ([0-9.]+) s \(.*\)$", text, re.M)
        check(m is not None and abs(float(m.group(1)) - expected) <= 1e-6,
              f"the cycle time of --summary, {expected} s:\n{st.show(text)}")
        check("[exit 0]" in text and len(block_lines(text)) == 6,
              f"c prints no more blocks, exit 0:\n{st.show(text)}")
    finally:
        term.close()


def case_times_and_axes(d):
    """Hand-computed: the second G00 starts at 0.25 s with X at 10, the third at 0.5 s."""
    write(os.path.join(d, "p.mpf"), "G00 X10\nG00 X20\n  G00 X0   \nM30\n")
    write(os.path.join(d, "m.json"), machine_json())
    term = Terminal(d, isosim("--single-block", "p.mpf", "--machine", "m.json"))
    try:
        term.wait_for("^t=.*  >", "the first block and its prompt")
        for n in (2, 3, 4):  # one Enter at a time, each once the prompt is there
            term.keys("Enter")
            term.wait_for(rf"^t=.*p\.mpf:{n} .*  >", f"Enter: the block of line {n}")
        term.keys("Enter")
        text = term.wait_for(r"^\[exit \d+\]", "the end")
        check(block_lines(text) == ["t=0.000 s  p.mpf:1  G00 X10  X=0",
                                    "t=0.250 s  p.mpf:2  G00 X20  X=10",
                                    "t=0.500 s  p.mpf:3  G00 X0  X=20",
                                    "t=0.950 s  p.mpf:4  M30  X=0"],
              f"the blocks:\n{st.show(text)}")
        check(re.search(r"^cycle_time_s: 0\.95 s \(0:01\.0\)$", text, re.M) and "[exit 0]" in text,
              f"the summary, exit 0:\n{st.show(text)}")
    finally:
        term.close()


def case_quit(d):
    """q stops the run: the summary says the run was ended, exit 0."""
    write(os.path.join(d, "p.mpf"), "G00 X10\nG00 X20\nG00 X0\nM30\n")
    write(os.path.join(d, "m.json"), machine_json())
    term = Terminal(d, isosim("--single-block", "p.mpf", "--machine", "m.json"))
    try:
        term.wait_for("^t=.*  >", "the first block and its prompt")
        term.keys("Enter")
        term.wait_for(r"^t=0\.250 s.*  >", "the second block and its prompt")
        term.keys("q", "Enter")
        text = term.wait_for(r"^\[exit \d+\]", "q: the end")
        check(len(block_lines(text)) == 2, f"q stops at once:\n{st.show(text)}")
        check("the debugger ended the run" in text and "[exit 0]" in text,
              f"the summary says the run was ended, exit 0:\n{st.show(text)}")
        check(re.search(r"^cycle_time_s: 0\.25 s \(0:00\.3\)$", text, re.M),
              f"stopped before the second move:\n{st.show(text)}")
    finally:
        term.close()


def case_when_body_and_help(d):
    """A WHEN body's block names its WHEN; an unknown command prints the commands."""
    write(os.path.join(d, "p.mpf"),
          "WHEN $aa_iw[X] > 5 DO\n  $aa_out[3] = 1\nCANCEL\nG01 X10 F=50\nM30\n")
    write(os.path.join(d, "m.json"), machine_json())
    term = Terminal(d, isosim("--single-block", "p.mpf", "--machine", "m.json"))
    try:
        term.wait_for("^t=.*  >", "the first block and its prompt")
        term.keys("x", "Enter")
        term.wait_for(r"^isosim: single block: Enter runs the next block, c continues to the end, "
                      r"q stops the run\n(.*\n)*.*isosim: single block", "the commands")
        for i in range(5):  # the first block again, then the other four: one Enter at a time
            before = len(block_lines(term.screen()))
            term.keys("Enter")
            deadline = time.monotonic() + 20
            while len(block_lines(term.screen())) <= before and "[exit" not in term.screen():
                check(time.monotonic() < deadline, f"Enter {i + 1} ran no block:\n{st.show(term.screen())}")
                time.sleep(0.05)
        text = term.wait_for(r"^\[exit \d+\]", "the end")
        # G01 X10 at 50 mm/s, 1000 mm/s^2: 0.25 s, symmetric; X passes 5 mm at half of it
        check(block_lines(text) == ["t=0.000 s  p.mpf:1  WHEN $aa_iw[X] > 5 DO  X=0",
                                    "t=0.000 s  p.mpf:3  CANCEL  X=0",
                                    "t=0.000 s  p.mpf:4  G01 X10 F=50  X=0",
                                    "t=0.125 s  p.mpf:2  [WHEN p.mpf:1]  $aa_out[3] = 1  X=5",
                                    "t=0.250 s  p.mpf:5  M30  X=10"],
              f"the blocks, the WHEN body's named:\n{st.show(text)}")
    finally:
        term.close()


def case_pipe(d):
    """Without a terminal the commands come from the pipe, one block a line."""
    write(os.path.join(d, "p.mpf"), "G00 X10\nG00 X20\nG00 X0\nM30\n")
    write(os.path.join(d, "m.json"), machine_json())
    p = subprocess.run([st.tool("isosim"), "--single-block", "p.mpf", "--machine", "m.json"],
                       input=b"\nc\n", cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       timeout=30)
    out = p.stdout.decode()
    check(p.returncode == 0 and block_lines(out) == ["t=0.000 s  p.mpf:1  G00 X10  X=0",
                                                     "t=0.250 s  p.mpf:2  G00 X20  X=10"],
          f"two blocks then c\nexit {p.returncode}\n{out}\n{p.stderr.decode()}")
    check(re.search(r"^cycle_time_s: 0\.95 s \(0:01\.0\)$", out, re.M), f"the summary\n{out}")


# ----------------------------------------------------------------------------------------

CASES = {name[len("case_"):]: fn for name, fn in sorted(globals().items())
         if name.startswith("case_") and callable(fn)}


if __name__ == "__main__":
    sys.exit(st.main(CASES, "singleblock", __doc__))
