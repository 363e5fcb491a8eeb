#!/usr/bin/env bash
# Installs what the build and the tests need, or prints the exact command when not root.
# Debian package names; sourced by .ci/test and .ci/demo.
iso_deps() {
  local pkgs=(cmake make g++ libcli11-dev nlohmann-json3-dev libfmt-dev doctest-dev python3 python3-jsonschema
              groff-base librsvg2-bin)
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
