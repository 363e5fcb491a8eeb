#!/usr/bin/python3
"""check_views.py: end-to-end tests of isosim's views of a run (--plot, --timeline, --report).

Usage: check_views.py CASE --tool ISOSIM --dir TESTS_VIEWS_DIR --out-dir DIR

CASE is one of:
  timeline   isosim timeline.mpf --machine machine.json --timeline: the file equals the golden
             timeline.json (ISO_UPDATE_GOLDEN=1 rewrites it); the main track's slices tile the
             run and add up to the cycle time in whole µs; the WHEN body, the PLC sequences,
             the axes and the I/O have their tracks
  peak       a run of 10,000 s that dwells for hours around one rapid of 0.85 s (0.35 s of it at 500 mm/s): the velocity
             curve of the plot still reaches the rapid's 500 mm/s (min/max decimation per
             pixel), the time axis spans the run, and the SVG stays small
  report     isosim --report on a sample: the page parses (html.parser), has the sections
             summary, warnings, plot (an inline <svg>) and profile (rows slowest first, the
             cycle time of --summary), no <script>, no external URL (src, href, url(), @import)
  render     the same page rendered by headless Chromium to a PNG that is not blank
             (exit 77, a CTest skip, when chromium is not installed)
  docs       docs/taglio_piastra.svg (the README's picture) is what isosim --plot draws today
             for samples/contour_g64/taglio_piastra.mpf (ISO_UPDATE_GOLDEN=1 redraws it)

Exit 0 pass, 1 fail (reasons on stdout), 77 skip.
"""
import argparse
import html.parser
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET
import zlib

SVG = "{http://www.w3.org/2000/svg}"
SKIP = 77


def run(argv, cwd=None):
    r = subprocess.run(argv, cwd=cwd, capture_output=True, text=True, timeout=300)
    if r.returncode != 0:
        raise SystemExit(f"`{' '.join(argv)}` exited {r.returncode}:\n{r.stdout}{r.stderr}")
    return r.stdout


# ---- timeline

def case_timeline(a):
    out = os.path.join(a.out_dir, "timeline.json")
    run([a.tool, "timeline.mpf", "--machine", "machine.json", "--summary", "--timeline", out], cwd=a.dir)
    with open(out, "rb") as f:
        got = f.read()
    expected_path = os.path.join(a.dir, "timeline.json")
    problems = []
    if os.environ.get("ISO_UPDATE_GOLDEN") == "1":
        with open(expected_path, "wb") as f:
            f.write(got)
        print(f"rebased {expected_path}")
    else:
        with open(expected_path, "rb") as f:
            if f.read() != got:
                problems.append(f"{out} differs from {expected_path} (ISO_UPDATE_GOLDEN=1 rebases it; "
                                f"diff -u {expected_path} {out})")
    doc = json.loads(got)
    summary = json.loads(run([a.tool, "timeline.mpf", "--machine", "machine.json", "--summary", "--format",
                              "json"], cwd=a.dir))
    ev = [e for e in doc["traceEvents"] if e["ph"] != "M"]
    main = [e for e in ev if e["ph"] == "X" and e["tid"] == 1]
    cyc_us = round(summary["cycle_time_s"] * 1_000_000)
    if sum(e["dur"] for e in main) != cyc_us or doc["otherData"]["cycle_time_us"] != cyc_us:
        problems.append(f"main slices add up to {sum(e['dur'] for e in main)} µs, cycle {cyc_us} µs")
    if any(x["ts"] + x["dur"] != y["ts"] for x, y in zip(main, main[1:])) or main[0]["ts"] != 0:
        problems.append("the main slices do not tile the run")
    names = {e["tid"]: e["args"]["name"] for e in doc["traceEvents"] if e["name"] == "thread_name"}
    for want in ("main program", "I/O", "axis X", "axis Y", "WHEN timeline.mpf:4", "PLC M23", "PLC M24"):
        if want not in names.values():
            problems.append(f"no track '{want}' (tracks: {sorted(names.values())})")
    by_track = {}
    for e in ev:
        by_track.setdefault(names.get(e["tid"]), []).append(e)
    when = by_track.get("WHEN timeline.mpf:4", [])
    body = [e for e in when if e["cat"] == "when"]
    lines = [e for e in when if e["cat"] == "line"]
    if len(body) != 1 or [e["args"].get("n") for e in lines] != [21, 22]:
        problems.append(f"the WHEN track should hold one body with lines N21 and N22: {when}")
    elif any(e["ts"] < body[0]["ts"] or e["ts"] + e["dur"] > body[0]["ts"] + body[0]["dur"] for e in lines):
        problems.append("the body's lines are not inside the body's slice")
    m23 = by_track.get("PLC M23", [])
    if [(e["name"], e["dur"]) for e in m23] != [("M=NB(23)", 1_000_000)]:
        problems.append(f"PLC M23: {m23}")
    io = [e["name"] for e in by_track.get("I/O", [])]
    if io != ["output 3 = 1", "input 5 = 1", "output 3 = 0"]:
        problems.append(f"I/O instants: {io}")
    limits = {e["args"].get("n"): e["args"].get("limit") for e in main}
    for n, want in ((30, "feed"), (50, "dwell"), (60, "plc")):
        if limits.get(n) != want:
            problems.append(f"N{n}: limit {limits.get(n)!r}, expected {want!r}")
    rapid = [e for e in by_track.get("axis X", []) if e["args"]["motion"] == "G00"]
    if len(rapid) != 1:
        problems.append(f"axis X should have one G00 move: {by_track.get('axis X')}")
    return problems, f"{len(ev)} events, main slices add up to {cyc_us} µs"


