#!/usr/bin/python3
"""validate_sarif.py: check isolint's SARIF output against the SARIF 2.1.0 schema.

Usage: validate_sarif.py --schema sarif-2.1.0.json --tool path/to/isolint INPUT...

Runs `isolint --color never --format sarif INPUT` in the current directory for each INPUT,
validates the log against the OASIS SARIF 2.1.0 JSON schema with python3-jsonschema
(Debian: apt-get install python3-jsonschema) and checks what SPEC.md section 8 adds:
one run, the rules are the rule table of section 7 (id + name), every result names a rule
of that table by ruleId and ruleIndex and has a physical location with a start line and
column, and results and exit code agree (exit 1 exactly when some result is an error).
Exit 0 when every log passes, 1 otherwise (a missing jsonschema module is a failure,
not a skip: the README's install step provides it).
"""
import argparse
import json
import re
import subprocess
import sys

try:
    import jsonschema
except ImportError:
    print(f"error: the Python module 'jsonschema' is missing for {sys.executable}.\n"
          "Install it with: apt-get install python3-jsonschema (see README.md).",
          file=sys.stderr)
    sys.exit(1)

RULE_ID = re.compile(r"^[EWI][1-5][0-9][0-9]$")


def check_log(log, rc, what):
    errs = []
    runs = log.get("runs", [])
    if log.get("version") != "2.1.0":
        errs.append(f"version is {log.get('version')!r}, expected '2.1.0'")
    if len(runs) != 1:
        errs.append(f"{len(runs)} runs, expected exactly one")
        return errs
    run = runs[0]
    driver = run["tool"]["driver"]
    if driver.get("name") != "isolint":
        errs.append(f"tool.driver.name is {driver.get('name')!r}")
    rules = driver.get("rules", [])
    ids = [r.get("id") for r in rules]
    if len(rules) < 50:
        errs.append(f"only {len(rules)} rules; the rule table of SPEC section 7 has 52")
    if len(set(ids)) != len(ids):
        errs.append("duplicate rule ids")
    for r in rules:
        if not RULE_ID.match(r.get("id", "")) or not r.get("name"):
            errs.append(f"rule without a proper id and name: {r}")
    has_error = False
    for i, res in enumerate(run.get("results", [])):
        where = f"results[{i}]"
        rid, idx = res.get("ruleId"), res.get("ruleIndex")
        if rid not in ids:
            errs.append(f"{where}: ruleId {rid!r} is not in the rules")
        elif idx is not None and ids[idx] != rid:
            errs.append(f"{where}: ruleIndex {idx} is {ids[idx]!r}, not {rid!r}")
        if res.get("level") == "error":
            has_error = True
        locs = res.get("locations", [])
        if not locs:
            errs.append(f"{where}: no locations")
        for loc in locs + res.get("relatedLocations", []):
            phys = loc.get("physicalLocation", {})
            region = phys.get("region", {})
            if not phys.get("artifactLocation", {}).get("uri"):
                errs.append(f"{where}: a location without an artifact uri")
            if region.get("startLine", 0) < 1 or region.get("startColumn", 0) < 1:
                errs.append(f"{where}: a location without startLine/startColumn >= 1")
    if rc != (1 if has_error else 0):
        errs.append(f"exit code {rc}, but the log {'has' if has_error else 'has no'} error results")
    return [f"{what}: {e}" for e in errs]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--schema", required=True)
    ap.add_argument("--tool", required=True)
    ap.add_argument("inputs", nargs="+")
    a = ap.parse_args()

    with open(a.schema, encoding="utf-8") as f:
        schema = json.load(f)
    cls = jsonschema.validators.validator_for(schema)
    cls.check_schema(schema)
    validator = cls(schema, format_checker=jsonschema.FormatChecker())

    failures = []
    results = 0
    for inp in a.inputs:
        cmd = [a.tool, "--color", "never", "--format", "sarif", inp]
        p = subprocess.run(cmd, capture_output=True, timeout=60)
        what = "isolint --format sarif " + inp
        if p.returncode not in (0, 1):
            failures.append(f"{what}: exit {p.returncode}: {p.stderr.decode(errors='replace')}")
            continue
        try:
            log = json.loads(p.stdout)
        except ValueError as e:
            failures.append(f"{what}: not JSON: {e}")
            continue
        for err in sorted(validator.iter_errors(log), key=lambda e: list(e.absolute_path)):
            path = "/" + "/".join(str(x) for x in err.absolute_path)
            failures.append(f"{what}: schema: at {path}: {err.message}")
        failures += check_log(log, p.returncode, what)
        n = len(log.get("runs", [{}])[0].get("results", []))
        results += n
        print(f"ok   {what}: {n} results")

    if results == 0:
        failures.append("no input produced a result: give at least one program with diagnostics")
    for f in failures:
        print("FAIL " + f, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
