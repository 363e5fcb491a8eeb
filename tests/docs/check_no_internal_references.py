#!/usr/bin/env python3
"""What users read must stand on its own: the man pages, the READMEs meant for users, the JSON
Schemas (descriptions and $id), the VS Code extension's manifest and the --help (and shell
completion) output of every tool may not point at documents users do not have, nor at a
link that leads nowhere. Each finding is printed as FILE:LINE: the text.

Refused:
- the project's internal specification: `SPEC` (as a word) and the section sign of its
  numbers (`§`, roff `\\(sc` or `\\[sc]`); "section 6.2" of the SIDAC manual, which users
  have, and the sections of an image (isoimage(5)) are fine;
- the tracker and the way the work was organised: "issue #14", "issues/14", "PR #3",
  "session 10", "earlier sessions";
- the reserved, dead host `isotools.invalid`.

Usage: check_no_internal_references.py PROJECT_DIR TOOLS_DIR
"""
import glob
import os
import re
import subprocess
import sys

TOOLS = ("isolint", "isocc", "isosim", "isofmt")

# The READMEs for users (tests/, lib/ and the fuzz ledger are for the project's developers).
USER_FILES = ("README.md", "editors/vscode/README.md", "editors/vscode/package.json",
              "schemas/README.md", "samples/README.md")
USER_GLOBS = ("man/*.[1-9]", "schemas/*.json")

PATTERNS = [
    (re.compile(r"\bSPEC\b"), "the internal specification"),
    (re.compile(r"§|\\\(sc|\\\[sc\]"), "a section sign"),
    (re.compile(r"\b(issue|issues|pr|pull request)\s*(#|/)\s*\d+", re.I), "an issue number"),
    (re.compile(r"\bsessions?\s+\d+|\b(earlier|previous|this|last) sessions?\b", re.I),
     "how the work was organised"),
    (re.compile(r"isotools\.invalid", re.I), "a dead link"),
]


def scan(name, text, failures):
    for n, line in enumerate(text.splitlines(), 1):
        for rx, what in PATTERNS:
            if rx.search(line):
                failures.append(f"{name}:{n}: {what}: {line.strip()}")


def tool_outputs(tools_dir):
    """(name, text) of `TOOL --help` and `TOOL --completion fish` (its descriptions)."""
    for tool in TOOLS:
        exe = os.path.join(tools_dir, tool)
        for args in (["--help"], ["--completion", "fish"]):
            p = subprocess.run([exe] + args, capture_output=True, timeout=60)
            text = (p.stdout + p.stderr).decode("utf-8", "replace")
            yield f"`{tool} {' '.join(args)}`", p.returncode, text


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    project, tools_dir = sys.argv[1], sys.argv[2]
    failures, checked = [], []
    paths = [os.path.join(project, f) for f in USER_FILES]
    for g in USER_GLOBS:
        found = sorted(glob.glob(os.path.join(project, g)))
        if not found:
            failures.append(f"{g}: no file matches (the check would be empty)")
        paths += found
    for path in paths:
        rel = os.path.relpath(path, project)
        if not os.path.isfile(path):
            failures.append(f"{rel}: missing (update the list of files users read)")
            continue
        with open(path, encoding="utf-8") as f:
            scan(rel, f.read(), failures)
        checked.append(rel)
    for name, rc, text in tool_outputs(tools_dir):
        if rc != 0 or len(text) < 100:
            failures.append(f"{name}: exit {rc}, {len(text)} bytes of output")
        scan(name, text, failures)
        checked.append(name)
    for f in failures:
        print(f)
    print(f"{len(checked)} documents and outputs checked, {len(failures)} findings")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
