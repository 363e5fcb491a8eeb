#!/usr/bin/python3
"""validate_outputs.py: check the JSON outputs of isolint and isosim against schemas/.

Usage: validate_outputs.py --schemas DIR --bin DIR --source DIR [--known-divergences] [-v]

Runs the real tools of --bin (isolint, isocc, isosim) on real inputs of the source tree
--source and validates every JSON document they print against the JSON Schemas of --schemas
(draft 2020-12, python3-jsonschema; the $refs between the files are resolved locally):

  isolint --format json     tests/golden/isolint/diagnostics.mpf (diagnostics with notes),
                            every set of samples/ (clean), and a missing input (input_errors)
                            -> isolint.schema.json
  isosim --summary --format json, --profile --format json, --format json -o T.json
                            every .mpf of samples/*/ (main and semi-automatic programs; the
                            sets that come with a machine file also with it), a program with a
                            runtime error, one with an emergency, a z32 program, a stripped
                            image, a source program with errors (--summary only)
                            -> isosim-summary / isosim-profile / isosim-trace.schema.json
  isosim --timeline T.json  every isosim case above but the program with errors
                            -> isosim-timeline.schema.json; besides: the main track's slices
                            tile [0, cycle time] and their durations add up to cycle_time_us,
                            which is the summary's cycle_time_s in whole µs; slices nest
                            properly on every track
  isosim NEW --compare OLD --format json (also with --budget)
                            every sample with itself (no line changes), the two programs of
                            tests/golden/isosim/compare/ -> isosim-compare.schema.json
  isosim --sweep FILE --format json
                            the sweeps of tests/golden/isosim/sweeps/ that run (ok rows, and
                            errors and emergencies) -> isosim-sweep.schema.json; besides: the
                            counts match the rows, and the exit status follows them
  isosim --calibrate FILE --fit KEY --format json -o FITTED.json
                            the calibrations of tests/golden/isosim/calibration/ ->
                            isosim-calibrate.schema.json, the fitted machine -> machine.schema.json
  isosim --print-machine    the built-in machine, and every machine file of samples/ and
                            tests/golden/ that isosim accepts (the file itself and its
                            --print-machine form) -> machine.schema.json

Besides the schemas it checks what the documentation promises and a schema cannot say: the
exit status matches the status, isolint's counts match its diagnostics, the trace's and the
profile's summary equal the --summary one, trace rows have one value per column, events come
in time order and end with end/error, the profile's lines add up to the cycle time. It also
checks that the schemas reject some wrong documents (so that this test can fail), and that
every property of every schema has a description.

--known-divergences also runs the cases whose output currently differs from the documentation
(reported to be fixed; see the list KNOWN_DIVERGENCES below); they fail until fixed.

Exit 0 when everything passes, 1 otherwise (each failure on a FAIL line), 77 (skip) when the
Python module jsonschema is missing (Debian: apt-get install python3-jsonschema).
"""
import argparse
import copy
import glob
import json
import math
import os
import subprocess
import sys
import tempfile

try:
    import jsonschema
except ImportError:
    print(f"skip: the Python module 'jsonschema' is missing for {sys.executable}; "
          "install it with: apt-get install python3-jsonschema", file=sys.stderr)
    sys.exit(77)

SCHEMA_FILES = {
    "isolint": "isolint.schema.json",
    "summary": "isosim-summary.schema.json",
    "profile": "isosim-profile.schema.json",
    "trace": "isosim-trace.schema.json",
    "machine": "machine.schema.json",
    "timeline": "isosim-timeline.schema.json",
    "compare": "isosim-compare.schema.json",
    "sweep": "isosim-sweep.schema.json",
    "calibrate": "isosim-calibrate.schema.json",
}

# Cases that --known-divergences adds: outputs that differ from the documentation today.
KNOWN_DIVERGENCES = []  # both earlier ones fixed: binary files (line 0), --profile json with errors


