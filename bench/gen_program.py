#!/usr/bin/env python3
"""Generates a large, valid SIDAC main program for benchmarks.

Usage: gen_program.py LINES OUT.mpf [--kind lint|motion]
  lint:   a mix of SIDAC blocks (Pos/Posa/Fa, R arithmetic, IF/ELSE, labels and jumps, WHEN)
          and classic word-address blocks (N12 G01 X10.5 Y-3 F200).
  motion: only short G01/G00 motion blocks (for isosim blocks-per-second).
Deterministic: the same arguments give the same file.
"""
import random
import sys


def main():
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    n = int(sys.argv[1])
    out = sys.argv[2]
    kind = sys.argv[4] if len(sys.argv) > 4 and sys.argv[3] == "--kind" else "lint"
    rnd = random.Random(42)
    lines = ["; generated benchmark program", "G90 G60", "F=250", "R1 = 0"]
    i = 0
    nnum = 10
    while len(lines) < n - 2:
        i += 1
        if kind == "motion":
            x = rnd.randint(0, 4000) / 10
            y = rnd.randint(0, 4000) / 10
            lines.append(f"G01 X{x} Y{y}" if i % 2 else f"X{x}")
            continue
        r = i % 8
        if r == 0:
            lines.append(f"N{nnum} G01 X{rnd.randint(0, 9000) / 10} Y-{rnd.randint(0, 900) / 10} F200")
            nnum += 1
        elif r == 1:
            lines.append(f"G01 Pos[X] = R1 + {rnd.randint(1, 99)} Pos[Y] = {rnd.randint(0, 500)}.5 F = 120")
        elif r == 2:
            lines.append(f"R{rnd.randint(2, 2000)} = R1 * 2 + {rnd.randint(1, 9)}.25 / 3  ; arithmetic")
        elif r == 3:
            lines.append(f"IF (R1 > {rnd.randint(0, 50)}) AND ($aa_in[{rnd.randint(0, 20)}] == 1)")
            lines.append(f"  G01 Posa[Z] = {rnd.randint(0, 300)} Fa[Z] = 50")
            lines.append("ELSE")
            lines.append(f"  M{rnd.choice([10, 23, 34, 45, 51, 62, 77, 88])}")
            lines.append("ENDIF")
        elif r == 4:
            lines.append(f"L{i}: G01 A{rnd.randint(0, 90)} B{rnd.randint(0, 90)} C10 U5 F100 (five axes)")
            lines.append(f"IF R1 > 1000 GOTOB L{i}")
        elif r == 5:
            lines.append(f"WHEN $aa_iw[X] > {rnd.randint(10, 200)} DO $aa_out[{rnd.randint(0, 50)}] = 1")
            lines.append(f"G01 X{rnd.randint(300, 900)} F300")
        elif r == 6:
            lines.append(f"N{nnum}G0X{rnd.randint(0, 100)}Y{rnd.randint(0, 100)}Z5")
            nnum += 1
        else:
            lines.append(f"G04 F0.{rnd.randint(1, 9)}")
    lines.append("M30")
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
