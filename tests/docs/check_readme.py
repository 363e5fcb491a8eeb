#!/usr/bin/env python3
"""README.md shows real output of real commands: this reruns every example whose output the
README quotes and compares it line by line.

- A fenced block whose first line is `$ COMMAND` holds COMMAND's output (stdout, then
  stderr). A last line `trace: FILE (N rows)` is what .ci/demo adds: FILE must have N lines.
  Commands run in a scratch folder holding `samples` (a link to the project's), `build/` and
  the files of tests/docs/readme/ (the `mill.json`, `w415.mpf`, `cambio.mpf` and `sweep.toml`
  the README names).
- A `$ isosim --single-block ...` block runs on a terminal (a pty): after each prompt (a block
  line ending in `  >`) the command written after it is typed (nothing: Enter).
- The block after "The trace loads with" is the head of the demo's trace.
- <!-- lint-output -->: `isolint diagnostics.mpf` in tests/golden/isolint.
- <!-- disasm-output -->: the head of `isocc --disasm` of samples/drilling_when.
- The `--profile` excerpt: each line but `...` occurs in the real output, in order.

Usage: check_readme.py PROJECT_DIR TOOLS_DIR
"""
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

TOOLS = ("isolint", "isocc", "isosim", "isofmt")


def blocks(text):
    """(line index of the opening fence, the block's lines) for each fenced block."""
    lines = text.split("\n")
    out, i = [], 0
    while i < len(lines):
        if lines[i].startswith("```"):
            j = i + 1
            while j < len(lines) and not lines[j].startswith("```"):
                j += 1
            out.append((i, lines[i + 1:j]))
            i = j + 1
        else:
            i += 1
    return lines, out


def run(tools, argv, cwd):
    if argv[0] in TOOLS:
        argv = [os.path.join(tools, argv[0])] + argv[1:]
    p = subprocess.run(argv, cwd=cwd, capture_output=True, timeout=120)
    return p.returncode, (p.stdout + p.stderr).decode("utf-8", "replace").splitlines()


def run_terminal(tools, argv, cwd, commands):
    """argv on a terminal (a pty): each of `commands` typed once the program shows its prompt."""
    import pty
    import select
    master, slave = pty.openpty()
    p = subprocess.Popen([os.path.join(tools, argv[0])] + argv[1:], cwd=cwd, stdin=slave, stdout=slave,
                         stderr=slave, close_fds=True)
    os.close(slave)
    out, sent, sent_at, deadline = b"", 0, -1, time.monotonic() + 120
    while time.monotonic() < deadline:
        if sent < len(commands) and out.endswith(b"  > ") and len(out) > sent_at:
            os.write(master, commands[sent].encode() + b"\n")
            sent, sent_at = sent + 1, len(out)
        if not select.select([master], [], [], 0.2)[0]:
            continue
        try:
            chunk = os.read(master, 65536)
        except OSError:  # EIO: the program ended and closed the terminal
            break
        if not chunk:
            break
        out += chunk
    else:
        p.kill()
    p.wait()
    os.close(master)
    text = out.decode("utf-8", "replace").replace("\r\n", "\n")
    return p.returncode, [line.rstrip() for line in text.splitlines()]


class Check:
    def __init__(self):
        self.failures, self.count = [], 0

    def same(self, what, expected, actual):
        self.count += 1
        if expected != actual:
            diff = [f"  line {k + 1}: README {e!r}\n  {' ' * len(str(k + 1))}       real   {a!r}"
                    for k, (e, a) in enumerate(zip(expected + [None] * len(actual), actual + [None] * len(expected)))
                    if e != a][:3]
            self.failures.append(f"{what}: the README's output differs from the real one\n" + "\n".join(diff))


def check_commands(chk, lines, fenced, project, tools, scratch):
    for _, body in fenced:
        if not body or not body[0].startswith("$ "):
            continue
        argv = shlex.split(body[0][2:])
        expected = list(body[1:])
        trace = None
        if expected and (m := re.fullmatch(r"trace: (\S+) \((\d+) rows\)", expected[-1])):
            trace = (m.group(1), int(m.group(2)))
            expected.pop()
        if "--single-block" in argv:
            commands = [m.group(1) or "" for line in expected if (m := re.fullmatch(r"t=.*  >(?: (.*))?", line))]
            _, actual = run_terminal(tools, argv, scratch, commands)
        else:
            _, actual = run(tools, argv, scratch)
        chk.same(body[0], expected, actual)
        if trace:
            path = os.path.join(scratch, trace[0])
            rows = sum(1 for _ in open(path, "rb")) if os.path.exists(path) else -1
            chk.same(body[0] + " (rows of the trace)", [str(trace[1])], [str(rows)])


def block_after(lines, fenced, marker):
    """The first fenced block after the first line containing `marker`."""
    at = next((i for i, line in enumerate(lines) if marker in line), None)
    if at is None:
        return None
    return next((body for start, body in fenced if start > at), None)


def main():
    project, tools = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    text = open(os.path.join(project, "README.md"), encoding="utf-8").read()
    lines, fenced = blocks(text)
    chk = Check()
    with tempfile.TemporaryDirectory() as scratch:
        os.symlink(os.path.join(project, "samples"), os.path.join(scratch, "samples"))
        os.mkdir(os.path.join(scratch, "build"))
        fixtures = os.path.join(project, "tests", "docs", "readme")
        for name in os.listdir(fixtures):
            shutil.copy(os.path.join(fixtures, name), scratch)
        check_commands(chk, lines, fenced, project, tools, scratch)

        head = block_after(lines, fenced, "The trace loads with")
        demo_trace = os.path.join(scratch, "build", "foratura_piastra.csv")
        if head is None or not os.path.exists(demo_trace):
            chk.failures.append("the demo's trace or its quoted head is missing")
        else:
            real = open(demo_trace, encoding="utf-8").read().splitlines()[:len(head)]
            chk.same("the head of the demo's trace", head, real)

        lint = block_after(lines, fenced, "<!-- lint-output -->")
        _, actual = run(tools, ["isolint", "diagnostics.mpf"], os.path.join(project, "tests", "golden", "isolint"))
        chk.same("<!-- lint-output --> (isolint diagnostics.mpf)", lint or [], actual)

        disasm = block_after(lines, fenced, "<!-- disasm-output -->") or []
        image = os.path.join(scratch, "build", "foratura.isob")
        run(tools, ["isocc", "samples/drilling_when/", "-o", image], scratch)
        _, actual = run(tools, ["isocc", "--disasm", image], scratch)
        chk.same("<!-- disasm-output --> (isocc --disasm)", disasm, actual[:len(disasm)])

        profile = block_after(lines, fenced, "isosim samples/contour_g64/taglio_piastra.mpf --profile") or []
        _, actual = run(tools, ["isosim", "samples/contour_g64/taglio_piastra.mpf", "--profile"], scratch)
        chk.count += 1
        at = 0
        for want in profile:
            if want == "...":
                continue
            while at < len(actual) and actual[at] != want:
                at += 1
            if at == len(actual):
                chk.failures.append(f"--profile excerpt: the line {want!r} is not in the real output (in this order)")
                break
    if chk.count < 7:
        chk.failures.append(f"only {chk.count} examples found in README.md: a marker or a `$ ` block was lost")
    for f in chk.failures:
        print(f)
    print(f"{chk.count} README examples checked, {len(chk.failures)} differ")
    return 1 if chk.failures else 0


if __name__ == "__main__":
    sys.exit(main())