# ---- peak

def case_peak(a):
    prog = os.path.join(a.out_dir, "peak.mpf")
    with open(prog, "w") as f:
        f.write("; hours of dwell around one short rapid\nN10 G04 F5000\nN20 G00 X300\nN30 G04 F5000\nN40 M30\n")
    svg_path = os.path.join(a.out_dir, "peak.svg")
    out = run([a.tool, prog, "--summary", "--plot", svg_path])
    problems = []
    size = os.path.getsize(svg_path)
    if size > 1_000_000:
        problems.append(f"the SVG of a 10,000 s run is {size} bytes")
    root = ET.parse(svg_path).getroot()
    panels = {r.get("data-kind"): r for r in root.iter(SVG + "rect") if r.get("class") == "panel"}
    if set(panels) != {"position", "velocity"}:
        return [f"panels {sorted(panels)}"], ""
    vp = panels["velocity"]
    lo, hi = float(vp.get("data-lo")), float(vp.get("data-hi"))
    top, height = float(vp.get("y")), float(vp.get("height"))
    t1 = float(vp.get("data-t1"))
    if not 10_000 <= t1 <= 10_001:
        problems.append(f"the time axis ends at {t1} s, not at the end of the run (10000.85 s)")
    curves = [p for p in root.iter(SVG + "polyline") if p.get("class") == "curve"]
    if len(curves) != 2:
        return problems + [f"{len(curves)} curves, expected X's position and velocity"], ""
    pts = [tuple(map(float, p.split(","))) for p in curves[1].get("points").split()]
    peak = max(lo + (top + height - y) / height * (hi - lo) for _, y in pts)
    px_per_unit = height / (hi - lo)
    if abs(peak - 500) * px_per_unit > 1:
        problems.append(f"the velocity curve peaks at {peak:.2f} mm/s, not at the rapid's 500 mm/s "
                        f"({len(pts)} points)")
    if len(pts) > 4 * 800:
        problems.append(f"{len(pts)} points in one curve: not decimated per pixel")
    cyc = re.search(r"cycle_time_s: (\S+)", out).group(1)
    return problems, f"cycle {cyc} s, velocity peak {peak:.3f} mm/s drawn with {len(pts)} points, {size} bytes"


# ---- report

