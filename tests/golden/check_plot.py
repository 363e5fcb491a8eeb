#!/usr/bin/env python3
"""isosim --plot end to end: the SVG of a sample parses as XML, draws exactly the axes that move,
has its axis labels with units and a legend, draws the tool path view (its planes, the program's
first, path segments tagged with their line, rapids dashed, start and end marks, the speed legend), and is the same bytes twice; with --render it is
also rendered to PNG by rsvg-convert (exit 77, a CTest skip, when rsvg-convert is missing).

Usage: check_plot.py --tool ISOSIM --program P.mpf --moving XYZ --out-dir DIR [--render]
"""
import argparse
import os
import shutil
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET

SVG = "{http://www.w3.org/2000/svg}"
SKIP = 77


def plot(tool, program, path):
    r = subprocess.run([tool, program, "--summary", "--plot", path], capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"isosim exited {r.returncode}:\n{r.stdout}{r.stderr}")
    with open(path, "rb") as f:
        return f.read()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tool", required=True)
    ap.add_argument("--program", required=True)
    ap.add_argument("--moving", required=True, help="the axis letters that move, in machine order")
    ap.add_argument("--out-dir", required=True)
    ap.add_argument("--render", action="store_true")
    ap.add_argument("--plane", default="XY", help="the plane the path view must show")
    ap.add_argument("--rapids", action="store_true", help="the program has G00 moves in the plane")
    a = ap.parse_args()
    if a.render and shutil.which("rsvg-convert") is None:
        print("rsvg-convert not installed (apt-get install librsvg2-bin): render check skipped")
        return SKIP
    os.makedirs(a.out_dir, exist_ok=True)
    stem = os.path.splitext(os.path.basename(a.program))[0]
    first = os.path.join(a.out_dir, stem + ".svg")
    svg = plot(a.tool, a.program, first)
    problems = []
    if plot(a.tool, a.program, os.path.join(a.out_dir, stem + "-again.svg")) != svg:
        problems.append("two runs gave different bytes")
    root = ET.fromstring(svg)  # raises on XML that is not well-formed
    if root.tag != SVG + "svg":
        problems.append(f"root element {root.tag}")
    texts = [t.text or "" for t in root.iter(SVG + "text")]
    axes = [t[len("axis "):] for t in texts if t.startswith("axis ")]
    if axes != list(a.moving):
        problems.append(f"legend axes {axes}, expected {list(a.moving)}")
    for want in ("time (s)", "position (mm", "velocity (mm/s", "block"):
        if not any(t.startswith(want) for t in texts):
            problems.append(f"no text '{want}...'")
    if not any(t.startswith(os.path.basename(a.program) + " - cycle time ") for t in texts):
        problems.append("no title with the program and its cycle time")
    curves = [p for p in root.iter(SVG + "polyline") if p.get("class") == "curve"]
    if len(curves) != 2 * len(a.moving):
        problems.append("not one curve per moving axis in each panel")
    # the tool path view: a plane, path segments (rapids dashed when there are any), start and
    # end marks, the speed legend
    # (a panel per plane whose two axes move: the program's plane first)
    views = [g for g in root.iter(SVG + "g") if g.get("class") == "path-view"]
    if not views:
        problems.append("no tool path view")
    else:
        view = views[0]
        if view.get("data-plane") != a.plane:
            problems.append(f"path view in plane {view.get('data-plane')}, expected {a.plane}")
        planes = [v.get("data-plane") for v in views]
        if len(set(planes)) != len(planes):
            problems.append(f"a plane drawn twice: {planes}")
        segs = [p for v in views for p in v.iter(SVG + "polyline") if p.get("class") == "path"]
        if any(not (p.get("data-line") or "").isdigit() or not p.get("data-file") for p in segs):
            problems.append("a path segment without data-file and data-line")
        if not segs:
            problems.append("no path segments")
        if a.rapids and not any(p.get("stroke-dasharray") for p in segs):
            problems.append("no dashed (rapid) path segment")
        if not any(p.get("stroke-dasharray") is None for p in segs):
            problems.append("no solid (feed) path segment")
        for mark in ("start", "end"):
            if not [e for e in view.iter() if e.get("class") == mark]:
                problems.append(f"no {mark} mark on the path")
        vtexts = [t.text or "" for t in view.iter(SVG + "text")]
        for want in ("path speed (mm/s)", "rapid (G00)", f"tool path, plane {a.plane}"):
            if not any(t.startswith(want) for t in vtexts):
                problems.append(f"path view: no text '{want}...'")
    if a.render:
        png = os.path.join(a.out_dir, stem + ".png")
        r = subprocess.run(["rsvg-convert", "-o", png, first], capture_output=True, text=True)
        if r.returncode != 0 or r.stderr.strip():
            problems.append(f"rsvg-convert exited {r.returncode}: {r.stderr}")
        else:
            with open(png, "rb") as f:
                head = f.read(24)
            if head[:8] != b"\x89PNG\r\n\x1a\n":
                problems.append("rsvg-convert did not write a PNG")
            else:
                w, h = struct.unpack(">II", head[16:24])
                width, height = (float(root.get(k)) for k in ("width", "height"))
                if (w, h) != (round(width), round(height)):
                    problems.append(f"PNG is {w}x{h}, the SVG {width}x{height}")
    if problems:
        print("\n".join(problems))
        return 1
    print(f"{first}: {len(a.moving)} moving axes, well-formed, deterministic" + (", rendered" if a.render else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