class Checker:
    def __init__(self, args):
        self.args = args
        self.failures = []
        self.passed = 0
        self.validators = {}
        self.tmp = None

    # ---- reporting

    def fail(self, what, msg):
        self.failures.append(f"{what}: {msg}")
        print(f"FAIL {what}: {msg}", file=sys.stderr)

    def ok(self, what, detail=""):
        self.passed += 1
        if self.args.verbose or detail:
            print(f"ok   {what}" + (f" ({detail})" if detail else ""))

    # ---- schemas

    def load_schemas(self):
        docs = {}
        for key, name in SCHEMA_FILES.items():
            path = os.path.join(self.args.schemas, name)
            try:
                with open(path, encoding="utf-8") as f:
                    docs[key] = json.load(f)
            except (OSError, ValueError) as e:
                self.fail(name, f"cannot load: {e}")
                continue
        if len(docs) != len(SCHEMA_FILES):
            return False
        for key, schema in docs.items():
            name = SCHEMA_FILES[key]
            cls = jsonschema.validators.validator_for(schema)
            try:
                cls.check_schema(schema)
            except jsonschema.exceptions.SchemaError as e:
                self.fail(name, f"not a valid JSON Schema: {e.message}")
                return False
            if schema.get("$schema") != "https://json-schema.org/draft/2020-12/schema":
                self.fail(name, "$schema is not draft 2020-12")
            # a relative $id (the file name): it resolves against wherever the file is read
            # from, and the $refs between the files follow it; no address pretends to be live
            if schema.get("$id") != name or not schema.get("title"):
                self.fail(name, "needs its file name as $id and a title")
            for path in undocumented_properties(schema):
                self.fail(name, f"property without a description: {path}")
        self.validators = make_validators(docs)
        return True

    def errors(self, kind, doc):
        v = self.validators[kind]
        out = []
        for e in sorted(v.iter_errors(doc), key=lambda e: [str(x) for x in e.absolute_path]):
            path = "/" + "/".join(str(x) for x in e.absolute_path)
            out.append(f"at {path}: {e.message[:300]}")
        return out

    def validate(self, kind, doc, what):
        errs = self.errors(kind, doc)
        for e in errs[:20]:
            self.fail(what, f"{SCHEMA_FILES[kind]}: {e}")
        if len(errs) > 20:
            self.fail(what, f"... and {len(errs) - 20} more schema errors")
        return not errs

    # ---- running the tools

    def tool(self, name):
        return os.path.join(self.args.bin, name)

    def run(self, argv, cwd=None):
        try:
            p = subprocess.run(argv, cwd=cwd, capture_output=True, timeout=100)
        except (OSError, subprocess.TimeoutExpired) as e:
            return None, b"", str(e).encode()
        return p.returncode, p.stdout, p.stderr

    def run_json(self, argv, what, cwd=None, want_rc=(0,)):
        rc, out, err = self.run(argv, cwd)
        if rc is None:
            self.fail(what, f"could not run: {err.decode(errors='replace')}")
            return None, None
        if rc not in want_rc:
            self.fail(what, f"exit {rc}, expected {' or '.join(map(str, want_rc))}; stderr: "
                            f"{err.decode(errors='replace').strip()[:500]}")
        try:
            return rc, json.loads(out)
        except ValueError as e:
            self.fail(what, f"standard output is not JSON ({e}): {out[:200]!r}")
            return rc, None

    # ---- isolint

    def check_isolint(self):
        src = self.args.source
        golden = os.path.join(src, "tests", "golden", "isolint")
        lint = self.tool("isolint")
        cases = [(["diagnostics.mpf"], golden, (1,), "diagnostics"),
                 (["diagnostics.mpf", "no-such-file.mpf"], golden, (2,), "input_errors")]
        for d in sorted(glob.glob(os.path.join(src, "samples", "*", ""))):
            cases.append(([os.path.relpath(d, src)], src, (0,), "clean"))
        if True:  # formerly a known divergence: line 0 now means the whole file (isolint(1))
            bin_dir = os.path.join(self.tmp, "binary")
            os.makedirs(bin_dir, exist_ok=True)
            with open(os.path.join(bin_dir, "bin.mpf"), "wb") as f:
                f.write(b"G00 X1\0\0binary\n")
            cases.append((["bin.mpf"], bin_dir, (1,), "diagnostics"))
        for inputs, cwd, want, expect in cases:
            what = "isolint --format json " + " ".join(inputs)
            rc, doc = self.run_json([lint, "--color", "never", "--format", "json"] + inputs,
                                    what, cwd=cwd, want_rc=want)
            if doc is None:
                continue
            good = self.validate("isolint", doc, what)
            good &= self.isolint_semantics(doc, rc, expect, what)
            if good:
                d = doc.get("diagnostics", [])
                self.ok(what, f"{len(d)} diagnostics, {sum(len(x['notes']) for x in d)} notes"
                              + (f", {len(doc['input_errors'])} input errors" if "input_errors" in doc else ""))

    def isolint_semantics(self, doc, rc, expect, what):
        diags = doc.get("diagnostics", [])
        before = len(self.failures)
        counts = {s: sum(1 for d in diags if d.get("severity") == s) for s in ("error", "warning", "info")}
        for sev, key in (("error", "errors"), ("warning", "warnings"), ("info", "infos")):
            if doc.get(key) != counts[sev]:
                self.fail(what, f"{key} is {doc.get(key)}, but the list has {counts[sev]} {sev} diagnostics")
        want_rc = 2 if doc.get("input_errors") else (1 if counts["error"] else 0)
        if rc != want_rc:
            self.fail(what, f"exit {rc}, but the output says {want_rc}")
        if expect == "diagnostics" and not diags:
            self.fail(what, "no diagnostics (the test needs some)")
        if expect == "diagnostics" and "diagnostics.mpf" in what and not any(d["notes"] for d in diags):
            self.fail(what, "no diagnostic with notes (the test needs some)")
        if expect == "input_errors" and not doc.get("input_errors"):
            self.fail(what, "no input_errors for a missing input")
        if expect == "clean" and counts["error"]:
            self.fail(what, "a sample set has errors (samples/README.md: they lint clean)")
        return len(self.failures) == before

    # ---- isosim

    def sim_cases(self):
        """(label, argv after 'isosim', expected status, run the trace and profile modes)."""
        src = self.args.source
        cases = []
        with_machine = {"wait_input": ["machine.json"], "recipe_case": ["ricetta3.json"]}
        for prog in sorted(glob.glob(os.path.join(src, "samples", "*", "*.mpf"))):
            rel = os.path.relpath(prog, src)
            cases.append((rel, [prog], "ok", True))
            set_dir = os.path.dirname(prog)
            for m in with_machine.get(os.path.basename(set_dir), []):
                if is_main_program(prog):
                    cases.append((f"{rel} --machine {m}",
                                  [prog, "--machine", os.path.join(set_dir, m)], "ok", True))
        t = self.tmp
        write(t, "runtime-error.mpf", "G00 X10\nR2 = 0\nR1 = 1 / R2\nM30\n")
        write(t, "emergency.mpf", "G00 X100\nG00 X5000\nM30\n")
        write(t, "z32.mpf", "T5 M6\nS1000 M3\nG00 X10 M8\nMA-100\nM5\nM30\n")
        write(t, "program-errors.mpf", "G00 X10\nGOTOF Nowhere\nM30\n")
        write(t, "search.mpf", "G00 X10\nM23\n$aa_out[2] = 1\nHier: G00 X20\nM30\n")
        cases += [("runtime error", [os.path.join(t, "runtime-error.mpf")], "error", True),
                  ("emergency", [os.path.join(t, "emergency.mpf")], "emergency", True),
                  ("z32", [os.path.join(t, "z32.mpf"), "--dialect", "z32"], "ok", True),
                  ("z32 with special M, MA/MB, M1",
                   [os.path.join(src, "tests", "golden", "isosim", "z32-set", "main.mpf"), "--machine",
                    os.path.join(src, "tests", "golden", "isosim", "z32-machine.json")], "ok", True),
                  ("block search (a label)", [os.path.join(t, "search.mpf"), "--search", "hier"], "ok", True),
                  ("z32 block search (a line number)",
                   [os.path.join(src, "tests", "golden", "isosim", "z32-set", "main.mpf"), "--machine",
                    os.path.join(src, "tests", "golden", "isosim", "z32-machine.json"), "--search", "N50"], "ok", True),
                  ("program with errors", [os.path.join(t, "program-errors.mpf")], "error", False)]
        # A stripped image (isocc --strip): no line table.
        image = os.path.join(t, "stripped.isob")
        drilling = os.path.join(src, "samples", "drilling_when", "foratura_piastra.mpf")
        rc, _, err = self.run([self.tool("isocc"), drilling, "-o", image, "--strip"])
        if rc != 0:
            self.fail("isocc --strip", f"exit {rc}: {err.decode(errors='replace')[:300]}")
        else:
            cases.append(("stripped image", [image], "ok", True))
        return cases

    def check_isosim(self):
        sim = self.tool("isosim")
        exit_of = {"ok": 0, "error": 1, "emergency": 3}
        for label, argv, status, full in self.sim_cases():
            rc_want = (exit_of[status],)
            what = f"isosim {label} --summary --format json"
            _, summary = self.run_json([sim] + argv + ["--summary", "--format", "json"], what,
                                       cwd=self.tmp, want_rc=rc_want)
            if summary is not None and self.validate("summary", summary, what):
                if summary.get("status") != status:
                    self.fail(what, f"status {summary.get('status')!r}, expected {status!r}")
                else:
                    self.ok(what, f"{status}, cycle {summary['cycle_time_s']} s")
            self.check_profile(sim, label, argv, rc_want, summary)
            if full:
                self.check_trace(sim, label, argv, rc_want, summary)
                self.check_timeline(sim, label, argv, rc_want, summary)
        self.check_compare(sim)
        self.check_sweep(sim)
        self.check_calibrate(sim)

    def check_calibrate(self, sim):
        sdir = os.path.join(self.args.source, "tests", "golden", "isosim")
        with tempfile.TemporaryDirectory() as tmp:
            for name, keys in (("hand.csv", "axes.X.max_accel,block_time_s"),
                               ("undetermined.csv", "block_time_s,axes.Z.max_accel")):
                fitted = os.path.join(tmp, "fitted.json")
                what = f"isosim --calibrate calibration/{name} --fit {keys} --format json"
                _, doc = self.run_json([sim, "--calibrate", os.path.join("calibration", name), "--fit", keys,
                                        "--format", "json", "-o", fitted], what, cwd=sdir, want_rc=(0,))
                if doc is None or not self.validate("calibrate", doc, what):
                    continue
                with open(fitted) as f:
                    machine = json.load(f)
                if self.validate("machine", machine, what + " -o FITTED.json"):
                    self.ok(what, f"{len(doc['keys'])} keys, {len(doc['rows'])} rows, the fitted machine")

    def check_sweep(self, sim):
        sdir = os.path.join(self.args.source, "tests", "golden", "isosim")
        for name, rc_want in (("grid.toml", 0), ("hand.toml", 0), ("errors.toml", 3)):
            what = f"isosim --sweep sweeps/{name} --format json"
            rc, doc = self.run_json([sim, "--sweep", os.path.join("sweeps", name), "--format", "json"], what, cwd=sdir,
                                    want_rc=(rc_want,))
            if doc is None or not self.validate("sweep", doc, what):
                continue
            counts = {k: sum(1 for r in doc["rows"] if r["status"] == k) for k in ("ok", "error", "emergency")}
            want_rc = 3 if counts["emergency"] else 1 if counts["error"] else 0
            if any(doc[k] != n for k, n in counts.items()) or doc["runs"] != len(doc["rows"]):
                self.fail(what, f"counts {[doc[k] for k in ('runs', 'ok', 'error', 'emergency')]} do not match the rows")
            elif rc != want_rc:
                self.fail(what, f"exit {rc}, but the rows call for {want_rc}")
            else:
                self.ok(what, f"{doc['runs']} runs: {counts}")

    def check_timeline(self, sim, label, argv, rc_want, summary):
        what = f"isosim {label} --timeline T.json"
        path = os.path.join(self.tmp, "timeline.json")
        if os.path.exists(path):
            os.remove(path)
        rc, _, err = self.run([sim] + argv + ["--summary", "--timeline", path], cwd=self.tmp)
        if rc not in rc_want:
            self.fail(what, f"exit {rc}: {err.decode(errors='replace')[:300]}")
            return
        try:
            with open(path, encoding="utf-8") as f:
                doc = json.load(f)
        except (OSError, ValueError) as e:
            self.fail(what, f"no JSON file: {e}")
            return
        if not self.validate("timeline", doc, what):
            return
        before = len(self.failures)
        problems = timeline_problems(doc, summary)
        for p in problems[:10]:
            self.fail(what, p)
        if len(self.failures) == before:
            ev = doc["traceEvents"]
            tracks = {e["tid"] for e in ev if e["ph"] not in ("M", "C")}
            self.ok(what, f"{len(ev)} events on {len(tracks)} tracks, main slices add up to "
                          f"{doc['otherData']['cycle_time_us']} µs")

    def check_compare(self, sim):
        src = self.args.source
        pairs = [(p, p) for p in sorted(glob.glob(os.path.join(src, "samples", "*", "*.mpf")))
                 if is_main_program(p)]
        cdir = os.path.join(src, "tests", "golden", "isosim", "compare")
        pairs.append((os.path.join(cdir, "new.mpf"), os.path.join(cdir, "old.mpf")))
        for new, old in pairs:
            what = f"isosim {os.path.relpath(new, src)} --compare {os.path.relpath(old, src)} --format json"
            _, doc = self.run_json([sim, new, "--compare", old, "--format", "json"], what, cwd=self.tmp)
            if doc is None or not self.validate("compare", doc, what):
                continue
            before = len(self.failures)
            o, n = doc["old"]["summary"], doc["new"]["summary"]
            if abs(n["cycle_time_s"] - o["cycle_time_s"] - doc["difference_s"]) > 1.5e-6:
                self.fail(what, f"difference_s {doc['difference_s']} is not new - old")
            if new == old and (doc["lines_changed"] or doc["lines"] or doc["lines_only_old"] or doc["lines_only_new"]):
                self.fail(what, "a program compared with itself has changed lines")
            if new != old and not doc["lines"]:
                self.fail(what, "two different programs and no line changed")
            for line in doc["lines"]:
                want = (line["new"]["time_s"] if line["new"] else 0) - (line["old"]["time_s"] if line["old"] else 0)
                if abs(want - line["change_s"]) > 1.5e-6:
                    self.fail(what, f"change_s of {line['key']} is {line['change_s']}, not new - old = {want}")
            if len(self.failures) == before:
                self.ok(what, f"difference {doc['difference_s']} s, {doc['lines_changed']} lines changed")

        # --budget: the object is in the schema, and the exit status follows `exceeded`
        new, old = pairs[-1]
        for first, second, budget, rc_want, exceeded in ((new, old, "2%", 0, False), (old, new, "2%", 1, True),
                                                         (old, new, "5s", 0, False)):
            what = f"isosim {os.path.basename(first)} --compare {os.path.basename(second)} --budget {budget} --format json"
            _, doc = self.run_json([sim, first, "--compare", second, "--budget", budget, "--format", "json"], what,
                                   cwd=self.tmp, want_rc=(rc_want,))
            if doc is None or not self.validate("compare", doc, what):
                continue
            b = doc.get("budget")
            if not b or b["given"] != budget or b["exceeded"] != exceeded:
                self.fail(what, f"budget {b}, expected given {budget}, exceeded {exceeded}")
            elif budget.endswith("%") and abs(b["allowed_s"] - doc["old"]["summary"]["cycle_time_s"] * 0.02) > 1.5e-6:
                self.fail(what, f"allowed_s {b['allowed_s']} is not 2% of the old cycle time")
            else:
                self.ok(what, f"allowed {b['allowed_s']} s, exceeded {b['exceeded']}")

    def check_profile(self, sim, label, argv, rc_want, summary):
        what = f"isosim {label} --profile --format json"
        _, doc = self.run_json([sim] + argv + ["--profile", "--format", "json"], what,
                               cwd=self.tmp, want_rc=rc_want)
        if doc is None or not self.validate("profile", doc, what):
            return
        before = len(self.failures)
        if summary is not None and doc["summary"] != summary:
            self.fail(what, "its summary differs from the --summary one")
        prof = doc["profile"]
        if prof is None:  # nothing ran: only for a program with errors
            if doc["summary"].get("status") != "error":
                self.fail(what, "profile null although the program ran")
            else:
                self.ok(what, "profile null (nothing ran)")
            return
        cyc = prof["cycle_time_s"]
        if abs(round(cyc, 6) - doc["summary"]["cycle_time_s"]) > 1.5e-6:
            self.fail(what, f"profile cycle_time_s {cyc} vs summary {doc['summary']['cycle_time_s']}")
        parts = ["accel_s", "cruise_s", "decel_s", "dwell_s", "plc_s", "inputs_s", "block_s", "stop_s", "when_s"]
        lines_total = math.fsum(l["total_s"] for l in prof["lines"])
        if not close(lines_total, cyc):
            self.fail(what, f"the lines add up to {lines_total} s, not the cycle time {cyc} s")
        for row in [prof["total"]] + prof["lines"] + prof["programs"]:
            s = math.fsum(row[p] for p in parts)
            if not close(s, row["total_s"]):
                self.fail(what, f"parts add up to {s}, total_s is {row['total_s']}: {row}")
                break
        if len(self.failures) == before:
            self.ok(what, f"{len(prof['lines'])} lines, {len(prof['programs'])} programs, {len(prof['m'])} M")

    def check_trace(self, sim, label, argv, rc_want, summary):
        out = os.path.join(self.tmp, "t.json")
        if os.path.exists(out):
            os.remove(out)
        what = f"isosim {label} --format json -o t.json"
        _, stdout_summary = self.run_json([sim] + argv + ["--format", "json", "-o", out], what,
                                          cwd=self.tmp, want_rc=rc_want)
        if stdout_summary is not None:
            self.validate("summary", stdout_summary, what + " (summary on standard output)")
        try:
            with open(out, encoding="utf-8") as f:
                doc = json.load(f)
        except (OSError, ValueError) as e:
            self.fail(what, f"no JSON trace in t.json: {e}")
            return
        if not self.validate("trace", doc, what):
            return
        before = len(self.failures)
        if summary is not None and doc["summary"] != summary:
            self.fail(what, "the trace's summary differs from the --summary one")
        if stdout_summary is not None and doc["summary"] != stdout_summary:
            self.fail(what, "the trace's summary differs from the one printed on standard output")
        cols = doc["columns"]
        if cols[1:] != list(doc["summary"]["final_position"]):
            self.fail(what, f"columns {cols} and final_position {list(doc['summary']['final_position'])} "
                            "do not name the same axes in the same order")
        bad_rows = [i for i, r in enumerate(doc["samples"]) if len(r) != len(cols)]
        if bad_rows:
            self.fail(what, f"{len(bad_rows)} sample rows without one value per column (first: row {bad_rows[0]})")
        ts = [r[0] for r in doc["samples"]]
        if ts and ts[0] != 0:
            self.fail(what, f"the first sample is at t={ts[0]}, not 0")
        if any(b <= a for a, b in zip(ts, ts[1:])):
            self.fail(what, "sample times are not strictly increasing")
        ev = doc["events"]
        if any(b["t"] < a["t"] for a, b in zip(ev, ev[1:])):
            self.fail(what, "events are not in time order")
        status = doc["summary"]["status"]
        last = ev[-1]["kind"] if ev else None
        if status == "ok" and last != "end":
            self.fail(what, f"status ok but the last event is {last!r}, not 'end'")
        if status != "ok" and (last != "error" or ev[-1].get("status") != status
                               or ev[-1].get("message") != doc["summary"]["message"]):
            self.fail(what, f"status {status} but the last event is {ev[-1] if ev else None}")
        if ev and ts and abs(ev[-1]["t"] - doc["summary"]["cycle_time_s"]) > 1e-9:
            self.fail(what, f"the last event is at t={ev[-1]['t']}, the cycle time is {doc['summary']['cycle_time_s']}")
        if ts and abs(ts[-1] - doc["summary"]["cycle_time_s"]) > 1e-9:
            self.fail(what, f"the last sample is at t={ts[-1]}, not at the end {doc['summary']['cycle_time_s']}")
        if len(self.failures) == before:
            kinds = sorted({e["kind"] for e in ev})
            self.ok(what, f"{len(ts)} samples, {len(ev)} events: {' '.join(kinds)}")

    # ---- machine files

    def check_machines(self):
        sim = self.tool("isosim")
        for extra, label in (([], "built-in"), (["--dialect", "z32"], "built-in, --dialect z32")):
            what = f"isosim --print-machine ({label})"
            _, doc = self.run_json([sim, "--print-machine"] + extra, what)
            if doc is not None and self.validate("machine", doc, what):
                self.ok(what, f"{len(doc['axes'])} axes")
        src = self.args.source
        files = sorted(set(glob.glob(os.path.join(src, "samples", "**", "*.json"), recursive=True)
                           + glob.glob(os.path.join(src, "tests", "golden", "**", "*.json"), recursive=True)))
        accepted = 0
        for path in files:
            rel = os.path.relpath(path, src)
            rc, out, err = self.run([sim, "--machine", path, "--print-machine"])
            try:
                with open(path, encoding="utf-8") as f:
                    written = json.load(f)
            except (OSError, ValueError):
                written = None
            if rc != 0:
                # Not accepted by isosim: the schema should reject it as well when it can tell.
                if isinstance(written, dict) and "axes" in written and not self.errors("machine", written):
                    print(f"note {rel}: isosim rejects it ({err.decode(errors='replace').strip()}) "
                          "but the schema accepts it (a check the schema cannot express)")
                elif isinstance(written, dict) and "axes" in written:
                    self.ok(f"machine file {rel} rejected by isosim and by the schema")
                continue
            accepted += 1
            what = f"machine file {rel}"
            if written is None:
                self.fail(what, "isosim accepts it but it is not JSON for Python")
            elif self.validate("machine", written, what):
                self.ok(what)
            what = f"isosim --machine {rel} --print-machine"
            try:
                printed = json.loads(out)
            except ValueError as e:
                self.fail(what, f"not JSON: {e}")
                continue
            if self.validate("machine", printed, what):
                self.ok(what)
        if accepted == 0:
            self.fail("machine files", "no machine file accepted by isosim was found")

    # ---- the schemas must reject wrong documents

    def check_rejections(self):
        lint_doc = {"format_version": 1, "diagnostics": [
            {"file": "p.mpf", "line": 6, "column": 1, "end_line": 6, "end_column": 6,
             "severity": "error", "code": "E203", "name": "label-duplicate",
             "message": "label 'Start' is defined twice in this file",
             "notes": [{"file": "p.mpf", "line": 3, "column": 1, "message": "first defined here"}]}],
            "files": 1, "errors": 1, "warnings": 0, "infos": 0}
        summary = {"format_version": 1, "status": "ok", "cycle_time_s": 5.04,
                   "final_position": {"X": 300, "Y": 400}, "blocks": 2, "message": None, "warnings": []}
        machine = {"name": "m", "axes": [{"name": "X", "max_velocity": 400, "max_accel": 1500,
                                          "limit_minus": 0, "limit_plus": 800}]}
        trace = {"format_version": 1, "machine": "m", "columns": ["t", "X"], "samples": [[0, 0], [0.1, 1]],
                 "events": [{"t": 0, "kind": "move_start", "axis": "X", "target": 1},
                            {"t": 0.1, "kind": "future_kind", "whatever": [1]},
                            {"t": 0.1, "kind": "end"}], "summary": summary}
        profile_row = {"file": "p.mpf", "line": 1, "count": 1, "total_s": 0, "accel_s": 0, "cruise_s": 0,
                       "decel_s": 0, "dwell_s": 0, "plc_s": 0, "inputs_s": 0, "block_s": 0,
                       "stop_s": 0, "when_s": 0, "bounds": ["feed"]}
        total = {k: v for k, v in profile_row.items() if k.endswith("_s")}
        profile = {"summary": summary, "profile": {"format_version": 1, "cycle_time_s": 0, "total": total,
                                                   "lines": [profile_row], "programs": [], "m": []}}
        with_fixes = copy.deepcopy(lint_doc)
        with_fixes["diagnostics"][0]["fixes"] = [
            {"description": "remove the ':' after the label name",
             "edits": [{"line": 1, "column": 11, "end_line": 1, "end_column": 12, "replacement": ""}]}]
        z32_summary = dict(summary, spindle_on_s=1.5, tool_changes=1, tool=5)
        timeline = {"displayTimeUnit": "ms",
                    "otherData": {"format": "isosim-timeline", "format_version": 1, "program": "p.mpf",
                                  "machine": "m", "status": "ok", "cycle_time_s": 1.5, "cycle_time_us": 1500000,
                                  "events": 2, "dropped": 0},
                    "traceEvents": [
                        {"name": "thread_name", "ph": "M", "pid": 1, "tid": 1, "args": {"name": "main program"}},
                        {"name": "N10 p.mpf:1", "cat": "line", "ph": "X", "ts": 0, "dur": 1500000, "pid": 1,
                         "tid": 1, "args": {"file": "p.mpf", "line": 1, "n": 10, "limit": "feed"}},
                        {"name": "output 3 = 1", "cat": "output", "ph": "i", "s": "t", "ts": 0, "pid": 1,
                         "tid": 2, "args": {"index": 3, "value": 1, "thread": 0}}]}
        compare = {"format_version": 1, "old": {"program": "a.mpf", "summary": summary},
                   "new": {"program": "b.mpf", "summary": summary}, "difference_s": 0, "lines_matched": 1,
                   "lines_only_old": 0, "lines_only_new": 0, "lines_changed": 1,
                   "lines": [{"key": "N10", "text": "N10 G01 X1", "change_s": -0.5,
                              "old": {"file": "a.mpf", "line": 1, "count": 1, "time_s": 1},
                              "new": {"file": "b.mpf", "line": 1, "count": 1, "time_s": 0.5}}]}
        sweep = {"format_version": 1, "sweep": "s.toml", "runs": 2, "ok": 1, "error": 0, "emergency": 1,
                 "rows": [{"program": "a.mpf", "variant": "axes.X.max_accel=2000", "values": {"axes.X.max_accel": 2000},
                           "status": "ok", "cycle_time_s": 1.5, "blocks": 3, "spindle_on_s": 0, "tool_changes": 0,
                           "warnings": 0, "message": None},
                          {"program": "a.mpf", "variant": "axes.X.max_accel=3000", "values": {"axes.X.max_accel": 3000},
                           "status": "emergency", "cycle_time_s": 0, "blocks": 1, "spindle_on_s": 0,
                           "tool_changes": 0, "warnings": 0, "message": "a.mpf:1: emergency at t=0 s: soft limit"}]}
        calibrate = {"format_version": 1, "calibration": "m.csv", "machine": None, "output": "fitted.json",
                     "iterations": 3, "converged": True,
                     "keys": [{"key": "block_time_s", "start": 0, "fitted": 0.01, "determined": True}],
                     "rows": [{"program": "a.mpf", "measured_s": 1.02, "model_s": 1.02, "residual_s": 0,
                               "residual_pct": 0}],
                     "rms_s": 0, "rms_pct": 0, "warnings": []}
        z32_machine = dict(machine, dialect="z32", special_m={"40": "PALLET", "6": "CAMBIO"},
                           optional_stop=True, aux_duration_s=0.1)
        # Documents that must pass (so that the rejections below are not vacuous).
        for kind, doc, what in (("isolint", lint_doc, "a minimal isolint output"),
                                ("isolint", with_fixes, "a diagnostic with the optional fixes"),
                                ("summary", summary, "a minimal summary"),
                                ("summary", z32_summary, "a z32 summary"),
                                ("machine", machine, "a minimal machine"),
                                ("machine", z32_machine, "a z32 machine"),
                                ("trace", trace, "a trace with a future event kind"),
                                ("profile", profile, "a minimal profile"),
                                ("timeline", timeline, "a minimal timeline"),
                                ("compare", compare, "a minimal comparison"),
                                ("sweep", sweep, "a sweep with an ok and an emergency row"),
                                ("calibrate", calibrate, "a minimal calibration")):
            errs = self.errors(kind, doc)
            if errs:
                self.fail(f"accept {what}", f"{SCHEMA_FILES[kind]} rejects it: {errs[0]}")
            else:
                self.ok(f"{SCHEMA_FILES[kind]} accepts {what}")

        def mutate(doc, fn):
            d = copy.deepcopy(doc)
            fn(d)
            return d

        wrong = [
            ("calibrate", "a calibration without keys", mutate(calibrate, lambda d: d.update(keys=[]))),
            ("calibrate", "a measured time of 0", mutate(calibrate, lambda d: d["rows"][0].update(measured_s=0))),
            ("calibrate", "a key without determined", mutate(calibrate, lambda d: d["keys"][0].pop("determined"))),
            ("isolint", "a diagnostic with severity fatal",
             mutate(lint_doc, lambda d: d["diagnostics"][0].update(severity="fatal"))),
            ("isolint", "a code X123", mutate(lint_doc, lambda d: d["diagnostics"][0].update(code="X123"))),
            ("isolint", "an E code with severity warning",
             mutate(lint_doc, lambda d: d["diagnostics"][0].update(severity="warning"))),
            ("isolint", "a diagnostic without notes", mutate(lint_doc, lambda d: d["diagnostics"][0].pop("notes"))),
            ("isolint", "a negative count", mutate(lint_doc, lambda d: d.update(errors=-1))),
            ("isolint", "a fix without edits",
             mutate(with_fixes, lambda d: d["diagnostics"][0]["fixes"][0].update(edits=[]))),
            ("isolint", "a fix edit without replacement",
             mutate(with_fixes, lambda d: d["diagnostics"][0]["fixes"][0]["edits"][0].pop("replacement"))),
            ("isolint", "an empty fixes array", mutate(with_fixes, lambda d: d["diagnostics"][0].update(fixes=[]))),
            ("isolint", "format_version 2", mutate(lint_doc, lambda d: d.update(format_version=2))),
            ("isolint", "an unknown top-level key", mutate(lint_doc, lambda d: d.update(fatal=0))),
            ("summary", "a summary without status", mutate(summary, lambda d: d.pop("status"))),
            ("summary", "status crashed", mutate(summary, lambda d: d.update(status="crashed"))),
            ("summary", "status ok with a message", mutate(summary, lambda d: d.update(message="x.mpf:1: oops"))),
            ("summary", "status error with message null", mutate(summary, lambda d: d.update(status="error"))),
            ("summary", "a position that is a string",
             mutate(summary, lambda d: d["final_position"].update(X="300"))),
            ("machine", "a machine with an unknown key", mutate(machine, lambda d: d.update(max_speed=3))),
            ("machine", "an axis named XX", mutate(machine, lambda d: d["axes"][0].update(name="XX"))),
            ("machine", "an axis named G", mutate(machine, lambda d: d["axes"][0].update(name="G"))),
            ("machine", "an axis named S in z32",
             mutate(machine, lambda d: (d.update(dialect="z32"), d["axes"][0].update(name="S")))),
            ("machine", "max_velocity 0", mutate(machine, lambda d: d["axes"][0].update(max_velocity=0))),
            ("machine", "no axes", mutate(machine, lambda d: d.pop("axes"))),
            ("machine", "ten axes", mutate(machine, lambda d: d.update(axes=d["axes"] * 10))),
            ("machine", "an M sequence key that is not a number",
             mutate(machine, lambda d: d.update(m_sequences={"M23": {"duration_s": 1}}))),
            ("machine", "an input step of 2", mutate(machine, lambda d: d.update(inputs={"3": [[0, 2]]}))),
            ("machine", "r_preset R0", mutate(machine, lambda d: d.update(r_preset={"0": 1}))),
            ("machine", "special M 30", mutate(z32_machine, lambda d: d.update(special_m={"30": "FINE"}))),
            ("trace", "a move_start without axis",
             mutate(trace, lambda d: d["events"][0].pop("axis"))),
            ("trace", "an event without t", mutate(trace, lambda d: d["events"][1].pop("t"))),
            ("trace", "an event without kind", mutate(trace, lambda d: d["events"][1].pop("kind"))),
            ("trace", "columns not starting with t", mutate(trace, lambda d: d.update(columns=["X", "t"]))),
            ("trace", "a summary without status", mutate(trace, lambda d: d["summary"].pop("status"))),
            ("profile", "a profile line with an unknown key",
             mutate(profile, lambda d: d["profile"]["lines"][0].update(idle_s=0))),
            ("profile", "a profile line without when_s",
             mutate(profile, lambda d: d["profile"]["lines"][0].pop("when_s"))),
            ("profile", "a summary without status", mutate(profile, lambda d: d["summary"].pop("status"))),
            ("profile", "a bound 'slow'", mutate(profile, lambda d: d["profile"]["lines"][0].update(bounds=["slow"]))),
            ("timeline", "a slice without dur", mutate(timeline, lambda d: d["traceEvents"][1].pop("dur"))),
            ("timeline", "a slice at a negative time", mutate(timeline, lambda d: d["traceEvents"][1].update(ts=-1))),
            ("timeline", "a time in seconds (not whole µs)",
             mutate(timeline, lambda d: d["traceEvents"][1].update(dur=1.5))),
            ("timeline", "an instant on an axis track", mutate(timeline, lambda d: d["traceEvents"][2].update(tid=10))),
            ("timeline", "no otherData", mutate(timeline, lambda d: d.pop("otherData"))),
            ("compare", "a comparison without difference_s", mutate(compare, lambda d: d.pop("difference_s"))),
            ("compare", "a line without its old side", mutate(compare, lambda d: d["lines"][0].pop("old"))),
            ("sweep", "an ok row with a message", mutate(sweep, lambda d: d["rows"][0].update(message="x"))),
            ("sweep", "an emergency row without a message", mutate(sweep, lambda d: d["rows"][1].update(message=None))),
            ("sweep", "a row without values", mutate(sweep, lambda d: d["rows"][0].pop("values"))),
            ("sweep", "a value that is an array",
             mutate(sweep, lambda d: d["rows"][0]["values"].update({"axes.X.max_accel": [1]}))),
        ]
        for kind, what, doc in wrong:
            if self.errors(kind, doc):
                self.ok(f"{SCHEMA_FILES[kind]} rejects {what}")
            else:
                self.fail(f"{SCHEMA_FILES[kind]} must reject {what}", "it accepts it")

    def main(self):
        for name in ("isolint", "isocc", "isosim"):
            if not os.access(self.tool(name), os.X_OK):
                self.fail(name, f"not found or not executable in {self.args.bin}")
        if self.failures or not self.load_schemas():
            return 1
        with tempfile.TemporaryDirectory(prefix="isotools-schemas-") as tmp:
            self.tmp = tmp
            self.check_rejections()
            self.check_isolint()
            self.check_isosim()
            self.check_machines()
        if self.args.known_divergences:
            print("known divergences checked:\n  " + "\n  ".join(KNOWN_DIVERGENCES))
        print(f"{self.passed} checks passed, {len(self.failures)} failed")
        return 1 if self.failures else 0


