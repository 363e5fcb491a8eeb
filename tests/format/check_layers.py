#!/usr/bin/python3
"""check_layers.py SOURCE_DIR: every #include "area/..." in lib/<area>/ names an area that
lib/README.md lets <area> include (its "may include:" line), and the README maps every file: each
source of lib/<area>/ (by name without its extension, with its subfolder) is listed once on the
area's "files:" line, and every name listed there is a file. Exit 1 on any other include, a file
left out or listed twice, a name that is no file, an area of lib/ without these lines, or a
header that declares a `std::string& why` out-argument (the error rule of lib/README.md)."""
import os
import re
import sys


def main():
    src = sys.argv[1]
    lib = os.path.join(src, "lib")
    with open(os.path.join(lib, "README.md"), encoding="utf-8") as f:
        text = f.read()
    allowed, listed, area = {}, {}, None
    for line in text.splitlines():
        m = re.match(r"^## (\w+)\s*$", line)
        if m:
            area = m.group(1)
        m = re.match(r"^files:\s*(.*)$", line)
        if m and area:  # "files: Name — what; Name — what."
            listed[area] = [part.split(" — ")[0].strip() for part in m.group(1).rstrip(".").split("; ")]
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
        stems = {os.path.splitext(n)[0] for n in names}
        mapped = listed.get(a, [])
        for n in sorted(stems - set(mapped)):
            fails.append(f"lib/{a}/{n}: not on the 'files:' line of '## {a}' in lib/README.md")
        for n in sorted(set(mapped) - stems):
            fails.append(f"lib/README.md '## {a}' lists {n}, which is no file of lib/{a}")
        for n in sorted({n for n in mapped if mapped.count(n) > 1}):
            fails.append(f"lib/README.md '## {a}' lists {n} more than once")
        for fn in names:  # an area's subfolders (frontend/checks) belong to it
            if not fn.endswith((".h", ".cpp", ".def")):
                continue
            with open(os.path.join(d, fn), encoding="utf-8", errors="replace") as f:
                for no, line in enumerate(f, 1):
                    if fn.endswith(".h") and re.search(r"std::string\s*[&*]\s*why\b(?!\s*\()", line):
                        fails.append(f"lib/{a}/{fn}:{no}: a reason out-argument in a header (return "
                                     "support::Expected, support::Status or a result type)")
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
