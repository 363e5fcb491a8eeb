#!/usr/bin/env python3
"""bench/lsp_latency.py: how long the language server takes to answer an edit, beside the
command line's full check of the same file, in one run.

For each size (lines of a generated SIDAC program, bench/gen_program.py, alone in its folder):
  - cli: `isolint FILE --format json` (the median of 3 runs), the full check an edit is measured
    against;
  - open: didOpen to its publishDiagnostics;
  - edit start/middle/end: the median, over EDITS one-character edits (a blank added at the end
    of a line, then taken away again) near the start, the middle and the end of the file, of
    the time from didChange to the publishDiagnostics of that version;
  - enter and label, in the middle of the file: a line end added (Enter) and taken away, and
    a digit added to a label's name and taken away: edits that change what the whole-file
    passes read (the median over EDITS of each);
  - memory: the server's resident memory after the open minus before (after a small document
    was opened and closed, so that the server's own code and buffers are not counted), over the
    file's size.
The dry runs of the cycle time are off (initializationOptions), so that only checking is
measured. Ratios are printed against the reference of the same run; nothing is asserted.

Usage: bench/lsp_latency.py [--sizes 10000,100000,1200000] [--edits 20] [--build BUILD_DIR]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def frame(msg):
    body = json.dumps(msg).encode()
    return b"Content-Length: %d\r\n\r\n" % len(body) + body


class Lsp:
    def __init__(self, isolint):
        self.p = subprocess.Popen([isolint, "--lsp"], stdin=subprocess.PIPE, stdout=subprocess.PIPE)
        self.id = 0

    def send(self, msg):
        self.p.stdin.write(frame(msg))
        self.p.stdin.flush()

    def read(self):
        n = None
        while True:
            line = self.p.stdout.readline()
            if not line:
                raise EOFError("the server ended")
            line = line.strip()
            if not line:
                break
            k, v = line.split(b":", 1)
            if k.strip().lower() == b"content-length":
                n = int(v)
        return json.loads(self.p.stdout.read(n))

    def request(self, method, params):
        self.id += 1
        self.send({"jsonrpc": "2.0", "id": self.id, "method": method, "params": params})
        while True:
            m = self.read()
            if m.get("id") == self.id and "method" not in m:
                return m

    def notify(self, method, params):
        self.send({"jsonrpc": "2.0", "method": method, "params": params})

    def diagnostics_of(self, version):
        while True:
            m = self.read()
            if m.get("method") == "textDocument/publishDiagnostics" and m["params"].get("version") == version:
                return m

    def rss_kb(self):
        for line in open("/proc/%d/status" % self.p.pid):
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
        return 0


def cli_seconds(isolint, path):
    times = []
    for _ in range(3):
        t = time.perf_counter()
        subprocess.run([isolint, path, "--format", "json"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def measure(isolint, lines, edits, work):
    folder = os.path.join(work, "p%d" % lines)
    os.makedirs(folder)
    path = os.path.join(folder, "cam.mpf")
    subprocess.run([sys.executable, os.path.join(HERE, "gen_program.py"), str(lines), path], check=True,
                   stdout=subprocess.DEVNULL)
    text = open(path, encoding="utf-8").read()
    cli = cli_seconds(isolint, path)
    s = Lsp(isolint)
    s.request("initialize", {"capabilities": {}, "initializationOptions": {"cycleTime": {"enabled": False}}})
    s.notify("initialized", {})
    # a small document opened and closed first: the server's code and buffers are then in
    # memory, and what the measured open adds is the document's own
    warm = os.path.join(work, "warm%d" % lines)
    os.makedirs(warm)
    wpath = os.path.join(warm, "w.mpf")
    with open(wpath, "w") as f:
        f.write("G01 X1 F100\nM30\n")
    s.notify("textDocument/didOpen", {"textDocument": {"uri": "file://" + wpath, "languageId": "iso", "version": 1,
                                                       "text": open(wpath).read()}})
    s.diagnostics_of(1)
    s.notify("textDocument/didClose", {"textDocument": {"uri": "file://" + wpath}})
    before = s.rss_kb()
    uri = "file://" + path
    t = time.perf_counter()
    s.notify("textDocument/didOpen", {"textDocument": {"uri": uri, "languageId": "iso", "version": 1, "text": text}})
    s.diagnostics_of(1)
    opened = time.perf_counter() - t
    rss = s.rss_kb() - before
    rows = text.split("\n")
    version = 1
    out = {"lines": lines, "bytes": len(text.encode()), "cli": cli, "open": opened, "rss_kb": rss}
    for name, line in (("start", 5), ("middle", len(rows) // 2), ("end", len(rows) - 3)):
        col = len(rows[line].encode("utf-16-le")) // 2
        samples = []
        for k in range(edits):
            version += 1
            add = k % 2 == 0  # a blank at the end of the line, then taken away
            rng = {"start": {"line": line, "character": col if add else col},
                   "end": {"line": line, "character": col if add else col + 1}}
            t = time.perf_counter()
            s.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": version},
                                                "contentChanges": [{"range": rng, "text": " " if add else ""}]})
            s.diagnostics_of(version)
            samples.append(time.perf_counter() - t)
        out[name] = statistics.median(samples)
    # edits that change what the whole-file passes read, in the middle: a line end added at the
    # end of a line (Enter) and taken away again; a digit added to a label's name and taken away
    mid = len(rows) // 2
    label = next(k for k in range(mid, len(rows)) if rows[k].startswith("L") and ":" in rows[k])
    for name, line, col, piece in (("enter", mid, len(rows[mid].encode("utf-16-le")) // 2, "\n"),
                                   ("label", label, rows[label].index(":"), "9")):
        samples = []
        for k in range(edits):
            version += 1
            add = k % 2 == 0
            end = {"line": line, "character": col} if add else (
                {"line": line + 1, "character": 0} if piece == "\n" else {"line": line, "character": col + 1})
            t = time.perf_counter()
            s.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": version}, "contentChanges": [
                {"range": {"start": {"line": line, "character": col}, "end": end}, "text": piece if add else ""}]})
            s.diagnostics_of(version)
            samples.append(time.perf_counter() - t)
        out[name] = statistics.median(samples)
    s.request("shutdown", None)
    s.notify("exit", None)
    s.p.wait(30)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", default="10000,100000,1200000")
    ap.add_argument("--edits", type=int, default=20)
    ap.add_argument("--build", default=os.path.join(HERE, "..", "build"))
    a = ap.parse_args()
    isolint = os.path.join(a.build, "tools", "isolint")
    results = []
    with tempfile.TemporaryDirectory() as work:
        for n in (int(x) for x in a.sizes.split(",")):
            results.append(measure(isolint, n, a.edits, work))
    print("%9s %9s %9s %9s %9s %9s %9s %8s %8s" % ("lines", "MB", "cli_s", "open_s", "start_s", "middle_s",
                                                  "end_s", "edit/cli", "mem/file"))
    for r in results:
        worst = max(r["start"], r["middle"], r["end"])
        print("%9d %9.1f %9.4f %9.4f %9.4f %9.4f %9.4f %7.3fx %7.1fx" % (
            r["lines"], r["bytes"] / 1e6, r["cli"], r["open"], r["start"], r["middle"], r["end"], worst / r["cli"],
            r["rss_kb"] * 1024 / r["bytes"]))
    print("edits that change what the whole-file passes read (the middle of the file):")
    print("%9s %9s %9s %9s %9s" % ("lines", "enter_s", "label_s", "enter/cli", "label/cli"))
    for r in results:
        print("%9d %9.4f %9.4f %8.3fx %8.3fx" % (r["lines"], r["enter"], r["label"], r["enter"] / r["cli"],
                                                 r["label"] / r["cli"]))
    if len(results) > 1:
        small, big = results[0], results[-1]
        flat = max(big["start"], big["middle"], big["end"]) / max(small["start"], small["middle"], small["end"])
        print("edit latency at %d lines over %d lines: %.1fx" % (big["lines"], small["lines"], flat))
    print("goals (one run): edit/cli <= 0.15x at 100k lines, <= 0.05x at 1.2M; the latency at 1.2M <= 3x the "
          "latency at 10k; memory <= 5x the file")


if __name__ == "__main__":
    main()