def make_validators(docs):
    """One validator per schema, resolving $refs between the files of the directory by $id."""
    validators = {}
    try:
        from referencing import Registry, Resource
        from referencing.jsonschema import DRAFT202012
        registry = Registry().with_resources(
            (s["$id"], Resource.from_contents(s, default_specification=DRAFT202012)) for s in docs.values())
        for key, schema in docs.items():
            cls = jsonschema.validators.validator_for(schema)
            validators[key] = cls(schema, registry=registry)
    except ImportError:  # jsonschema < 4.18: RefResolver with a store
        store = {s["$id"]: s for s in docs.values()}
        for key, schema in docs.items():
            cls = jsonschema.validators.validator_for(schema)
            resolver = jsonschema.RefResolver(base_uri=schema["$id"], referrer=schema, store=store)
            validators[key] = cls(schema, resolver=resolver)
    return validators


def undocumented_properties(schema, path="#", refinement=False):
    """JSON pointers of the properties that have no description. Properties inside if/then/
    else/not only restate a constraint on a property declared (and described) elsewhere."""
    out = []
    if isinstance(schema, dict):
        for key, value in schema.items():
            if key == "properties" and isinstance(value, dict) and not refinement:
                for name, sub in value.items():
                    if isinstance(sub, dict) and "description" not in sub:
                        out.append(f"{path}/properties/{name}")
            out += undocumented_properties(value, f"{path}/{key}",
                                           refinement or key in ("if", "then", "else", "not"))
    elif isinstance(schema, list):
        for i, value in enumerate(schema):
            out += undocumented_properties(value, f"{path}/{i}", refinement)
    return out


