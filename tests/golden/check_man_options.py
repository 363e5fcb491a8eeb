#!/usr/bin/env python3
"""Keeps a man page in step with --help: every option that the --help golden lists must be
documented in the man page, and the page must be clean under `groff -man -ww -z`.

Usage: check_man_options.py MAN_PAGE HELP_GOLDEN
"""
import re
import subprocess
import sys


def main():
    man_path, help_path = sys.argv[1], sys.argv[2]
    man = open(man_path, encoding="utf-8").read()
    # roff escapes: \- is a minus; \f[BIR] font changes; \& zero-width
    plain = re.sub(r"\\f[BIRP]|\\&|\\\(em", "", man).replace("\\-", "-")
    helptext = open(help_path, encoding="utf-8").read()
    options = sorted(set(re.findall(r"(?<![\w-])(--[a-z][a-z0-9-]*|-[a-zA-Z])(?=[\s,=]|$)", helptext)))
    missing = [o for o in options if o not in plain]
    problems = []
    if missing:
        problems.append(f"{man_path}: options in --help but not in the man page: {', '.join(missing)}")
    r = subprocess.run(["groff", "-man", "-ww", "-z", man_path], capture_output=True, text=True)
    if r.returncode != 0 or r.stderr.strip():
        problems.append(f"groff -man -ww -z {man_path}:\n{r.stderr}")
    if problems:
        print("\n".join(problems))
        return 1
    print(f"{man_path}: {len(options)} options documented, groff clean")
    return 0


if __name__ == "__main__":
    sys.exit(main())
