#!/usr/bin/env bash
# Installs the npm packages of the VS Code extension into editors/vscode/node_modules, exactly
# as package-lock.json pins them: vscode-languageclient (the client) and, for the tests,
# vscode-textmate and vscode-oniguruma. Needs node, npm and the npm registry.
#   bash editors/vscode/setup.sh              npm ci
#   bash editors/vscode/setup.sh --if-needed  the same, only when node_modules is missing or older
#                                             than package-lock.json; without node/npm it says
#                                             so and exits 0 (the CTest test is then skipped)
set -euo pipefail
cd "$(dirname "$0")"
if_needed=0
[ "${1:-}" = "--if-needed" ] && if_needed=1
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  echo "editors/vscode: node and npm are needed for its packages (Debian: apt-get install nodejs npm)" >&2
  if [ "$if_needed" = 1 ]; then exit 0; else exit 1; fi
fi
if [ "$if_needed" = 1 ] && [ -f node_modules/.package-lock.json ] &&
   [ node_modules/.package-lock.json -nt package-lock.json ]; then
  exit 0
fi
echo "editors/vscode: npm ci"
npm ci --no-audit --no-fund
