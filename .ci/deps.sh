#!/usr/bin/env bash
# Installs what the build and the tests need, or prints the exact command when not root.
# Debian package names; sourced by .ci/test and .ci/demo.
iso_deps() {
  local pkgs=(cmake make g++ libcli11-dev nlohmann-json3-dev libfmt-dev doctest-dev python3 python3-jsonschema
              groff-base librsvg2-bin neovim libtomlplusplus-dev zsh fish)
  # node and npm for the VS Code extension's tests (any install of them will do)
  command -v node >/dev/null 2>&1 && command -v npm >/dev/null 2>&1 || pkgs+=(nodejs npm)
  local missing=()
  for p in "${pkgs[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  if [ "$(id -u)" = 0 ]; then
    echo "installing: ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq && apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null || {
      echo "error: apt-get install failed" >&2; return 1; }
  else
    echo "missing packages: ${missing[*]}" >&2
    echo "run: sudo apt-get install -y ${missing[*]}" >&2
    return 1
  fi
}

# Optional, test-only packages: a test that needs one is skipped (CTest SKIP) without it, so a
# machine whose package lists lack it, or where its install fails, still builds and passes.
#   chromium      renders the page of isosim --report (views/render)
#   clang-format  checks that every C++ file follows .clang-format (format/clang-format)
# Installed quietly, one by one; never fails.
iso_optional_deps() {
  local pkgs=(chromium clang-format) p
  for p in "${pkgs[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" && continue
    if [ "$(id -u)" != 0 ]; then
      echo "note: optional package $p is not installed (its tests are skipped): sudo apt-get install $p" >&2
      continue
    fi
    export DEBIAN_FRONTEND=noninteractive
    apt-cache show "$p" >/dev/null 2>&1 || apt-get update -qq >/dev/null 2>&1 || true
    if apt-get install -y -qq --no-install-recommends "$p" >/dev/null 2>&1; then
      echo "installed optional package: $p"
    else
      echo "note: optional package $p could not be installed: its tests are skipped" >&2
    fi
  done
  return 0
}

# The VS Code extension's npm packages (editors/vscode/node_modules), pinned by its
# package-lock.json; without node/npm the CTest test editors/vscode-grammar is skipped.
iso_node_deps() {
  bash "$(dirname "${BASH_SOURCE[0]}")/../editors/vscode/setup.sh" --if-needed ||
    echo "warning: npm ci in editors/vscode failed: editors/vscode-grammar will be skipped" >&2
}