def is_main_program(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            s = line.strip()
            if not s or s.startswith(";") or s.startswith("("):
                continue
            return not s.upper().startswith("SEMI")
    return True


def timeline_problems(doc, summary):
    """What a schema cannot say about a timeline: the main track tiles the run, its durations
    add up to the cycle time exactly, slices nest on every track, cycle_time_us is the µs of
    the summary's cycle_time_s."""
    out = []
    od = doc["otherData"]
    cyc_us = od["cycle_time_us"]
    if summary is not None and cyc_us != round(summary["cycle_time_s"] * 1_000_000):
        out.append(f"cycle_time_us {cyc_us} is not the summary's {summary['cycle_time_s']} s")
    if summary is not None and od["status"] != summary["status"]:
        out.append(f"status {od['status']} is not the summary's {summary['status']}")
    ev = [e for e in doc["traceEvents"] if e["ph"] not in ("M", "C")]
    counters = [e for e in doc["traceEvents"] if e["ph"] == "C"]
    if od.get("counter_values") != len(counters):
        out.append(f"otherData.counter_values is {od.get('counter_values')}, the document has {len(counters)}")
    main = [e for e in ev if e["ph"] == "X" and e["tid"] == 1]
    if not main:
        out.append("no slice on the main track")
        return out
    if sum(e["dur"] for e in main) != cyc_us:
        out.append(f"the main slices add up to {sum(e['dur'] for e in main)} µs, not {cyc_us}")
    if main[0]["ts"] != 0:
        out.append(f"the main track starts at {main[0]['ts']} µs, not 0")
    for a, b in zip(main, main[1:]):
        if a["ts"] + a["dur"] != b["ts"]:
            out.append(f"main slices do not tile: {a['name']} ends at {a['ts'] + a['dur']}, {b['name']} starts at {b['ts']}")
            break
    if od["events"] != len(ev):
        out.append(f"otherData.events is {od['events']}, the document has {len(ev)}")
    names = {e["tid"]: e["args"]["name"] for e in doc["traceEvents"] if e["name"] == "thread_name"}
    for tid in sorted({e["tid"] for e in ev}):
        if tid not in names:
            out.append(f"track {tid} has no name")
        stack = []
        for e in sorted((e for e in ev if e["tid"] == tid and e["ph"] == "X"), key=lambda e: (e["ts"], -e["dur"])):
            while stack and stack[-1] <= e["ts"] and not (stack[-1] == e["ts"] and e["dur"] == 0):
                stack.pop()
            if stack and e["ts"] + e["dur"] > stack[-1]:
                out.append(f"track {names.get(tid)}: {e['name']} at {e['ts']} overlaps the slice it starts in")
                break
            stack.append(e["ts"] + e["dur"])
        if any(e["ts"] > cyc_us or e["ts"] + e.get("dur", 0) > cyc_us for e in ev if e["tid"] == tid):
            out.append(f"track {names.get(tid)}: an event past the end of the run")
    return out


def write(directory, name, text):
    with open(os.path.join(directory, name), "w", encoding="utf-8") as f:
        f.write(text)


def close(a, b):
    return abs(a - b) <= 1e-9 * max(1.0, abs(a), abs(b))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--schemas", required=True, help="the directory of the *.schema.json files")
    ap.add_argument("--bin", required=True, help="the directory of isolint, isocc and isosim")
    ap.add_argument("--source", required=True, help="the source tree (samples/, tests/golden/)")
    ap.add_argument("--known-divergences", action="store_true",
                    help="also run the cases whose output differs from the documentation today")
    ap.add_argument("-v", "--verbose", action="store_true", help="print every passing check")
    args = ap.parse_args()
    for name in ("schemas", "bin", "source"):
        setattr(args, name, os.path.abspath(getattr(args, name)))
    return Checker(args).main()


if __name__ == "__main__":
    sys.exit(main())