class PageParser(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.tags = []
        self.sections = []
        self.stack = []
        self.attrs = []
        self.text = {}
        self.current = None
        self.rows = []
        self.row = None
        self.cell = None

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        self.attrs.append((tag, dict(attrs)))
        d = dict(attrs)
        if tag == "section":
            self.sections.append(d.get("id"))
            self.current = d.get("id")
        if self.current == "profile" and tag == "tr":
            self.row = []
        if self.row is not None and tag == "td":
            self.cell = ""

    def handle_endtag(self, tag):
        if tag == "section":
            self.current = None
        if tag == "td" and self.row is not None and self.cell is not None:
            self.row.append(self.cell)
            self.cell = None
        if tag == "tr" and self.row is not None:
            if self.row:
                self.rows.append(self.row)
            self.row = None

    def handle_data(self, data):
        if self.current:
            self.text[self.current] = self.text.get(self.current, "") + data
        if self.cell is not None:
            self.cell += data


def report_path(a):
    return os.path.join(a.out_dir, "report.html")


def make_report(a):
    path = report_path(a)
    out = run([a.tool, a.program, "--summary", "--report", path])
    return path, re.search(r"cycle_time_s: (\S+)", out).group(1)


def case_report(a):
    path, cyc = make_report(a)
    with open(path, encoding="utf-8") as f:
        page = f.read()
    p = PageParser()
    p.feed(page)
    p.close()
    problems = []
    for want in ("summary", "warnings", "plot", "profile"):
        if want not in p.sections:
            problems.append(f"no section '{want}' (sections: {p.sections})")
    if "script" in p.tags:
        problems.append("the page has a <script>")
    if "svg" not in p.tags or "polyline" not in p.tags:
        problems.append("no inline SVG plot")
    for tag, attrs in p.attrs:
        for k in ("src", "href", "xlink:href", "action", "data"):
            v = attrs.get(k)
            if v and (re.match(r"^[a-z][a-z0-9+.-]*:", v, re.I) or v.startswith("//")):
                problems.append(f"<{tag} {k}={v!r}>: an external reference")
        if tag in ("link", "iframe", "img", "object", "embed"):
            problems.append(f"<{tag}>: the page must be self-contained")
    if re.search(r"url\s*\(|@import", page):
        problems.append("a CSS url() or @import")
    if f"{cyc} s" not in p.text.get("summary", ""):
        problems.append(f"the summary does not show the cycle time {cyc} s")
    times = [float(r[2]) for r in p.rows if len(r) > 2]
    if not times:
        problems.append("no profile rows")
    elif times != sorted(times, reverse=True):
        problems.append(f"profile rows not sorted by time: {times[:10]}")
    return problems, f"{len(p.sections)} sections, {len(times)} profile rows, {len(page)} bytes"


def png_not_blank(path):
    """True when the PNG has at least two distinct pixel bytes (it shows something)."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        return False, "not a PNG"
    pos, idat, w, h = 8, b"", 0, 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h = struct.unpack(">II", body[:8])
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw = zlib.decompress(idat)
    return len(set(raw[1:min(len(raw), 4_000_000)])) > 8, f"{w}x{h}"


def case_render(a):
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if browser is None:
        print("chromium not installed (apt-get install chromium): render check skipped")
        sys.exit(SKIP)
    path, _ = make_report(a)
    png = os.path.join(a.out_dir, "report.png")
    if os.path.exists(png):
        os.remove(png)
    profile = os.path.join(a.out_dir, "chromium-profile")
    r = subprocess.run([browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                        "--no-first-run", f"--user-data-dir={profile}", "--window-size=1200,2400",
                        f"--screenshot={png}", "file://" + os.path.abspath(path)],
                       capture_output=True, text=True, timeout=120)
    if r.returncode != 0 or not os.path.exists(png):
        return [f"chromium exited {r.returncode}, no {png}:\n{r.stderr[-2000:]}"], ""
    ok, what = png_not_blank(png)
    if not ok:
        return [f"{png} is blank ({what})"], ""
    return [], f"rendered {png} ({what})"


# ---- docs

def case_docs(a):
    src = os.path.abspath(os.path.join(a.dir, "..", ".."))
    svg = os.path.join(src, "docs", "taglio_piastra.svg")
    out = os.path.join(a.out_dir, "taglio_piastra.svg")
    run([a.tool, os.path.join(src, "samples", "contour_g64", "taglio_piastra.mpf"), "--summary", "--plot", out])
    with open(out, "rb") as f:
        got = f.read()
    if os.environ.get("ISO_UPDATE_GOLDEN") == "1":
        with open(svg, "wb") as f:
            f.write(got)
        return [], f"redrew {svg}"
    with open(svg, "rb") as f:
        if f.read() != got:
            return [f"{svg} is not what isosim draws today (ISO_UPDATE_GOLDEN=1 ctest -R views/docs redraws it)"], ""
    ET.fromstring(got)
    return [], f"{svg} is up to date"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("case", choices=["timeline", "peak", "report", "render", "docs"])
    ap.add_argument("--tool", required=True)
    ap.add_argument("--dir", required=True, help="tests/views (timeline.mpf, machine.json, timeline.json)")
    ap.add_argument("--program", help="the program of the report cases")
    ap.add_argument("--out-dir", required=True)
    a = ap.parse_args()
    os.makedirs(a.out_dir, exist_ok=True)
    problems, detail = globals()["case_" + a.case](a)
    if problems:
        print("\n".join(problems))
        return 1
    print(f"{a.case}: {detail}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
