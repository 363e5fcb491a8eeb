#!/usr/bin/env python3
"""End-to-end tests of isofmt: the promise that formatting changes nothing the machine runs.

One CTest test isofmt/<case> per function case_<case> (tests/isofmt/CMakeLists.txt):

  samples   every program set of samples/: formatted (-i), it compiles to the image of the
            original (isocc --strip: everything but the line table), isolint reports the same
            codes at the same (mapped) lines, a second run changes nothing; renumbered (--renumber 10,10) the same
  tests     the same for every folder of .mpf/.spf files under tests/ whose programs compile,
            in dialect sidac and z32
  corpus    the programs of ../shared/corpus: formatting (and renumbering) twice changes nothing,
            and a program
            that compiles alone compiles to the same image formatted (exit 77 when absent)
  cli       --check, --diff, -i, standard input, usage errors, refusals write nothing

Usage: isofmt_tests.py CASE --bin DIR --source DIR
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

PROGRAM_EXTS = (".mpf", ".spf")


def run(args, cwd=None, stdin=None):
    return subprocess.run(args, cwd=cwd, input=stdin, capture_output=True, timeout=120)


def line_map(original, formatted):
    """Line numbers of `original` (1-based) -> those of `formatted`: formatting rewrites lines
    in place and only drops blank lines, so the lines that stay keep their order."""
    def lines(path):
        with open(path, "rb") as f:
            return f.read().split(b"\n")
    old, new = lines(original), lines(formatted)
    mapping, j = {}, 0
    for i, text in enumerate(old):
        if not text.strip():
            if j < len(new) and not new[j].strip():
                mapping[i + 1] = j + 1
                j += 1
            continue  # a dropped blank line
        while j < len(new) and not new[j].strip():
            j += 1
        mapping[i + 1] = j + 1
        j += 1
    return mapping


class Checker:
    def __init__(self, bindir):
        self.isofmt = os.path.join(bindir, "isofmt")
        self.isocc = os.path.join(bindir, "isocc")
        self.isolint = os.path.join(bindir, "isolint")
        self.problems = []
        self.compiled = 0

    def fail(self, what):
        self.problems.append(what)

    def image(self, cwd, main, extra):
        out = os.path.join(cwd, ".image.isob")
        r = run([self.isocc, "--strip", *extra, main, "-o", out], cwd=cwd)
        if r.returncode != 0:
            return None
        with open(out, "rb") as f:
            data = f.read()
        os.remove(out)
        return data

    def codes(self, cwd, files, extra, line_maps=None):
        """isolint's (file, line, code) triples; with line_maps, each line mapped through the
        file's map (original line -> formatted line)."""
        r = run([self.isolint, "--format", "json", *extra, *files], cwd=cwd)
        try:
            doc = json.loads(r.stdout)
        except ValueError:
            return None
        rows = []
        for d in doc["diagnostics"]:
            line = d.get("line", 0)
            if line_maps is not None:
                line = line_maps.get(d["file"], {}).get(line, line)
            rows.append((d["file"], line, d["code"]))
        return sorted(rows)

    def check_folder(self, src, label, extra, renumber=True):
        """Formats a copy of folder `src` and compares it with another copy."""
        files = sorted(f for f in os.listdir(src) if f.lower().endswith(PROGRAM_EXTS)
                       and os.path.isfile(os.path.join(src, f)))
        if not files:
            return
        with tempfile.TemporaryDirectory() as tmp:
            orig = os.path.join(tmp, "orig")
            shutil.copytree(src, orig, ignore=lambda d, names: [n for n in names if os.path.isdir(os.path.join(d, n))])
            mains = [f for f in files if f.lower().endswith(".mpf")]
            images = {m: self.image(orig, m, extra) for m in mains}
            if not any(images.values()):
                return
            self.compare(orig, tmp, "fmt", label, files, mains, images, extra, [])
            if renumber:
                self.compare(orig, tmp, "renumbered", label, files, mains, images, extra, ["--renumber", "10,10"])

    def compare(self, orig, tmp, name, label, files, mains, images, extra, options):
        work = os.path.join(tmp, name)
        shutil.copytree(orig, work)
        r = run([self.isofmt, "-i", *options, *extra, *files], cwd=work)
        if options and r.returncode == 1 and b"cannot renumber" in r.stderr:
            return  # refused, and nothing written: checked by the cli case
        if r.returncode != 0:
            self.fail(f"{label}: isofmt -i {' '.join(options)} exit {r.returncode}: {r.stderr.decode()}")
            return
        for m in mains:
            if images[m] is None:
                continue
            self.compiled += 1
            formatted = self.image(work, m, extra)
            if formatted is None:
                self.fail(f"{label}/{m}: {name} does not compile")
            elif formatted != images[m]:
                self.fail(f"{label}/{m}: {name} compiles to another image")
        if not options:
            maps = {f: line_map(os.path.join(orig, f), os.path.join(work, f)) for f in files}
            before, after = self.codes(orig, files, extra, maps), self.codes(work, files, extra)
            if before != after:
                self.fail(f"{label}: isolint's codes at the mapped lines differ once formatted: "
                          f"{sorted(set(before or []) ^ set(after or []))[:6]}")
        again = run([self.isofmt, "--check", *options, *extra, *files], cwd=work)
        if again.returncode != 0:
            self.fail(f"{label}: a second {name} run would change {again.stdout.decode().split()}")

    def report(self, what):
        for p in self.problems:
            print("FAIL:", p)
        print(f"{what}: {self.compiled} programs compiled formatted and as written")
        return 1 if self.problems else 0


