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
             cycle time of --summary), profile rows and path segments with data-file and
             data-line, the source lines they link to embedded, only inline scripts, no
             external URL (src, href, url(), @import) and no network call in the script
  render     the same page rendered by headless Chromium to a PNG that is not blank
             (exit 77, a CTest skip, when chromium is not installed)
  scale      a generated 100,000-block CAM-like program: the SVG stays under 8 MB with no
             block marker, one path element per run of rapids, a legend (feed scale, rapid);
             its four feeds give at least four feed colours; a program that moves X, Y and Z
             gets the panels XY, ZX and YZ, one with --plot-plane
  shots      headless Chromium screenshots (PNG, decoded here with zlib) of a sample's SVG, of
             its report and of the 100,000-block plot: at least N distinct hues, and no large
             grey area (what thousands of dashed block markers made); SKIP without chromium
  dom        the report after its script ran (chromium --dump-dom): "#line=FILE:N" shows line
             N of the source and marks its path segments and its row; "#sort=1" orders the
             rows by runs; SKIP without chromium
  docs       docs/taglio_piastra.svg (the README's picture) is what isosim --plot draws today
             for samples/contour_g64/taglio_piastra.mpf (ISO_UPDATE_GOLDEN=1 redraws it)

Exit 0 pass, 1 fail (reasons on stdout), 77 skip.
"""
import argparse
import html
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
        if "tid" in e:
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
    # counter tracks: position and velocity of each axis that moves, in time order, bounded
    counters = {}
    for e in ev:
        if e["ph"] == "C":
            counters.setdefault(e["name"], []).append(e)
    if sorted(counters) != ["X position", "X velocity", "Y position", "Y velocity"]:
        problems.append(f"counter tracks {sorted(counters)}")
    for name, values in counters.items():
        ts = [e["ts"] for e in values]
        if ts != sorted(ts) or len(set(ts)) != len(ts) or len(ts) > 2002:
            problems.append(f"{name}: {len(ts)} values, not one per µs in time order")
    xs = [e["args"]["X"] for e in counters.get("X position", [])]
    if xs and (xs[0] != 0 or abs(max(xs) - 100) > 1e-6):
        problems.append(f"X position counts from {xs[0]} up to {max(xs)}, expected 0 to 100")
    if doc["otherData"].get("counter_values") != sum(len(v) for v in counters.values()):
        problems.append("otherData.counter_values is not the number of counter values")
    return problems, f"{len(ev)} events ({sum(len(v) for v in counters.values())} counter values), " \
                     f"main slices add up to {cyc_us} µs"


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
    for tag, attrs in p.attrs:
        if tag == "script" and "src" in attrs:
            problems.append("a <script src>: scripts must be inline")
    scripts = re.findall(r"<script>(.*?)</script>", page, re.S)
    if len(scripts) != 1:
        problems.append(f"{len(scripts)} inline scripts, expected 1")
    elif re.search(r"fetch\(|XMLHttpRequest|import\(|WebSocket|sendBeacon|https?:", scripts[0]):
        problems.append("the script reaches for the network")
    rows = [attrs for tag, attrs in p.attrs if tag == "tr" and "data-line" in attrs]
    segs = [attrs for tag, attrs in p.attrs if tag == "polyline" and attrs.get("class") == "path"]
    if not rows or not segs:
        problems.append(f"{len(rows)} profile rows and {len(segs)} path segments with data-line")
    if any(not s.get("data-line", "").isdigit() or not s.get("data-file") for s in segs):
        problems.append("a path segment without data-file and data-line")
    data = re.search(r'<script type="application/json" id="iso-source">(.*?)</script>', page, re.S)
    src = json.loads(data.group(1)) if data else {}
    with open(a.program, encoding="utf-8") as f:
        text = f.read().split("\n")
    main = os.path.basename(a.program)
    for r in rows[:20]:
        if r["data-file"] == main and src.get(main, {}).get(r["data-line"]) != text[int(r["data-line"]) - 1]:
            problems.append(f"line {r['data-line']} of {main} is not embedded as it reads")
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
    return problems, f"{len(p.sections)} sections, {len(times)} profile rows, {len(segs)} linked path segments, " \
                     f"{len(page)} bytes"


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


# ---- scale

FEEDS = (5, 15, 30, 60)  # mm/s


def cam_program(path, blocks):
    """A CAM-like program of `blocks` lines: spiral passes of short G01 segments, each pass at one
    of FEEDS around its own centre, a rapid retract and approach and a plunge between passes."""
    import math
    lines = ["; generated: spiral passes at four feeds", "G90 G64", "G00 X0 Y0 Z5"]
    p = 0
    while len(lines) < blocks - 2:
        f, cx, cy = FEEDS[p % 4], 50 + 110 * (p % 2), 50 + 110 * (p // 2 % 2)
        lines += ["G00 Z5", f"G00 X{cx + 5} Y{cy}", f"G01 Z{-1 - p % 5} F={FEEDS[0]}"]
        for i in range(400):
            r, ang = 5 + i * 0.1, i * 0.05
            lines.append(f"G01 X{cx + r * math.cos(ang):.3f} Y{cy + r * math.sin(ang):.3f} F={f}")
        p += 1
    lines = lines[:blocks - 2] + ["G00 Z5", "M30"]
    with open(path, "w") as out:
        out.write("\n".join(lines) + "\n")


def big_plot(a):
    prog = os.path.join(a.out_dir, "cam100k.mpf")
    svg = os.path.join(a.out_dir, "cam100k.svg")
    cam_program(prog, 100_000)
    r = subprocess.run([a.tool, prog, "--summary", "--plot", svg, "--max-diagnostics", "1"],
                       capture_output=True, text=True, timeout=300)
    if r.returncode != 0:
        raise SystemExit(f"isosim on {prog} exited {r.returncode}:\n{r.stderr[-2000:]}")
    return svg


def feed_colours(root):
    return {p.get("stroke") for p in root.iter(SVG + "polyline") if p.get("data-kind") == "feed"}


def case_scale(a):
    problems = []
    svg = big_plot(a)
    size = os.path.getsize(svg)
    if size > 8_000_000:
        problems.append(f"the SVG of 100,000 blocks is {size} bytes")
    root = ET.parse(svg).getroot()
    titles = [t.text or "" for t in root.iter(SVG + "title")]
    if any(t.startswith("cam100k.mpf:") for t in titles):
        problems.append("block markers drawn for 100,000 blocks")
    notes = [t.text for t in root.iter(SVG + "text") if t.get("class") == "cap-note"]
    if not notes or "no block marker (99999 lines run" not in notes[0]:
        problems.append(f"no note that block markers are left out: {notes}")
    # the note line fits the width; the notes left out of it are counted and in its tooltip
    for t in root.iter(SVG + "text"):
        if t.get("class") != "cap-note":
            continue
        if len(t.text or "") > 150:
            problems.append(f"a note line of {len(t.text)} characters runs past the plot's width")
        tip = [x.text or "" for x in t.iter(SVG + "title")]
        if "more" in (t.text or "") and not (tip and "the tool path is drawn to within" in tip[0]):
            problems.append(f"notes left out of the line and not in its tooltip: {t.text!r} {tip}")
    segs = [p for p in root.iter(SVG + "polyline") if p.get("class") == "path"]
    rapids = [p for p in segs if p.get("data-kind") == "rapid"]
    if any(p.get("stroke") != "#8c8c8c" or not p.get("stroke-dasharray") for p in rapids):
        problems.append("a rapid that is not thin grey and dashed")
    # the program has about 500 runs of rapids (a retract and an approach per pass) in each panel
    views = [g for g in root.iter(SVG + "g") if g.get("class") == "path-view"]
    if [v.get("data-plane") for v in views] != ["XY", "ZX", "YZ"]:
        problems.append(f"panels {[v.get('data-plane') for v in views]}, expected XY, ZX, YZ")
    first = [p for p in views[0].iter(SVG + "polyline") if p.get("data-kind") == "rapid"] if views else []
    if not 0 < len(first) <= 1000:
        problems.append(f"{len(first)} rapid elements in the XY panel: not one per run of rapids")
    legend = [g for g in root.iter(SVG + "g") if g.get("class") == "path-legend"]
    ltexts = [t.text for g in legend for t in g.iter(SVG + "text")]
    if len(legend) != 1 or "rapid (G00)" not in ltexts or "path speed (mm/s)" not in ltexts:
        problems.append(f"legend: {ltexts}")
    classes = [r for g in legend for r in g.iter(SVG + "rect") if r.get("class") == "speed-class"]
    top = ltexts[2] if len(ltexts) > 2 else ""
    if len(classes) != 8 or not top.endswith(f"- {FEEDS[-1]}"):
        problems.append(f"the feed scale should end at the fastest feed {FEEDS[-1]} mm/s: {top!r}")
    colours = feed_colours(root)
    if len(colours) < 4:
        problems.append(f"{len(colours)} feed colours for four feeds: {sorted(colours)}")
    # three planes, or the one --plot-plane picks
    prog3 = os.path.join(a.out_dir, "planes.mpf")
    with open(prog3, "w") as f:
        f.write("G00 X50\nG01 Y40 F=50\nG01 Z-10\nG01 X0 Y0 Z0\nM30\n")
    for extra, want in (([], ["XY", "ZX", "YZ"]), (["--plot-plane", "yz"], ["YZ"])):
        out = os.path.join(a.out_dir, "planes.svg")
        run([a.tool, prog3, "--summary", "--plot", out] + extra)
        got = [g.get("data-plane") for g in ET.parse(out).getroot().iter(SVG + "g") if g.get("class") == "path-view"]
        if got != want:
            problems.append(f"panels {got} with {extra}, expected {want}")
    return problems, f"100,000 blocks: {size} bytes, {len(segs)} path elements, {len(colours)} feed colours"


# ---- shots

def read_png(path):
    """(width, height, rows of RGB tuples' bytes) of an 8-bit RGB or RGBA PNG, unfiltered here."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise SystemExit(f"{path}: not a PNG")
    pos, idat = 8, b""
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    if depth != 8 or ctype not in (2, 6):
        raise SystemExit(f"{path}: PNG colour type {ctype}, depth {depth}")
    bpp = 3 if ctype == 2 else 4
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev = [], bytearray(stride)
    for y in range(h):
        ft = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        if ft == 1:
            for i in range(bpp, stride):
                line[i] = (line[i] + line[i - bpp]) & 255
        elif ft == 2:
            line = bytearray((x + p) & 255 for x, p in zip(line, prev))
        elif ft == 3:
            for i in range(stride):
                left = line[i - bpp] if i >= bpp else 0
                line[i] = (line[i] + ((left + prev[i]) >> 1)) & 255
        elif ft == 4:
            for i in range(stride):
                left = line[i - bpp] if i >= bpp else 0
                up, ul = prev[i], prev[i - bpp] if i >= bpp else 0
                pa, pb, pc = abs(up - ul), abs(left - ul), abs(left + up - 2 * ul)
                pr = left if pa <= pb and pa <= pc else up if pb <= pc else ul
                line[i] = (line[i] + pr) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, bpp, rows


def look(path):
    """What the eye needs of a screenshot: the hues present (12 sectors of 30 degrees, each on
    at least 0.02 % of the pixels) and the greyest band of 100 rows: its share of grey pixels
    (unsaturated, neither white nor black), what dashed block markers by the thousand make."""
    import colorsys
    w, h, bpp, rows = read_png(path)
    hues, n, bands = {}, 0, []
    for y0 in range(0, h, 100):
        grey = total = 0
        for y in range(y0, min(h, y0 + 100), 2):
            row = rows[y]
            for x in range(0, w, 2):
                r, g, b = row[x * bpp], row[x * bpp + 1], row[x * bpp + 2]
                n += 1
                total += 1
                if r == g == b == 255:
                    continue
                hh, ss, vv = colorsys.rgb_to_hsv(r / 255, g / 255, b / 255)
                if ss > 0.35 and vv > 0.25:
                    k = int(hh * 12) % 12
                    hues[k] = hues.get(k, 0) + 1
                elif ss < 0.12 and 0.35 < vv < 0.93:
                    grey += 1
        bands.append(grey / max(total, 1))
    return sorted(k for k, c in hues.items() if c >= n * 0.0002), max(bands), (w, h)


def chromium():
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if browser is None:
        print("chromium not installed (apt-get install chromium): browser check skipped")
        sys.exit(SKIP)
    return browser


def browse(a, url, size=None, png=None, dom=False):
    argv = [chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--no-first-run",
            f"--user-data-dir={os.path.join(a.out_dir, 'chromium-profile')}", "--virtual-time-budget=3000"]
    if size:
        argv.append(f"--window-size={size[0]},{size[1]}")
    if png:
        if os.path.exists(png):
            os.remove(png)
        argv.append(f"--screenshot={png}")
    if dom:
        argv.append("--dump-dom")
    r = subprocess.run(argv + [url], capture_output=True, text=True, timeout=150)
    if r.returncode != 0 or (png and not os.path.exists(png)):
        raise SystemExit(f"chromium exited {r.returncode} on {url}:\n{r.stderr[-2000:]}")
    return r.stdout


def case_shots(a):
    chromium()
    problems, details = [], []
    sample = os.path.join(a.out_dir, "sample.svg")
    run([a.tool, a.program, "--summary", "--plot", sample])
    report, _ = make_report(a)
    shots = [("sample plot", sample, 3, None), ("report", report, 3, (1200, 3000)),
             ("100,000-block plot", big_plot(a), 4, None)]
    for name, path, min_hues, size in shots:
        if size is None:
            root = ET.parse(path).getroot()
            size = (round(float(root.get("width"))), round(float(root.get("height"))))
        png = os.path.join(a.out_dir, os.path.splitext(os.path.basename(path))[0] + ".png")
        browse(a, "file://" + os.path.abspath(path), size, png)
        hues, grey, wh = look(png)
        details.append(f"{name}: {wh[0]}x{wh[1]}, {len(hues)} hues, greyest band {grey:.1%}")
        if len(hues) < min_hues:
            problems.append(f"{name} ({png}): {len(hues)} distinct hues {hues}, expected at least {min_hues}")
        if grey > 0.10:
            problems.append(f"{name} ({png}): a band of 100 rows is {grey:.1%} grey (banding)")
    return problems, "; ".join(details)


# ---- dom

def case_dom(a):
    chromium()
    problems = []
    path, _ = make_report(a)
    with open(path, encoding="utf-8") as f:
        page = f.read()
    main = os.path.basename(a.program)
    lines = re.findall(r'<polyline class="path" data-kind="feed" data-file="' + re.escape(main) + r'" data-line="(\d+)"',
                       page)
    if not lines:
        return [f"no feed segment of {main} carries data-line"], ""
    line = int(lines[0])
    with open(a.program, encoding="utf-8") as f:
        text = f.read().split("\n")[line - 1]
    dom = browse(a, f"file://{os.path.abspath(path)}#line={main}:{line}", (1200, 2000), dom=True)
    view = re.search(r'<div id="source-view"[^>]*>(.*?)</div>\s*<section', dom, re.S)
    if not view or f'data-line="{line}"' not in re.search(r'<div id="source-view"[^>]*>', dom).group(0):
        problems.append(f"#source-view does not show line {line} after #line={main}:{line}")
    elif html.unescape(re.sub(r"<[^>]+>", "", re.search(r'<pre class="line cur">(.*?)</pre>', view.group(1)).group(1))) \
            .strip() != f"{line}  {text}".strip():
        problems.append(f"#source-view's line is not line {line} of {main}: {view.group(1)[:300]}")
    marked = re.findall(r'<(polyline|tr)\b[^>]*class="[^"]*selected[^"]*"[^>]*>', dom)
    marked += re.findall(r'<(polyline|tr)\b[^>]*data-line="' + str(line) + r'"[^>]*class="[^"]*selected', dom)
    if "polyline" not in marked:
        problems.append(f"no path segment of line {line} is marked")
    segs = len(re.findall(r'<polyline class="path', dom))
    rows = re.findall(r'<tr data-file="[^"]*" data-line="\d+"', dom)
    if segs == 0 or not rows:
        problems.append(f"the DOM has {segs} path segments and {len(rows)} rows with data-line")
    # sorted by runs (column 1), ascending
    dom = browse(a, f"file://{os.path.abspath(path)}#sort=1", (1200, 2000), dom=True)
    body = dom[dom.find('id="profile-table"'):]
    runs = [int(x) for x in re.findall(r'<tr data-file[^>]*><td[^>]*>[^<]*</td><td class="n">(\d+)</td>', body)]
    if not runs or runs != sorted(runs) or runs == sorted(runs, reverse=True) and len(set(runs)) > 1:
        problems.append(f"#sort=1 does not order the rows by runs: {runs[:20]}")
    if 'aria-sort="ascending"' not in body[:body.find("</thead>")]:
        problems.append("the runs heading is not marked ascending")
    return problems, f"line {line} shown and marked, {segs} path segments, {len(rows)} rows sorted by runs"


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
    ap.add_argument("case", choices=["timeline", "peak", "report", "render", "scale", "shots", "dom", "docs"])
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
