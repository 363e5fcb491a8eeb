#!/bin/sh
# CTest driver of the tests editors/vscode-grammar and editors/vscode-debugger: runs the
# extension's tests (all, or the files given) with Node's test runner in editors/vscode. Exits
# 77 (CTest: skipped) when node (18 or later) or the npm packages are missing;
# `bash editors/vscode/setup.sh` installs the packages. The debugger's tests need ISOSIM, the
# isosim executable; without it they are skipped.
case $0 in */*) here=${0%/*} ;; *) here=. ;; esac
cd "$here/.." || exit 1
if ! command -v node >/dev/null 2>&1; then
  echo "SKIP: node is not installed"
  exit 77
fi
if ! node -e 'process.exit(Number(process.versions.node.split(".")[0]) >= 18 ? 0 : 1)'; then
  echo "SKIP: node $(node --version) has no test runner (node 18 or later needed)"
  exit 77
fi
for m in vscode-textmate vscode-oniguruma vscode-languageclient @vscode/debugadapter-testsupport; do
  if [ ! -f "node_modules/$m/package.json" ]; then
    echo "SKIP: node_modules/$m is missing: run bash editors/vscode/setup.sh (npm ci)"
    exit 77
  fi
done
if [ $# -eq 0 ]; then set -- test/*.test.js; fi
exec node --test "$@"
