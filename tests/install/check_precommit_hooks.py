#!/usr/bin/env python3
"""install/pre-commit-hooks: .pre-commit-hooks.yaml is a list of hooks with the keys pre-commit
requires (id, name, entry, language), the isolint, isofmt (-i) and isofmt-check (--check)
hooks run the installed tools, and each one's `files` pattern (a Python regular expression, as pre-commit reads it) selects program files.

Reads the file with PyYAML when it is there, else with a small parser of the subset the file
uses (a block list of mappings of plain or quoted scalars).

Usage: check_precommit_hooks.py .pre-commit-hooks.yaml
"""
import re
import sys

REQUIRED = ("id", "name", "entry", "language")
LANGUAGES = {"system", "script", "python", "node", "docker", "docker_image", "fail", "golang", "rust",
             "conda", "coursier", "dart", "dotnet", "haskell", "julia", "lua", "perl", "r", "ruby", "swift",
             "pygrep", "unsupported", "unsupported_script"}


def scalar(text, where):
    text = text.strip()
    if text.startswith("'"):
        if len(text) < 2 or not text.endswith("'"):
            raise ValueError(f"{where}: unterminated single-quoted scalar")
        return text[1:-1].replace("''", "'")
    if text.startswith('"'):
        if len(text) < 2 or not text.endswith('"') or "\\" in text:
            raise ValueError(f"{where}: double-quoted scalar this parser does not read")
        return text[1:-1]
    if " #" in text:
        text = text[:text.index(" #")].rstrip()
    return text


def parse_subset(text):
    hooks = []
    for number, line in enumerate(text.splitlines(), 1):
        where = f"line {number}"
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        if line.startswith("- "):
            hooks.append({})
            line = "  " + line[2:]
        if not hooks or not line.startswith("  ") or line.startswith("   "):
            raise ValueError(f"{where}: not a list of mappings: {line!r}")
        key, sep, value = line.strip().partition(":")
        if not sep or not re.fullmatch(r"[a-z_]+", key):
            raise ValueError(f"{where}: not 'key: value': {line!r}")
        if key in hooks[-1]:
            raise ValueError(f"{where}: duplicate key {key}")
        hooks[-1][key] = scalar(value, where)
    return hooks


def load(path):
    text = open(path, encoding="utf-8").read()
    try:
        import yaml
    except ImportError:
        return parse_subset(text), "the subset parser"
    hooks = yaml.safe_load(text)
    # Keep the fallback honest: where both read the file, they must agree.
    if parse_subset(text) != hooks:
        raise ValueError("the subset parser reads the file otherwise than PyYAML")
    return hooks, "PyYAML and the subset parser"


def main():
    path = sys.argv[1]
    try:
        hooks, reader = load(path)
    except Exception as e:  # a YAML error of either reader
        print(f"{path}: does not parse: {e}")
        return 1
    problems = []
    if not isinstance(hooks, list) or not hooks:
        print(f"{path}: not a non-empty list of hooks")
        return 1
    ids = set()
    for i, hook in enumerate(hooks):
        if not isinstance(hook, dict):
            problems.append(f"hook {i}: not a mapping")
            continue
        for key in REQUIRED:
            if not isinstance(hook.get(key), str) or not hook[key]:
                problems.append(f"hook {i}: no '{key}'")
        if hook.get("language") not in LANGUAGES:
            problems.append(f"hook {i}: unknown language {hook.get('language')!r}")
        if hook.get("id") in ids:
            problems.append(f"hook {i}: id {hook.get('id')} twice")
        ids.add(hook.get("id"))
    expected = {"isolint": "isolint", "isofmt": "isofmt -i", "isofmt-check": "isofmt --check"}
    for hook_id, entry in expected.items():
        hook = next((h for h in hooks if isinstance(h, dict) and h.get("id") == hook_id), None)
        if hook is None:
            problems.append(f"no hook with id {hook_id}")
            continue
        if hook.get("entry") != entry or hook.get("language") != "system":
            problems.append(f"the {hook_id} hook must run the installed tool (entry: {entry}, language: system)")
        try:
            files = re.compile(hook.get("files", ""))
        except re.error as e:
            problems.append(f"the {hook_id} hook's files is not a regular expression: {e}")
            continue
        for name in ("a.mpf", "sub/dir/B.SPF", "x.spf", "PALLET.MPF"):
            if not files.search(name):
                problems.append(f"{hook_id}: files does not select {name}")
        for name in ("a.txt", "a.mpf.bak", "mpf", "notes.md", "a.isob"):
            if files.search(name):
                problems.append(f"{hook_id}: files selects {name}")
    if problems:
        print("\n".join(f"{path}: {p}" for p in problems))
        return 1
    print(f"{path}: {len(hooks)} hook(s) with the required keys (read with {reader})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
