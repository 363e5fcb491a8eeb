#!/usr/bin/env python3
"""isosim --sweep-jobs end to end: the commands it prints, run by GNU parallel (parallel -k keeps
their order), give the cycle times and statuses of the --sweep table, row for row (exit 77, a CTest
skip, when parallel is not installed).

Usage: check_sweep_parallel.py --tool ISOSIM --sweep FILE.toml --work-dir DIR --out-dir DIR
"""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys

SKIP = 77


def run(cmd, cwd, env=None, stdin=None):
    r = subprocess.run(cmd, cwd=cwd, env=env, input=stdin, capture_output=True, text=True)
    return r


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tool", required=True)
    ap.add_argument("--sweep", required=True, help="the sweep file, relative to --work-dir")
    ap.add_argument("--work-dir", required=True)
    ap.add_argument("--out-dir", required=True)
    a = ap.parse_args()
    a.tool = os.path.abspath(a.tool)
    if shutil.which("parallel") is None:
        print("GNU parallel not installed (apt-get install parallel): --sweep-jobs check skipped")
        return SKIP
    os.makedirs(a.out_dir, exist_ok=True)
    table = os.path.join(os.path.abspath(a.out_dir), "sweep.csv")
    r = run([a.tool, "--sweep", a.sweep, "-j", "2", "-o", table], a.work_dir)
    if r.returncode != 0:
        raise SystemExit(f"isosim --sweep exited {r.returncode}:\n{r.stdout}{r.stderr}")
    with open(table, newline="") as f:
        rows = list(csv.DictReader(f))
    r = run([a.tool, "--sweep", a.sweep, "--sweep-jobs"], a.work_dir)
    if r.returncode != 0:
        raise SystemExit(f"isosim --sweep-jobs exited {r.returncode}:\n{r.stdout}{r.stderr}")
    jobs = r.stdout.splitlines()
    if len(jobs) != len(rows) or not all(j.startswith("isosim ") for j in jobs):
        raise SystemExit(f"{len(jobs)} commands for {len(rows)} rows:\n{r.stdout}")
    # the commands name the tool as isosim: this build's comes first on PATH
    env = dict(os.environ, PATH=os.path.dirname(os.path.abspath(a.tool)) + os.pathsep + os.environ.get("PATH", ""))
    p = run(["parallel", "--will-cite", "-k", "-j", "2"], a.work_dir, env, r.stdout)
    if p.returncode != 0:
        raise SystemExit(f"parallel exited {p.returncode}:\n{p.stdout}{p.stderr}")
    summaries, text, at = [], p.stdout, 0
    decoder = json.JSONDecoder()
    while at < len(text):
        if text[at].isspace():
            at += 1
            continue
        value, at = decoder.raw_decode(text, at)
        summaries.append(value)
    if len(summaries) != len(rows):
        raise SystemExit(f"parallel printed {len(summaries)} summaries for {len(rows)} rows:\n{p.stdout}")
    failures = 0
    for job, row, s in zip(jobs, rows, summaries):
        cycle = json.dumps(s["cycle_time_s"])
        if s["status"] != row["status"] or float(cycle) != float(row["cycle_time_s"]) or s["blocks"] != int(row["blocks"]):
            print(f"{job}\n  summary: {s['status']} {cycle} s, {s['blocks']} blocks;"
                  f" table: {row['status']} {row['cycle_time_s']} s, {row['blocks']} blocks")
            failures += 1
    if failures:
        return 1
    print(f"{len(rows)} runs: the commands run by parallel give the table's cycle times")
    return 0


if __name__ == "__main__":
    sys.exit(main())
