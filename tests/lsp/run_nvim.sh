#!/bin/sh
# run_nvim.sh ISOLINT SCRIPT WORKDIR: runs a headless Neovim as the LSP client of `isolint --lsp`
# (tests/lsp/nvim_client.lua). Exit 77 (skipped) when nvim is not installed.
isolint=$1 script=$2 work=$3
if ! command -v nvim >/dev/null 2>&1; then
  echo "nvim is not installed: test skipped"
  exit 77
fi
rm -rf "$work" && mkdir -p "$work/prog" "$work/xdg" || exit 1
# Keep Neovim's state, logs and caches inside the build tree.
XDG_CONFIG_HOME=$work/xdg XDG_DATA_HOME=$work/xdg XDG_STATE_HOME=$work/xdg XDG_CACHE_HOME=$work/xdg \
  ISOLINT=$isolint ISO_LSP_DIR=$work/prog \
  timeout 25 nvim --headless --clean -i NONE -c "luafile $script" </dev/null
rc=$?
[ $rc -eq 124 ] && echo "nvim did not finish within 25 s"
exit $rc
