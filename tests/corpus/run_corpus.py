#!/usr/bin/python3
"""run_corpus.py: isolint must survive real programs written by others (../shared/corpus).

Usage: run_corpus.py --tool path/to/isolint --corpus DIR [--max-seconds 5]

Runs `isolint --color never --format json FILE` on every regular file under DIR (dot
files aside), one run per file, and checks for each run:
  - the exit code is 0 or 1 (never 2 for a readable file, 70 or a crash),
  - stdout is one valid JSON object with "diagnostics", "files", "errors", "warnings",
  - every diagnostic has "code", "line" and "column" (and a file, severity, name and
    message; line and column are integers >= 1); every note has a file, line, column,
  - the exit code is 1 exactly when "errors" > 0, and the counts match the diagnostics,
  - the run ends (a run still going after 6 x --max-seconds, at least 30 s, is a hang and
    fails; one slower than --max-seconds is only noted: speed is measured in bench/).
Exit 0 when every file passes, 1 otherwise, 77 (CTest SKIP_RETURN_CODE) when DIR does
not exist. Only the standard library is used.
"""
import argparse
import json
import os
import subprocess
import sys
import time

SKIP = 77
SEVERITIES = {"error", "warning", "info"}


def check_output(data, rc):
    """Returns a list of problems of one run's JSON output."""
    probs = []
    try:
        doc = json.loads(data)
    except ValueError as e:
        return [f"stdout is not valid JSON: {e}"]
    if not isinstance(doc, dict):
        return ["stdout is not a JSON object"]
    for key in ("diagnostics", "files", "errors", "warnings"):
        if key not in doc:
            probs.append(f"missing top-level key {key!r}")
    diags = doc.get("diagnostics", [])
    if not isinstance(diags, list):
        return probs + ["'diagnostics' is not a list"]
    count = {"error": 0, "warning": 0, "info": 0}
    for i, d in enumerate(diags):
        where = f"diagnostics[{i}]"
        for key in ("code", "line", "column", "file", "severity", "name", "message"):
            if key not in d:
                probs.append(f"{where}: missing {key!r}")
        for key in ("line", "column"):
            v = d.get(key)
            if key in d and not (isinstance(v, int) and v >= 1):
                probs.append(f"{where}: {key} is {v!r}, expected an integer >= 1")
        sev = d.get("severity")
        if sev in SEVERITIES:
            count[sev] += 1
        elif "severity" in d:
            probs.append(f"{where}: severity {sev!r}")
        for j, n in enumerate(d.get("notes", [])):
            for key in ("file", "line", "column", "message"):
                if key not in n:
                    probs.append(f"{where}.notes[{j}]: missing {key!r}")
    if doc.get("errors") != count["error"] or doc.get("warnings") != count["warning"]:
        probs.append(f"counts errors={doc.get('errors')} warnings={doc.get('warnings')} do not match "
                     f"the diagnostics ({count['error']} errors, {count['warning']} warnings)")
    if rc != (1 if count["error"] else 0):
        probs.append(f"exit code {rc} with {count['error']} error diagnostics")
    return probs


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tool", required=True)
    ap.add_argument("--corpus", required=True)
    ap.add_argument("--max-seconds", type=float, default=5.0)
    a = ap.parse_args()

    if not os.path.isdir(a.corpus):
        print(f"SKIP: no corpus at {a.corpus}")
        return SKIP

    files = []
    for root, dirs, names in os.walk(a.corpus):
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))
        files += [os.path.join(root, n) for n in sorted(names) if not n.startswith(".")]
    if not files:
        print(f"SKIP: the corpus {a.corpus} holds no files")
        return SKIP

    failures = 0
    slowest = (0.0, "")
    for path in files:
        rel = os.path.relpath(path, a.corpus)
        cmd = [a.tool, "--color", "never", "--format", "json", path]
        start = time.monotonic()
        try:
            # A hang is cut off well after the limit, so that it is reported, not waited for.
            p = subprocess.run(cmd, capture_output=True, timeout=max(30.0, 6 * a.max_seconds))
        except subprocess.TimeoutExpired:
            print(f"FAIL {rel}: still running after {max(30.0, 6 * a.max_seconds):.0f} s (killed)")
            failures += 1
            continue
        took = time.monotonic() - start
        slowest = max(slowest, (took, rel))
        probs = []
        if p.returncode not in (0, 1):
            err = p.stderr.decode("utf-8", "replace").strip()
            probs.append(f"exit code {p.returncode} (expected 0 or 1): {err}")
        else:
            probs += check_output(p.stdout, p.returncode)
        if took > a.max_seconds:
            # speed is measured in bench/, not asserted here: a slow run on a busy machine is
            # reported; only a hang (the timeout above) fails
            print(f"note {rel}: took {took:.2f} s (more than {a.max_seconds:g} s)")
        if probs:
            failures += 1
            print(f"FAIL {rel}")
            for pr in probs[:20]:
                print(f"     {pr}")
            if len(probs) > 20:
                print(f"     ... and {len(probs) - 20} more")
        else:
            print(f"ok   {rel} (exit {p.returncode}, {took:.2f} s)")

    print(f"{len(files)} files, {failures} failed; slowest {slowest[1]} in {slowest[0]:.2f} s")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
