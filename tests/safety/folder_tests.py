#!/usr/bin/python3
"""folder_tests.py: end-to-end tests that the folder of a program does not cost isocc and
isosim what they do not link (man/isocc.1, man/isosim.1: program sets).

Usage: folder_tests.py CASE --bin DIR --source DIR
       folder_tests.py --list

CASE is the name of one function case_<CASE> below; tests/safety/CMakeLists.txt registers
each one as the CTest test folder/<CASE> (label safety).  --bin is the directory holding
isolint, isocc and isosim; --source is the source tree.  Every case works in its own
temporary directory and builds its inputs there.

What is checked:
- a large main program beside the one compiled, which nothing calls, is not read: isocc and
  isosim on a sample beside it take the memory they take alone, and write the same image and
  summary;
- the siblings an image links are still read: the subprograms called, the semi-automatic
  programs (isosim --entry runs one beside the large program);
- E209 (one subprogram name twice) stops isocc where it did.

Exit status: 0 pass, 1 fail (the reasons on stderr). On a sanitizer build
(ISO_SANITIZE_BUILD=1) the memory bound is not checked.
Uses only the standard library and the helpers of safety_tests.py (same folder).
"""
import os
import shutil
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import safety_tests as st  # noqa: E402  (run, run_measured, check, ...)

from safety_tests import check, read, write  # noqa: E402

MIB = 1024 * 1024
LARGE = 64 * MIB      # bytes of the uncalled sibling: read whole, it would cost more than this
SLACK = 16 * MIB      # what the peak RSS beside it may exceed the peak RSS alone by


def sanitizer_build():
    return os.environ.get("ISO_SANITIZE_BUILD") == "1"


