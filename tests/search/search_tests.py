#!/usr/bin/python3
"""search_tests.py: end-to-end tests of isosim --search TEXT (block search, man/isosim.1).

Usage: search_tests.py CASE --bin DIR --source DIR
       search_tests.py --list

CASE is the name of one function case_<CASE> below; tests/search/CMakeLists.txt registers
each one as the CTest test search/<CASE>.  --bin is the directory holding isolint, isocc and
isosim; --source is the source tree. Every case works in its own temporary directory.
Times are hand-computed from the machine of machine_json (1e-6 s, the summary's rounding).

Exit status: 0 pass, 1 fail (the reasons on stderr). Uses only the standard library and the
helpers of ../safety/safety_tests.py.
"""
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "safety"))
import safety_tests as st  # noqa: E402
from safety_tests import check, write  # noqa: E402


def machine_json(dialect):
    """X: 50 mm/s, 1000 mm/s^2 (a move of d >= 2.5 mm takes d/50 + 0.05 s); M23 lasts 5 s."""
    return json.dumps({"name": "search", "dialect": dialect,
                       "axes": [{"name": "X", "max_velocity": 50, "max_accel": 1000,
                                 "limit_minus": -100, "limit_plus": 100}],
                       "m_sequences": {"23": {"duration_s": 5}}})


def setup(d, main, dialect="sidac", more=None):
    write(os.path.join(d, "p.mpf"), main)
    for name, text in (more or {}).items():
        write(os.path.join(d, name), text)
    write(os.path.join(d, "m.json"), machine_json(dialect))


def summary(res):
    check(res.rc == 0, f"isosim failed\n{res.describe()}")
    return json.loads(res.out)


def near(a, b):
    return abs(a - b) <= 1e-6


Z32_PROGRAM = ("N10 G00 X10\n"
               "N20 T1 M6\n"
               "N30 S1000 M3\n"
               "M23\n"
               "G91 F=50\n"
               "N40 G01 X10\n"     # G91 F50: X 10 -> 20, 0.25 s
               "G04 F1\n"
               "M30\n")


def case_z32_line_number(d):
    """z32: --search N40 starts at that line, modal G91/F carried, times from there."""
    setup(d, Z32_PROGRAM, "z32")
    s = summary(st.run("isosim", "p.mpf", "--machine", "m.json", "--search", "N40",
                       "--summary", "--format", "json", cwd=d))
    check(near(s["cycle_time_s"], 1.25), f"cycle time {s['cycle_time_s']}, expected 0.25 + 1")
    check(s["final_position"]["X"] == 20, f"final position {s['final_position']}")
    check(s["blocks"] == 3, f"blocks {s['blocks']}")
    check(s["tool"] == 1 and s["tool_changes"] == 1, f"tool {s['tool']}, changes {s['tool_changes']}")
    check(near(s["spindle_on_s"], 1.25), f"spindle_on_s {s['spindle_on_s']}")
    check(s["search"] == {"text": "N40", "file": "p.mpf", "line": 6}, f"search {s['search']}")
    full = summary(st.run("isosim", "p.mpf", "--machine", "m.json", "--summary", "--format", "json",
                          cwd=d))
    check(near(full["cycle_time_s"], 0.25 + 5 + 0.25 + 1),
          f"without --search: {full['cycle_time_s']}, expected 0.25 + 5 (M23) + 0.25 + 1")
    text = st.run("isosim", "p.mpf", "--machine", "m.json", "--search", "N40", "--summary", cwd=d)
    check(text.rc == 0 and b"\nsearch: N40 (p.mpf:6)\n" in text.out,
          f"the text summary has no search line\n{text.describe()}")


def case_sidac_label_from_image_refused(d):
    """sidac: a label (any case) from the source; an image is refused with exit 2."""
    setup(d, "G00 X10\nM23\nG04 F3\nFine: G00 X20\nM30\n")
    s = summary(st.run("isosim", "p.mpf", "--machine", "m.json", "--search", "FINE", "--summary",
                       "--format", "json", cwd=d))
    check(near(s["cycle_time_s"], 0.25), f"cycle time {s['cycle_time_s']}, expected 0.25")
    check(s["search"]["line"] == 4, f"search {s['search']}")
    cc = st.run("isocc", "p.mpf", "-o", "p.isob", cwd=d)
    check(cc.rc == 0, f"isocc failed\n{cc.describe()}")
    res = st.run("isosim", "p.isob", "--machine", "m.json", "--search", "Fine", "--summary", cwd=d)
    check(res.rc == 2 and b"--search needs the source program" in res.err,
          f"an image with --search is not refused\n{res.describe()}")


def case_not_found_and_subprogram(d):
    """TEXT not in the entry program: exit 2 naming it (and the subprogram that has it)."""
    setup(d, "N10 Lift\nM30\n", "z32", {"lift.spf": "PROC Lift SAVE\nN90 G04 F1\nM17\n"})
    res = st.run("isosim", "p.mpf", "--machine", "m.json", "--search", "N50", "--summary", cwd=d)
    check(res.rc == 2 and b"--search N50: no line of p.mpf begins with N50" in res.err,
          f"not found\n{res.describe()}")
    res = st.run("isosim", "p.mpf", "--machine", "m.json", "--search", "N90", "--summary", cwd=d)
    check(res.rc == 2 and b"the line is in subprogram Lift (lift.spf:2)" in res.err,
          f"a subprogram's line\n{res.describe()}")
    res = st.run("isosim", "p.mpf", "--machine", "m.json", "--search", "N10", "--compare", "p.mpf",
                 cwd=d)
    check(res.rc == 2 and b"--search cannot be combined with --compare" in res.err,
          f"--compare\n{res.describe()}")


def case_program_ends_first(d):
    """A jump past the found line: the run ends with a runtime error (exit 1) naming it."""
    setup(d, "G00 X10\nGOTOF Past\nHere: X20\nPast: M30\n")
    res = st.run("isosim", "p.mpf", "--machine", "m.json", "--search", "Here", "--summary", cwd=d)
    check(res.rc == 1 and b"the program ended before the searched line p.mpf:3 (--search Here)"
          in res.out, f"the program ending first\n{res.describe()}")


# ----------------------------------------------------------------------------------------

CASES = {name[len("case_"):]: fn for name, fn in sorted(globals().items())
         if name.startswith("case_") and callable(fn)}


if __name__ == "__main__":
    sys.exit(st.main(CASES, "search", __doc__))
