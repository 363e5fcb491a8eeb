-- nvim_client.lua: a real LSP client against `isolint --lsp` (Neovim 0.7 API, headless).
-- Opens a program with an error, waits for its diagnostics, fixes it in the buffer (an
-- incremental change), waits for the diagnostics to clear, asks for hover, definition and
-- completion, renames a label and a subprogram (and its file), shuts the server down. Exits
-- non-zero, naming each failure, on any failure.
-- Environment: ISOLINT (the binary), ISO_LSP_DIR (an empty directory for the programs).
-- Helpers: nvim_util.lua.
local util = dofile(debug.getinfo(1, 'S').source:sub(2):match('^(.*)/[^/]*$') .. '/nvim_util.lua')
local check, write = util.check, util.write

local function code_of(d)
  return d.code or (d.user_data and d.user_data.lsp and d.user_data.lsp.code)
end

local function run()
  local dir = assert(os.getenv('ISO_LSP_DIR'), 'ISO_LSP_DIR is not set')
  write(dir .. '/main.mpf', 'G90 G01 F=100\nX10 G7\nLift\nGOTOF Fine\nFine: M30\n')
  write(dir .. '/lift.spf', 'PROC Lift SAVE\nZ=10\nM17\n')

  vim.cmd('edit ' .. vim.fn.fnameescape(dir .. '/main.mpf'))
  local buf = vim.api.nvim_get_current_buf()
  local client, exit_code = util.start(buf, dir)
  if not client then return end

  -- 1. The error on line 2 (0-based 1): G7 is not a G code.
  local got = vim.wait(10000, function() return #vim.diagnostic.get(buf) > 0 end, 20)
  if check(got, 'no diagnostics for main.mpf within 10 s') then
    local d = vim.diagnostic.get(buf)[1]
    check(code_of(d) == 'E310', 'diagnostic code: expected E310, got ' .. tostring(code_of(d)))
    check(d.lnum == 1 and d.col == 4, ('diagnostic position: expected 1:4, got %d:%d'):format(d.lnum, d.col))
    check(d.source == 'isolint', 'diagnostic source: ' .. tostring(d.source))
  end

  -- 2. Fix it in the buffer (not saved): the diagnostics clear.
  vim.api.nvim_buf_set_lines(buf, 1, 2, false, { 'X10' })
  check(vim.wait(10000, function() return #vim.diagnostic.get(buf) == 0 end, 20),
        'diagnostics not cleared after the fix: ' .. vim.inspect(vim.diagnostic.get(buf)))

  local uri = vim.uri_from_bufnr(buf)
  local function at(line, character)
    return { textDocument = { uri = uri }, position = { line = line, character = character } }
  end

  -- 3. Hover on G01.
  local r = client.request_sync('textDocument/hover', at(0, 5), 5000, buf)
  local value = r and r.result and r.result.contents and r.result.contents.value or ''
  check(value:find('G01', 1, true) ~= nil, 'hover on G01: ' .. vim.inspect(r))

  -- 4. Definition of the call Lift: the PROC line of lift.spf.
  r = client.request_sync('textDocument/definition', at(2, 1), 5000, buf)
  local loc = r and r.result and r.result[1]
  check(loc ~= nil and loc.uri:sub(-8) == 'lift.spf' and loc.range.start.line == 0,
        'definition of Lift: ' .. vim.inspect(r))

  -- 5. Completion after GOTOF offers the label.
  r = client.request_sync('textDocument/completion', at(3, 6), 5000, buf)
  local found = false
  for _, item in ipairs((r and r.result and r.result.items) or {}) do
    if item.label == 'Fine' then found = true end
  end
  check(found, 'completion after GOTOF lacks the label Fine: ' .. vim.inspect(r))

  -- 6. Rename the label Fine from its jump: the definition and the jump change in the buffer.
  r = client.request_sync('textDocument/rename', vim.tbl_extend('force', at(3, 7), { newName = 'Done' }), 5000, buf)
  if check(r and r.result, 'rename of Fine: ' .. vim.inspect(r)) then
    vim.lsp.util.apply_workspace_edit(r.result, client.offset_encoding)
    local lines = vim.api.nvim_buf_get_lines(buf, 3, 5, false)
    check(lines[1] == 'GOTOF Done' and lines[2] == 'Done: M30', 'after renaming Fine: ' .. vim.inspect(lines))
  end

  -- 7. prepareRename on a keyword is refused; renaming the subprogram Lift renames its call,
  -- its PROC line and its file lift.spf, named after it (Neovim renames files).
  r = client.request_sync('textDocument/prepareRename', at(3, 2), 5000, buf)
  check(r and r.err and r.err.code == -32803, 'prepareRename on GOTOF: ' .. vim.inspect(r))
  r = client.request_sync('textDocument/rename', vim.tbl_extend('force', at(2, 1), { newName = 'Raise' }), 5000, buf)
  if check(r and r.result, 'rename of Lift: ' .. vim.inspect(r)) then
    vim.lsp.util.apply_workspace_edit(r.result, client.offset_encoding)
    check(vim.api.nvim_buf_get_lines(buf, 2, 3, false)[1] == 'Raise', 'the call after renaming Lift: ' ..
          vim.inspect(vim.api.nvim_buf_get_lines(buf, 0, -1, false)))
    local f = io.open(dir .. '/Raise.spf', 'rb')
    local text = f and f:read('*a') or '(no Raise.spf)'
    if f then f:close() end
    check(text == 'PROC Raise SAVE\nZ=10\nM17\n', 'Raise.spf after renaming Lift: ' .. vim.inspect(text))
    check(io.open(dir .. '/lift.spf', 'rb') == nil, 'lift.spf is still there after renaming Lift')
  end

  -- 8. Shutdown and exit: the server ends with status 0.
  util.stop(client, exit_code)
end

util.finish(run, 'nvim LSP client: diagnostics, fix, hover, definition, completion, rename, shutdown ok')
