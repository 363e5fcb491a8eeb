#!/usr/bin/python3
"""check_man_isolint.py: keeps man/isolint.1 in step with isolint (STYLE habit 15).

Usage: check_man_isolint.py --man man/isolint.1 --help-golden tests/golden/help/isolint.txt
                            --diagnostics lib/diag/Diagnostics.def --tool path/to/isolint

Checks that
  1. every option that `isolint --help` prints (its golden) is documented in OPTIONS;
  2. every rule of Diagnostics.def (the SPEC section 7 table) has an entry in RULES,
     tagged `\\fBCODE\\fR \\fIname\\fR`, and RULES lists no other code;
  3. the example of each entry (the .EX/.EE block after its tag) triggers that rule when
     isolint checks it. An example is a main program `ex.mpf`, or `ex.spf` when it starts
     with PROC; a line `; NAME.mpf` or `; NAME.spf` starts a file of that name, for
     examples that need several files. Entries in NOT_RUNNABLE describe their example in
     words (it would be too long for a manual page) and are not run;
  4. `groff -man -ww -z` is silent on the page (when groff is installed).
Exit 0 when all holds, 1 otherwise.
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

NOT_RUNNABLE = {
    "E102": "a 241-character line",
    "E211": "a call chain 31 levels deep",
}
FILE_LINE = re.compile(r"^;\s*(\S+\.(?:mpf|spf|json))\s*$", re.IGNORECASE)
# "; isolint --dialect z32" in an example: the options to check it with
ARGS_LINE = re.compile(r"^;\s*isolint\s+(--.*?)\s*$")
TAG = re.compile(r"^\\fB([EWI][0-9]{3})\\fR \\fI(.*?)\\fR\s*$")


def unescape(s):
    """The text a reader sees for a line of an .EX block (the escapes used there)."""
    s = re.sub(r"\\\[u([0-9A-Fa-f]{4,6})\]", lambda m: chr(int(m.group(1), 16)), s)
    s = re.sub(r"\\f[BIRP]", "", s)
    for esc, ch in (("\\-", "-"), ("\\(aq", "'"), ("\\(en", "\u2013"), ("\\(->", "->"),
                    ("\\&", ""), ("\\e", "\\")):
        s = s.replace(esc, ch)
    return s


def section(lines, title):
    """Lines of the .SH section named title."""
    out, inside = [], False
    for line in lines:
        if line.startswith(".SH "):
            inside = line[4:].strip().strip('"') == title
            continue
        if inside:
            out.append(line)
    return out


def rule_entries(rules_lines):
    """{code: (name, example lines or None)} from the RULES section."""
    entries, order = {}, []
    cur, ex, in_ex = None, None, False
    for line in rules_lines + [".SS end"]:
        if in_ex:
            if line.startswith(".EE"):
                in_ex = False
            else:
                ex.append(unescape(line))
            continue
        if line.startswith((".TP", ".SS", ".SH")) and cur:
            entries[cur[0]] = (cur[1], ex)
            cur, ex = None, None
        m = TAG.match(line)
        if m:
            cur = (m.group(1), unescape(m.group(2)))
            order.append(m.group(1))
            continue
        if cur and line.startswith(".EX"):
            if ex is not None:
                raise SystemExit(f"{cur[0]}: more than one example")
            ex, in_ex = [], True
    return entries, order


def split_files(example):
    """[(file name, text)] of an example."""
    files, name, body = [], None, []
    for line in example:
        m = FILE_LINE.match(line)
        if m:
            if name or any(l.strip() for l in body):
                files.append((name, body))
            name, body = m.group(1), []
        else:
            body.append(line)
    files.append((name, body))
    out = []
    for name, body in files:
        if not name:
            first = next((l for l in body if l.strip() and not l.lstrip().startswith(";")), "")
            name = "ex.spf" if first.split()[:1] and first.split()[0].upper() == "PROC" else "ex.mpf"
        out.append((name, "\n".join(body) + "\n"))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--man", required=True)
    ap.add_argument("--help-golden", required=True)
    ap.add_argument("--diagnostics", required=True)
    ap.add_argument("--tool", required=True)
    a = ap.parse_args()
    a.tool = os.path.abspath(a.tool)
    fails = []

    with open(a.man, encoding="utf-8") as f:
        man = f.read().splitlines()

    # 1. options
    with open(a.help_golden, encoding="utf-8") as f:
        help_text = f.read()
    options_text = "\n".join(section(man, "OPTIONS"))
    opts = set(re.findall(r"(?<![\w-])(--[a-z][a-z-]*|-[a-z])\b", help_text))
    for opt in sorted(opts):
        if opt.replace("-", "\\-") not in options_text:
            fails.append(f"option {opt} (in --help) is not documented in OPTIONS")

    # 2. rules
    with open(a.diagnostics, encoding="utf-8") as f:
        table = re.findall(r'^DIAG\(\s*\w+\s*,\s*"([EWI][0-9]{3})"\s*,\s*"([^"]+)"', f.read(), re.M)
    if len(table) < 50:
        fails.append(f"only {len(table)} rules read from {a.diagnostics}")
    entries, order = rule_entries(section(man, "RULES"))
    for code, name in table:
        if code not in entries:
            fails.append(f"{code} {name}: no entry in RULES")
        elif entries[code][0] != name:
            fails.append(f"{code}: RULES calls it {entries[code][0]!r}, isolint {name!r}")
    extra = set(entries) - {c for c, _ in table}
    for code in sorted(extra):
        fails.append(f"{code}: in RULES but not a rule of isolint")
    if len(order) != len(set(order)):
        fails.append("a code is listed twice in RULES")

    # 3. examples
    ran = 0
    for code, (name, example) in sorted(entries.items()):
        if code in NOT_RUNNABLE:
            continue
        if not example:
            fails.append(f"{code} {name}: no example (.EX/.EE block)")
            continue
        args = []
        for line in example:
            m = ARGS_LINE.match(line)
            if m:
                args += m.group(1).split()
        with tempfile.TemporaryDirectory(prefix="isolint-man-") as d:
            for fname, text in split_files(example):
                with open(os.path.join(d, fname), "w", encoding="utf-8") as f:
                    f.write(text)
                if fname.lower().endswith(".json"):
                    args += ["--machine", fname]
            p = subprocess.run([a.tool, "--color", "never", "--format", "json"] + args + ["."],
                               cwd=d, capture_output=True, timeout=60)
        ran += 1
        try:
            got = [x["code"] for x in json.loads(p.stdout)["diagnostics"]]
        except (ValueError, KeyError):
            fails.append(f"{code} {name}: isolint exit {p.returncode}: "
                         f"{p.stderr.decode(errors='replace').strip()}")
            continue
        if code not in got:
            fails.append(f"{code} {name}: its example reports {sorted(set(got)) or 'nothing'}")
    # 4. groff warnings
    groff = shutil.which("groff")
    if groff:
        p = subprocess.run([groff, "-man", "-ww", "-z", a.man], capture_output=True, timeout=60)
        msg = (p.stdout + p.stderr).decode(errors="replace").strip()
        if p.returncode or msg:
            fails.append(f"groff -man -ww -z {a.man}: exit {p.returncode}\n{msg}")
    else:
        print("groff not found: the page's markup was not checked")

    print(f"{len(opts)} options, {len(table)} rules, {ran} examples run")
    for f in fails:
        print("FAIL " + f, file=sys.stderr)
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