def case_samples(args):
    c = Checker(args.bin)
    root = os.path.join(args.source, "samples")
    for d in sorted(os.listdir(root)):
        if os.path.isdir(os.path.join(root, d)):
            c.check_folder(os.path.join(root, d), f"samples/{d}", [])
    if c.compiled == 0:
        c.fail("no sample compiled")
    return c.report("samples")


def case_tests(args):
    c = Checker(args.bin)
    root = os.path.join(args.source, "tests")
    for d, _, names in sorted(os.walk(root)):
        if not any(n.lower().endswith(PROGRAM_EXTS) for n in names):
            continue
        label = os.path.relpath(d, args.source)
        c.check_folder(d, label, [])
        c.check_folder(d, label + " (z32)", ["--dialect", "z32"])
    if c.compiled == 0:
        c.fail("no test program compiled")
    return c.report("tests")


def case_corpus(args):
    root = os.path.join(args.source, "..", "shared", "corpus")
    if not os.path.isdir(root):
        print("skipped: no corpus at", root)
        return 77
    c = Checker(args.bin)
    formatted = renumbered = refused = 0
    for d, _, names in sorted(os.walk(root)):
        for n in sorted(names):
            if not n.lower().endswith(PROGRAM_EXTS + (".nc", ".iso", ".txt")):
                continue
            path = os.path.join(d, n)
            r = run([c.isofmt, path])
            if r.returncode != 0:
                c.fail(f"{path}: isofmt exit {r.returncode}: {r.stderr.decode()[:200]}")
                continue
            formatted += 1
            again = run([c.isofmt, "-"], stdin=r.stdout)
            if again.returncode != 0 or again.stdout != r.stdout:
                c.fail(f"{path}: formatting twice changes the text")
            # renumbered: done (and then stable), or refused with the reason and exit 1
            n = run([c.isofmt, "--renumber", "10,10", path])
            if n.returncode == 1 and b"cannot renumber" in n.stderr:
                refused += 1
            elif n.returncode != 0:
                c.fail(f"{path}: isofmt --renumber exit {n.returncode}: {n.stderr.decode()[:200]}")
            else:
                renumbered += 1
                again = run([c.isofmt, "--renumber", "10,10", "-"], stdin=n.stdout)
                if again.returncode != 0 or again.stdout != n.stdout:
                    c.fail(f"{path}: renumbering twice changes the text")
        if names and any(n.lower().endswith(PROGRAM_EXTS) for n in names):
            c.check_folder(d, os.path.relpath(d, root), [])
    print(f"corpus: {formatted} files formatted, {renumbered} renumbered, {refused} refused for renumbering")
    return c.report("corpus")


