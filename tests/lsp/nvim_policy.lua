-- nvim_policy.lua: the editor and the command line apply one lint policy. Headless Neovim opens
-- (1) the z32 sample, whose isotools.toml names its machine file and dialect, and (2) a folder
-- whose isotools.toml disables a rule, plus a per-path override that disables another; for each
-- document, the diagnostics Neovim receives from `isolint --lsp` must be those of
-- `isolint --format json FILE` run from the same folder (code, severity, position, message).
-- Environment: ISOLINT (the binary), ISO_LSP_DIR (an empty directory), ISO_SAMPLES (samples/).
-- Helpers: nvim_util.lua.
local util = dofile(debug.getinfo(1, 'S').source:sub(2):match('^(.*)/[^/]*$') .. '/nvim_util.lua')
local check, write = util.check, util.write

local function code_of(d)
  return d.code or (d.user_data and d.user_data.lsp and d.user_data.lsp.code)
end

local severities = { 'error', 'warning', 'info', 'info' }

-- One line per diagnostic, sorted: "LINE:COL SEVERITY CODE MESSAGE" (1-based like the CLI).
local function from_editor(buf)
  local out = {}
  for _, d in ipairs(vim.diagnostic.get(buf)) do
    table.insert(out, ('%d:%d %s %s %s'):format(d.lnum + 1, d.col + 1, severities[d.severity] or '?',
                                               tostring(code_of(d)), d.message))
  end
  table.sort(out)
  return out
end

local function from_cli(dir, file)
  local isolint = assert(os.getenv('ISOLINT'))
  local text = vim.fn.system({ 'sh', '-c', 'cd "$1" && "$2" --format json "$3"', 'sh', dir, isolint, file })
  local out = {}
  local ok, doc = pcall(vim.fn.json_decode, text)
  if not check(ok and type(doc) == 'table', 'isolint --format json ' .. file .. ': ' .. text) then return out end
  for _, d in ipairs(doc.diagnostics) do
    table.insert(out, ('%d:%d %s %s %s'):format(d.line, d.column, d.severity, d.code, d.message))
  end
  table.sort(out)
  return out
end

-- Opens DIR/FILE, waits until the server has published for it, compares with the CLI.
local function compare(dir, file, expect_count)
  local published = false
  local default = vim.lsp.handlers['textDocument/publishDiagnostics']
  vim.lsp.handlers['textDocument/publishDiagnostics'] = function(err, result, ctx, config)
    default(err, result, ctx, config)
    if result and result.uri and result.uri:sub(-#file) == file then published = true end
  end
  vim.cmd('edit ' .. vim.fn.fnameescape(dir .. '/' .. file))
  local buf = vim.api.nvim_get_current_buf()
  local client, exit_code = util.start(buf, dir)
  if not client then return end
  check(vim.wait(10000, function() return published end, 20), 'no diagnostics published for ' .. file)
  vim.wait(200) -- a second publish (there must be none that differs) would land here
  local editor, cli = from_editor(buf), from_cli(dir, file)
  check(vim.inspect(editor) == vim.inspect(cli),
        file .. ': editor ' .. vim.inspect(editor) .. ' but command line ' .. vim.inspect(cli))
  check(#cli == expect_count, file .. ': expected ' .. expect_count .. ' diagnostics, got ' .. vim.inspect(cli))
  util.stop(client, exit_code)
  vim.lsp.handlers['textDocument/publishDiagnostics'] = default
  vim.cmd('bwipeout!')
end

local function run()
  local dir = assert(os.getenv('ISO_LSP_DIR'), 'ISO_LSP_DIR is not set')
  local samples = assert(os.getenv('ISO_SAMPLES'), 'ISO_SAMPLES is not set')

  -- 1. The z32 sample with its settings file (machine file, z32 dialect): clean on both sides.
  local z32 = dir .. '/z32'
  vim.fn.mkdir(z32, 'p')
  for _, f in ipairs({ 'fresatura_flangia.mpf', 'cambio_utensile.spf', 'isotools.toml', 'machine.json' }) do
    local lines = vim.fn.readfile(samples .. '/z32_toolchange/' .. f, 'b')
    vim.fn.writefile(lines, z32 .. '/' .. f, 'b')
  end
  compare(z32, 'fresatura_flangia.mpf', 0)

  -- 2. A disable list and a per-path override: W404 is off everywhere, W405 under legacy/.
  local pol = dir .. '/policy'
  vim.fn.mkdir(pol .. '/legacy', 'p')
  write(pol .. '/isotools.toml', 'disable = ["unreachable"]\n\n[[overrides]]\npaths = ["legacy/**"]\ndisable = ["W405"]\n')
  local program = 'G90 G01 F=100\nX10\nGOTOF Fine\nX20\nFine: X5\nY=1 G7\n'
  write(pol .. '/main.mpf', program)
  write(pol .. '/legacy/old.mpf', program)
  compare(pol, "main.mpf", 2) -- W405 and E310, not W404
  compare(pol, "legacy/old.mpf", 1) -- E310 only
end

util.finish(run, 'nvim LSP policy: the z32 sample and a disable list match the command line')
