#!/bin/sh
# readme_nvim.sh ISOLINT README WORKDIR: runs the Neovim snippet of README.md (between the
# nvim-snippet markers) as the init file of a headless Neovim, opens a program with an error
# and waits for isolint's diagnostic. Exit 77 (skipped) when nvim is not installed.
isolint=$1 readme=$2 work=$3
if ! command -v nvim >/dev/null 2>&1; then
  echo "nvim is not installed: test skipped"
  exit 77
fi
rm -rf "$work" && mkdir -p "$work/bin" "$work/prog" "$work/xdg" || exit 1
ln -s "$isolint" "$work/bin/isolint" || exit 1 # the snippet runs 'isolint' from the PATH
sed -n '/<!-- nvim-snippet -->/,/<!-- \/nvim-snippet -->/p' "$readme" | sed '1,2d;$d' | sed '$d' > "$work/init.lua"
[ -s "$work/init.lua" ] || { echo "no nvim-snippet block in $readme"; exit 1; }
printf 'G01 X10 F100\nG07 X5\nM30\n' > "$work/prog/p.mpf"
cat > "$work/check.lua" <<'LUA'
local ok = vim.wait(15000, function() return #vim.diagnostic.get(0) > 0 end, 50)
if not ok then
  io.stderr:write('no diagnostics from isolint --lsp\n')
  vim.cmd('cquit 1')
end
local d = vim.diagnostic.get(0)[1]
if d.code ~= 'E310' or d.lnum ~= 1 then
  io.stderr:write(('unexpected diagnostic %s at line %d\n'):format(tostring(d.code), d.lnum + 1))
  vim.cmd('cquit 1')
end
io.stdout:write('got ' .. d.code .. ' on line ' .. (d.lnum + 1) .. '\n')
vim.cmd('qall!')
LUA
PATH=$work/bin:$PATH XDG_CONFIG_HOME=$work/xdg XDG_DATA_HOME=$work/xdg XDG_STATE_HOME=$work/xdg \
  XDG_CACHE_HOME=$work/xdg timeout 25 nvim --headless -i NONE -u "$work/init.lua" \
  -c "edit $work/prog/p.mpf" -c "luafile $work/check.lua" </dev/null
rc=$?
[ $rc -eq 124 ] && echo "nvim did not finish within 25 s"
exit $rc