def write(path, text, mode="w"):
    with open(path, mode, newline="") as f:
        f.write(text)


def case_cli(args):
    c = Checker(args.bin)
    problems = []

    def expect(cond, what):
        if not cond:
            problems.append(what)

    with tempfile.TemporaryDirectory() as tmp:
        p = os.path.join(tmp, "p.mpf")
        src = "n10 g01 x10 f=100\r\nr1=2\r\n\r\n\r\nm30\r\n"
        write(p, src)
        r = run([c.isofmt, "--check", p])
        expect(r.returncode == 1 and r.stdout.decode().strip() == p, f"--check: {r.returncode} {r.stdout!r}")
        r = run([c.isofmt, "--diff", p])
        expect(r.returncode == 0 and b"-n10 g01 x10 f=100" in r.stdout and b"+N10 G01 X10 F=100" in r.stdout,
               f"--diff: {r.stdout!r}")
        expect(open(p, newline="").read() == src, "--check/--diff changed the file")
        r = run([c.isofmt, p])
        expect(r.stdout == b"N10 G01 X10 F=100\r\nR1 = 2\r\n\r\nM30\r\n", f"stdout: {r.stdout!r}")
        r = run([c.isofmt, "-i", p])
        expect(r.returncode == 0 and open(p, "rb").read() == b"N10 G01 X10 F=100\r\nR1 = 2\r\n\r\nM30\r\n",
               "-i: the file is not the formatted text (CR LF kept)")
        expect(not [n for n in os.listdir(tmp) if n.startswith(".")], "-i left a temporary file")
        r = run([c.isofmt, "-"], stdin=b"g0 x1\nm30\n")
        expect(r.stdout == b"G0 X1\nM30\n", f"standard input: {r.stdout!r}")
        r = run([c.isofmt, "-i", "--check", p])
        expect(r.returncode == 2 and b"cannot be combined" in r.stderr, f"-i --check: {r.returncode}")
        r = run([c.isofmt])
        expect(r.returncode == 2, "no input is a usage error")
        r = run([c.isofmt, "--renumber", "x", p])
        expect(r.returncode == 2, "--renumber x is a usage error")
        r = run([c.isofmt, os.path.join(tmp, "missing.mpf")])
        expect(r.returncode == 2 and b"missing.mpf" in r.stderr, "a missing input is exit 2")
        # a GO naming a repeated N number: refused, nothing written, exit 1
        z = os.path.join(tmp, "z.mpf")
        zsrc = "N10 G0 X1\nN20 GON30\nN30 X2\nN30 X3\nM30\n"
        write(z, zsrc)
        r = run([c.isofmt, "-i", "--dialect", "z32", "--renumber", "100", p, z])
        expect(r.returncode == 1 and b"z.mpf:2: error: cannot renumber" in r.stderr, f"refusal: {r.stderr!r}")
        expect(open(z).read() == zsrc, "a refused file was written")
        # a file with syntax errors is left as written, exit 0, with a note
        bad = os.path.join(tmp, "bad.mpf")
        write(bad, "g01 x=(1\nm30\n")
        r = run([c.isofmt, bad])
        expect(r.returncode == 0 and r.stdout == b"g01 x=(1\nm30\n" and b"syntax errors" in r.stderr,
               f"syntax errors: {r.returncode} {r.stderr!r}")
        # -i onto the settings file is refused
        toml = os.path.join(tmp, "isotools.toml")
        write(toml, "[format]\nindent = 4\n")
        r = run([c.isofmt, "-i", p, toml])
        expect(r.returncode == 2, f"-i onto the settings file: {r.returncode}")
    for p in problems:
        print("FAIL:", p)
    return 1 if problems else 0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("case")
    ap.add_argument("--bin", required=True)
    ap.add_argument("--source", required=True)
    args = ap.parse_args()
    fn = globals().get("case_" + args.case)
    if not fn:
        print("unknown case", args.case)
        return 2
    return fn(args)


if __name__ == "__main__":
    sys.exit(main())
