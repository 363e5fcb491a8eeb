#!/usr/bin/python3
"""check_function_length.py SOURCE_DIR [--max N]: no function in lib/ is longer than N lines
(default 120, issue #10): long functions are split into named steps.

A function is a definition whose header ends a line with `{` (its parameter list closed, not a
control statement, not a lambda) outside any other function; its length is the number of lines
from the header to the matching `}`. Braces in strings, characters and comments are ignored.
Prints every function over the limit (file:line name length); exit 1 if there is one."""
import argparse
import os
import re
import sys

CONTROL = re.compile(r"^\s*(\}\s*)?(if|for|while|switch|catch|else|do|try)\b")
HEADER_END = re.compile(r"\)\s*(const)?\s*(override)?\s*(noexcept)?\s*(->\s*[\w:<>&*, ]+)?\s*\{\s*$")


def strip_code(text):
    """The text with comments, strings and character literals blanked (lines kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = text.find(")" + m.group(1) + '"', i)
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(" " * (min(j + 1, n) - i))
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        lines = strip_code(f.read()).split("\n")
    depth, inside, start, name, fdepth = 0, False, 0, "", 0
    for no, line in enumerate(lines, 1):
        if not inside and HEADER_END.search(line) and not CONTROL.match(line) and "](" not in line \
                and "[&" not in line and "[=" not in line and "[this" not in line:
            m = re.search(r"([~\w:]+)\s*\(", line)
            header = m.group(1) if m else line.strip()
            if header not in ("if", "for", "while", "switch", "catch"):
                inside, start, name, fdepth = True, no, header, depth
        depth += line.count("{") - line.count("}")
        if inside and depth <= fdepth:
            yield start, name, no - start + 1
            inside = False


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("source")
    ap.add_argument("--max", type=int, default=120)
    a = ap.parse_args()
    bad = 0
    count = 0
    for root, _, files in os.walk(os.path.join(a.source, "lib")):
        for fn in sorted(files):
            if not fn.endswith((".cpp", ".h")):
                continue
            p = os.path.join(root, fn)
            for line, name, length in functions(p):
                count += 1
                if length > a.max:
                    bad += 1
                    print(f"{os.path.relpath(p, a.source)}:{line}: {name} is {length} lines (limit {a.max})")
    print(f"{count} functions in lib/, {bad} over {a.max} lines")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
