#!/bin/sh
# CTest driver of the test editors/vscode-grammar: runs the extension's tests with Node's test
# runner in editors/vscode. Exits 77 (CTest: skipped) when node (18 or later) or the npm
# packages are missing; `bash editors/vscode/setup.sh` installs the packages.
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
for m in vscode-textmate vscode-oniguruma vscode-languageclient; do
  if [ ! -f "node_modules/$m/package.json" ]; then
    echo "SKIP: node_modules/$m is missing: run bash editors/vscode/setup.sh (npm ci)"
    exit 77
  fi
done
exec node --test test/*.test.js
