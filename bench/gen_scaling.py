#!/usr/bin/env python3
"""Generates the inputs of bench/scaling.sh: one shape that hurts editors and linters, at size N.

Usage: gen_scaling.py SHAPE N OUTDIR      (prints the path to give isolint)
       gen_scaling.py --list              (the shapes, one a line)

N counts lines (one-file shapes) or files/subprograms (set shapes); see SHAPES.
Deterministic: the same arguments give the same files.
"""
import os
import sys


def labels(n, w):
    # forward and backward jumps over n lines: labels, GOTOF, conditional GOTOB loops
    w("R1 = 0")
    k = 0
    while k < n // 4:
        w(f"GOTOF F{k}")
        w(f"B{k}: R1 = R1 + 1")
        w(f"F{k}: IF R1 < 0 GOTOB B{k}")
        w(f"G01 X{k % 500} F100")
        k += 1
    w("M30")


def nested_if(n, w):
    # IF nested n/2 deep, then closed
    d = n // 2
    for i in range(d):
        w(f"IF R{1 + i % 100} > {i % 7}")
    w("G01 X1 F100")
    for _ in range(d):
        w("ENDIF")
    w("M30")


def when(n, w):
    # n/4 anticipations, long and short forms, each with its trigger
    for i in range(n // 4):
        if i % 2:
            w(f"WHEN $aa_iw[X] > {i % 400} DO $aa_out[{i % 50}] = 1")
        else:
            w(f"WHEN $aa_iw[X] > {i % 400} DO")
            w(f"$aa_marker[{i % 200}] = 1")
            w("CANCEL")
        w(f"G01 X{(i % 2) * 500} F300")
    w("M30")


def continuation(n, w):
    # `$` continuation chains: every logical line is joined from 10 physical lines (within
    # the 240-character limit), then one chain of n/10 lines that exceeds it (E102)
    for i in range(n // 20):
        w("G01 $")
        for j in range(8):
            w(f"{'XYZABCUV'[j]}{j}$ ignored tail {i}")
        w(" F100")
    w("R1 = 1 $")
    for i in range(n // 2):
        w(f"+ 1 $ tail {i}")
    w(" ")
    w("M30")


def comments(n, w):
    # comment lines of every kind and blocks with inline comments
    for i in range(n):
        r = i % 4
        if r == 0:
            w(f"; commento {i} con accenti \u00e8 e $ dollari")
        elif r == 1:
            w(f"( comment line {i} )")
        elif r == 2:
            w(f"G01 X{i % 300} (inline {i}) F100 ; and a tail")
        else:
            w(f"R{1 + i % 100} = {i % 9} ; isolint: disable=W406")
    w("M30")


def case_arms(n, w):
    # CASE statements with 8 arms each, and their targets
    k = 0
    while k * 10 < n:
        arms = " ".join(f"{a} GOTOF C{k}_{a}" for a in range(8))
        w(f"CASE R1 OF {arms} DEFAULT GOTOF C{k}_d")
        for a in range(8):
            w(f"C{k}_{a}:")
        w(f"C{k}_d: R1 = R1 + 1")
        k += 1
    w("M30")


def many_diagnostics(n, w):
    # one error or warning on every line
    for i in range(n):
        r = i % 4
        if r == 0:
            w(f"G{80 + i % 9} X1")  # E110 / E310
        elif r == 1:
            w(f"R{i % 100 + 1} = 5 / 0")  # W406
        elif r == 2:
            w(f"$aa_out[{i % 50}] = 2")  # E308
        else:
            w(f"GOTOF Nowhere{i}")  # E202
    w("M30")


def long_lines(n, w):
    # lines at the 240-character limit and over it (E102), windows cut in the text format
    items = [f"R{k} = {k}" for k in range(1, 60)]
    short = ""
    for it in items:
        if len(short) + 1 + len(it) > 240:
            break
        short = f"{short} {it}" if short else it
    long = " ".join(items)
    for i in range(n):
        w(short if i % 2 else long)
    w("M30")


def write_file(path, fn, n):
    with open(path, "w", encoding="utf-8") as f:
        fn(n, lambda s: f.write(s + "\n"))


def call_chain(n, out):
    # n subprograms in n files, each calling the next (E211: deeper than 30)
    for i in range(n):
        with open(os.path.join(out, f"s{i}.spf"), "w") as f:
            f.write(f"PROC S{i} SAVE\n")
            if i + 1 < n:
                f.write(f"S{i + 1}\n")
            f.write("G01 X1 F100\nM17\n")
    with open(os.path.join(out, "main.mpf"), "w") as f:
        f.write("S0\nM30\n")
    return os.path.join(out, "main.mpf")


def fan_out(n, out):
    # one main program calling n subprograms, each in its own file
    with open(os.path.join(out, "main.mpf"), "w") as f:
        for i in range(n):
            f.write(f"S{i}\n")
        f.write("M30\n")
    for i in range(n):
        with open(os.path.join(out, f"s{i}.spf"), "w") as f:
            f.write(f"PROC S{i} SAVE\nG01 X{i % 100} F100\nM17\n")
    return os.path.join(out, "main.mpf")


def many_files(n, out):
    # n independent main programs in one folder, the folder linted
    for i in range(n):
        with open(os.path.join(out, f"p{i}.mpf"), "w") as f:
            f.write(f"G01 X{i % 100} F100\nR1 = R1 + 1\nM30\n")
    return out


ONE_FILE = {
    "labels-jumps": labels,
    "nested-if": nested_if,
    "when": when,
    "continuation": continuation,
    "comments": comments,
    "case-arms": case_arms,
    "many-diagnostics": many_diagnostics,
    "long-lines": long_lines,
}
SET = {"call-chain": call_chain, "fan-out": fan_out, "many-files": many_files}
SHAPES = list(ONE_FILE) + list(SET)


def main():
    if len(sys.argv) == 2 and sys.argv[1] == "--list":
        print("\n".join(SHAPES))
        return
    if len(sys.argv) != 4 or sys.argv[1] not in SHAPES:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    shape, n, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    os.makedirs(out, exist_ok=True)
    if shape in ONE_FILE:
        path = os.path.join(out, "prog.mpf")
        write_file(path, ONE_FILE[shape], n)
    else:
        path = SET[shape](n, out)
    print(path)


if __name__ == "__main__":
    main()
