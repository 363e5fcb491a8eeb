#!/usr/bin/env python3
"""The README's cycle-time gate for pull requests, run as a CI runner would run it.

The yaml block after "A cycle-time gate for pull requests" is read from README.md; its `run:`
lines are run by sh in a clone of a small git repository whose base branch holds
parts/flange.mpf, with ${{ github.base_ref }} replaced by the branch name and the built isosim
first on PATH. A pull request that makes the program 10 % slower must fail the step (exit 1)
with a GitHub annotation on the grown line; one that makes it faster must pass (exit 0).

Usage: check_readme_gate.py SOURCE_DIR TOOLS_DIR (TOOLS_DIR holds the built isosim).
Exit status: 0 pass, 1 fail, 77 skip (no git).
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

BASE = "G90 G60\nG01 X100 F=50\nG01 Y50\nM30\n"
SLOWER = "G90 G60\nG01 X100 F=45\nG01 Y50\nM30\n"  # 2.025 s -> 2.2472 s on the first line
FASTER = "G90 G60\nG01 X100 F=60\nG01 Y50\nM30\n"


def fail(msg):
    print("FAIL docs/readme-gate: " + msg, file=sys.stderr)
    sys.exit(1)


def snippet(readme):
    text = open(readme, encoding="utf-8").read()
    at = text.find("A cycle-time gate for pull requests")
    if at < 0:
        fail("README.md has no cycle-time gate")
    block = re.search(r"```yaml\n(.*?)```", text[at:], re.S)
    if not block:
        fail("no yaml block after the cycle-time gate")
    runs = [m.group(1) for m in re.finditer(r"^- run: (.*)$", block.group(1), re.M)]
    if len(runs) < 2:
        fail("the gate's yaml block has no run: steps: %r" % block.group(1))
    return runs


def git(cwd, *args):
    subprocess.run(["git", "-c", "user.name=ci", "-c", "user.email=ci@example.invalid"] + list(args), cwd=cwd,
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def pull_request(work, name, text, runs, tools):
    """Clones the repository, commits `text` as the pull request, runs the steps: (rc, output)."""
    clone = os.path.join(work, name)
    git(work, "clone", "-q", os.path.join(work, "origin.git"), clone)
    with open(os.path.join(clone, "parts", "flange.mpf"), "w") as f:
        f.write(text)
    git(clone, "commit", "-qam", "the change")
    env = dict(os.environ, PATH=tools + os.pathsep + os.environ.get("PATH", ""))
    out, rc = "", 0
    for run in runs:
        cmd = run.replace("${{ github.base_ref }}", "main").replace("/tmp/base", os.path.join(work, name + "-base"))
        p = subprocess.run(["sh", "-c", cmd], cwd=clone, env=env, capture_output=True, text=True)
        out += p.stdout + p.stderr
        rc = p.returncode
        if rc != 0:
            break
    return rc, out


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    source, tools = sys.argv[1], os.path.abspath(sys.argv[2])
    if not shutil.which("git"):
        print("skipped: git is not installed")
        return 77
    runs = snippet(os.path.join(source, "README.md"))
    with tempfile.TemporaryDirectory() as work:
        repo = os.path.join(work, "repo")
        os.makedirs(os.path.join(repo, "parts"))
        with open(os.path.join(repo, "parts", "flange.mpf"), "w") as f:
            f.write(BASE)
        git(repo, "init", "-q", "-b", "main")
        git(repo, "add", ".")
        git(repo, "commit", "-qm", "base")
        git(work, "clone", "-q", "--bare", repo, os.path.join(work, "origin.git"))
        rc, out = pull_request(work, "slower", SLOWER, runs, tools)
        if rc != 1:
            fail("a 10%% slower program: exit %d, expected 1:\n%s" % (rc, out))
        if not re.search(r"^::(warning|error) file=parts/flange\.mpf,line=2\b", out, re.M):
            fail("no annotation on parts/flange.mpf line 2:\n%s" % out)
        rc, out = pull_request(work, "faster", FASTER, runs, tools)
        if rc != 0:
            fail("a faster program: exit %d, expected 0:\n%s" % (rc, out))
    print("ok docs/readme-gate")
    return 0


if __name__ == "__main__":
    sys.exit(main())
