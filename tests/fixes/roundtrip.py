#!/usr/bin/env python3
"""fixes/roundtrip: isolint --fix on a copy of tests/fixes/ (every fixable diagnostic, LF and
CR LF files, Latin-1 comments).

Checks that
  - --diff changes nothing and its exit status is that of a plain run;
  - --fix removes every diagnostic that had a fix, and the others stay;
  - the fixed files are exactly the originals with the JSON edits applied (so every other
    byte, the line ends and the encoding are kept), also for the fixes of later passes;
  - a file without a fix is not written (same inode and mtime);
  - a second --fix changes nothing (byte-identical) and says 'fixed 0 problems in 0 files';
  - --fix with --stdin-filename prints the fixed text and writes nothing.

usage: roundtrip.py --tool ISOLINT --corpus DIR
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def run(tool, args, cwd, stdin=None):
    return subprocess.run([tool, "--color", "never"] + args, cwd=cwd, input=stdin, capture_output=True)


def lint_json(tool, cwd):
    r = run(tool, ["--format", "json", "."], cwd)
    return r.returncode, json.loads(r.stdout)


def apply(text, diags):
    """Applies the first fix of each diagnostic (no two overlap in the corpus)."""
    lines = text.split(b"\n")
    starts = [0]
    for line in lines[:-1]:
        starts.append(starts[-1] + len(line) + 1)
    edits = []
    for d in diags:
        for e in d.get("fixes", [{}])[0].get("edits", []):
            b = starts[e["line"] - 1] + e["column"] - 1
            end = starts[e["end_line"] - 1] + e["end_column"] - 1
            edits.append((b, end, e["replacement"].encode("utf-8")))
    edits.sort()
    out, at = b"", 0
    for b, end, rep in edits:
        out += text[at:b] + rep
        at = end
    return out + text[at:]


def snapshot(d):
    return {n: open(os.path.join(d, n), "rb").read() for n in sorted(os.listdir(d)) if n.endswith((".mpf", ".spf"))}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tool", required=True)
    ap.add_argument("--corpus", required=True)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="isotools-fixes-") as tmp:
        for n in os.listdir(a.corpus):
            if n.endswith((".mpf", ".spf")):
                shutil.copy(os.path.join(a.corpus, n), tmp)
        before = snapshot(tmp)
        check(any(b"\r\n" in t for t in before.values()) and any(b"\r\n" not in t for t in before.values()),
              "the corpus has CR LF and LF files")
        plain = run(a.tool, ["."], tmp)
        rc0, doc0 = lint_json(a.tool, tmp)
        fixable = [d for d in doc0["diagnostics"] if "fixes" in d]
        check(len({d["code"] for d in fixable}) >= 5, "the corpus has every kind of fix (E100, E101, E108, E110, W407)")

        diff = run(a.tool, ["--diff", "."], tmp)
        check(diff.returncode == plain.returncode, "--diff exits as a plain run")
        check(diff.stdout.startswith(b"--- a/"), "--diff prints a unified diff")
        check(snapshot(tmp) == before, "--diff changes nothing")

        # A file of the set without any fix must not be written.
        clean = os.path.join(tmp, "clean.spf")
        with open(clean, "wb") as f:
            f.write(b"PROC Clean SAVE\r\nM17\r\n")
        st = os.stat(clean)

        fix = run(a.tool, ["--fix", "."], tmp)
        after = snapshot(tmp)
        check(os.stat(clean).st_ino == st.st_ino and os.stat(clean).st_mtime_ns == st.st_mtime_ns,
              "a file without a fix is not written")
        rc1, doc1 = lint_json(a.tool, tmp)
        check(fix.returncode == rc1, "--fix exits with the status of what remains")
        check(not any("fixes" in d for d in doc1["diagnostics"]), "no fixable diagnostic remains")
        left = sorted((d["file"], d["code"]) for d in doc1["diagnostics"])
        # those that no fix can remove: IF R1 (bare value), 1000000000, STOPRE
        want = [("main.mpf", "E108"), ("main.mpf", "E101"), ("sub.spf", "E110")]
        check(all(w in left for w in want), f"the diagnostics without a fix are still there: {left}")
        check(b"isolint: fixed " in fix.stderr, "--fix says what it fixed on standard error")

        # Every byte outside the edits is kept: replay the edits of each pass from the JSON.
        cur = dict(before)
        cur.pop("clean.spf", None)
        doc = doc0
        for _ in range(10):
            files = {}
            for d in doc["diagnostics"]:
                if "fixes" in d:
                    files.setdefault(d["file"].lstrip("./"), []).append(d)
            if not files:
                break
            for name, ds in files.items():
                cur[name] = apply(cur[name], ds)
            with tempfile.TemporaryDirectory(prefix="isotools-fixes-replay-") as t2:
                for n, text in cur.items():
                    open(os.path.join(t2, n), "wb").write(text)
                _, doc = lint_json(a.tool, t2)
        for n in cur:
            check(after[n] == cur[n], f"{n}: the fixed bytes are the original ones with the edits applied")
        for n, text in before.items():
            crlf = text.count(b"\r\n")
            check(after[n].count(b"\r\n") == crlf and after[n].count(b"\n") == text.count(b"\n"),
                  f"{n}: line ends kept")
            check((b"\xe8" in text) == (b"\xe8" in after[n]), f"{n}: Latin-1 bytes kept")

        again = run(a.tool, ["--fix", "."], tmp)
        check(snapshot(tmp) == after, "a second --fix changes nothing")
        check(b"fixed 0 problems in 0 files" in again.stderr, "a second --fix fixes nothing")

        # Standard input: the fixed text on standard output, nothing written.
        name = "main.mpf"
        open(os.path.join(tmp, name), "wb").write(before[name])
        st = run(a.tool, ["--fix", "--stdin-filename", name, "-"], tmp, stdin=before[name])
        check(st.stdout == after[name], "--fix --stdin-filename prints the fixed text")
        check(open(os.path.join(tmp, name), "rb").read() == before[name], "--fix --stdin-filename writes no file")
    if failures:
        print(f"{len(failures)} check(s) failed", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
