#!/usr/bin/python3
"""check_layers.py SOURCE_DIR: every #include "area/..." in lib/<area>/ names an area that
lib/README.md lets <area> include (its "may include:" line). Exit 1 on any other include, or
when an area of lib/ has no such line (the README must describe every area)."""
import os
import re
import sys


def main():
    src = sys.argv[1]
    lib = os.path.join(src, "lib")
    with open(os.path.join(lib, "README.md"), encoding="utf-8") as f:
        text = f.read()
    allowed, area = {}, None
    for line in text.splitlines():
        m = re.match(r"^## (\w+)\s*$", line)
        if m:
            area = m.group(1)
        m = re.match(r"^may include:\s*(.*)$", line)
        if m and area:
            allowed[area] = {a.strip() for a in m.group(1).split(",") if a.strip()}
    fails, checked = [], 0
    for a in sorted(os.listdir(lib)):
        d = os.path.join(lib, a)
        if not os.path.isdir(d):
            continue
        if a not in allowed:
            fails.append(f"lib/{a}: no '## {a}' section with a 'may include:' line in lib/README.md")
            continue
        names = sorted(os.path.relpath(os.path.join(r, n), d) for r, _, ns in os.walk(d) for n in ns)
        for fn in names:  # an area's subfolders (frontend/checks) belong to it
            if not fn.endswith((".h", ".cpp", ".def")):
                continue
            with open(os.path.join(d, fn), encoding="utf-8", errors="replace") as f:
                for no, line in enumerate(f, 1):
                    m = re.match(r'^\s*#\s*include\s+"(\w+)/', line)
                    if not m:
                        continue
                    checked += 1
                    if m.group(1) not in allowed[a]:
                        fails.append(f"lib/{a}/{fn}:{no}: includes {m.group(1)}/, which lib/README.md does not "
                                     f"allow for {a} (may include: {', '.join(sorted(allowed[a]))})")
    for f in fails:
        print("FAIL", f)
    print(f"{checked} includes in {len(allowed)} areas checked, {len(fails)} failures")
    return 1 if fails or checked == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