def large_main(path):
    """A valid main program of about LARGE bytes: a CAM program nobody calls."""
    chunk = "G01 X123.456 Y654.321 Z-1.5 F1000\n" * 30000  # about 1 MiB
    with open(path, "w", encoding="ascii") as f:
        f.write("; CAM program\nG90 G01 F1000\n")
        for _ in range(LARGE // len(chunk) + 1):  # in pieces: this process stays small (a child's
            f.write(chunk)                         # peak RSS counts the parent's from before its exec)
        f.write("M30\n")


def alone_and_crowd(d, sample):
    """d/alone/SAMPLE and d/crowd/SAMPLE (the same beside a large uncalled main program)."""
    src = os.path.join(st.SOURCE, "samples", sample)
    for where in ("alone", "crowd"):
        shutil.copytree(src, os.path.join(d, where, sample))
    large_main(os.path.join(d, "crowd", sample, "cam.mpf"))
    return os.path.join(d, "alone", sample), os.path.join(d, "crowd", sample)


def measured(tool_name, *args, cwd):
    res, rss = st.run_measured(tool_name, *args, cwd=cwd, timeout=50)
    check(res.rc == 0, f"`{res.what()}` failed\n{res.describe()}")
    return res, rss


def check_rss(what, alone, crowd):
    if sanitizer_build():
        return
    check(crowd < alone + SLACK,
          f"{what}: peak RSS {crowd / MIB:.1f} MiB beside a {LARGE // MIB} MiB program nothing calls, "
          f"{alone / MIB:.1f} MiB alone: the sibling was read")


def case_uncalled_sibling_isocc(d):
    alone, crowd = alone_and_crowd(d, "pallet_loader")
    _, rss_alone = measured("isocc", "pallettizzatore.mpf", "-o", os.path.join(d, "alone.isob"), cwd=alone)
    _, rss_crowd = measured("isocc", "pallettizzatore.mpf", "-o", os.path.join(d, "crowd.isob"), cwd=crowd)
    check(read(os.path.join(d, "alone.isob")) == read(os.path.join(d, "crowd.isob")),
          "isocc: the image beside the large program differs from the image alone")
    check_rss("isocc pallettizzatore.mpf", rss_alone, rss_crowd)


def case_uncalled_sibling_isosim(d):
    alone, crowd = alone_and_crowd(d, "pallet_loader")
    a, rss_alone = measured("isosim", "pallettizzatore.mpf", "--summary", "--format", "json", cwd=alone)
    c, rss_crowd = measured("isosim", "pallettizzatore.mpf", "--summary", "--format", "json", cwd=crowd)
    check(a.out == c.out, f"isosim: the summary beside the large program differs\nalone: {a.out}\ncrowd: {c.out}")
    check(b'"status": "ok"' in a.out, f"isosim: the sample did not run to its end\n{a.describe()}")
    check_rss("isosim pallettizzatore.mpf --summary", rss_alone, rss_crowd)


def case_linked_siblings(d):
    alone, crowd = alone_and_crowd(d, "semi_auto")
    # the folder itself: every file named, the large one apart
    folder = os.path.join(d, "folder")
    shutil.copytree(os.path.join(st.SOURCE, "samples", "semi_auto"), folder)
    measured("isocc", folder, "-o", os.path.join(d, "folder.isob"), cwd=d)
    res, rss_crowd = measured("isocc", "fresatura_cornice.mpf", "-o", os.path.join(d, "crowd.isob"), cwd=crowd)
    _, rss_alone = measured("isocc", "fresatura_cornice.mpf", "-o", os.path.join(d, "alone.isob"), cwd=alone)
    image = read(os.path.join(d, "crowd.isob"))
    check(image == read(os.path.join(d, "folder.isob")),
          "isocc on the main program beside the large one: not the image of its folder (the semi-automatic "
          "programs and the subprogram are linked into it)")
    listing = st.run("isocc", "--disasm", os.path.join(d, "crowd.isob"), cwd=d)
    text = listing.out.decode("utf-8", "backslashreplace")
    for name in ("Cambio utensile manuale", "Posizione di carico", "Posizione_sicura"):
        check(name in text, f"isocc --disasm: no {name} in the image\n{listing.describe()}")
    check_rss("isocc fresatura_cornice.mpf", rss_alone, rss_crowd)
    # a semi-automatic program runs from the main program's folder beside the large program
    a = st.run("isosim", "fresatura_cornice.mpf", "--entry", "Posizione di carico", "--summary", cwd=alone)
    c = st.run("isosim", "fresatura_cornice.mpf", "--entry", "Posizione di carico", "--summary", cwd=crowd)
    check(a.rc == 0 and c.rc == 0 and a.out == c.out,
          f"isosim --entry beside the large program differs from alone\n{a.describe()}\n{c.describe()}")


def case_duplicate_subprogram(d):
    prog = os.path.join(d, "p")
    os.mkdir(prog)
    write(os.path.join(prog, "main.mpf"), "Giu\nM30\n")
    write(os.path.join(prog, "giu.spf"), "PROC Giu SAVE\nG0 Z0\nM17\n")
    write(os.path.join(prog, "giu2.spf"), "PROC GIU SAVE\nM17\n")
    large_main(os.path.join(prog, "cam.mpf"))
    for args in (["main.mpf", "giu.spf", "giu2.spf"], ["."]):
        res = st.run("isocc", *args, "-o", os.path.join(d, "out.isob"), cwd=prog, timeout=50)
        err = res.err.decode("utf-8", "backslashreplace")
        check(res.rc == 1 and "giu2.spf:1:6: error" in err and "E209" in err,
              f"isocc {' '.join(args)}: expected E209 in giu2.spf and exit 1\n{res.describe()}")
        check(not os.path.exists(os.path.join(d, "out.isob")), "isocc wrote an image despite E209")


CASES = {name[len("case_"):]: fn for name, fn in sorted(globals().items())
         if name.startswith("case_") and callable(fn)}


if __name__ == "__main__":
    sys.exit(st.main(CASES, "folder", __doc__))
