-- nvim_format.lua: format a buffer through `isolint --lsp` from a real Neovim LSP client
-- (headless; Neovim 0.7 API, vim.lsp.buf.format from 0.8 on). Opens a badly laid-out program
-- in a folder whose isotools.toml has a [format] table, formats the buffer (synchronously),
-- and checks that the buffer then holds exactly what `isofmt FILE` prints, that the buffer is
-- modified and the file on disk is not. Formats a second time: nothing changes.
-- Environment: ISOLINT, ISOFMT (the binaries), ISO_LSP_DIR (an empty directory). Helpers:
-- nvim_util.lua.
local util = dofile(debug.getinfo(1, 'S').source:sub(2):match('^(.*)/[^/]*$') .. '/nvim_util.lua')
local check, write = util.check, util.write

local function read(path)
  local f = assert(io.open(path, 'rb'))
  local text = f:read('*a')
  f:close()
  return text
end

local messy = table.concat({
  'n10 g90 g01    x10 y 20 f1000   ',
  'r1=5    ; a comment',
  'if r1>3',
  'g1 x=r1+2 y-.5',
  'if (r1 == 11) and ($aa_in[1]==0)',
  '$aa_out[2]=1',
  'endif',
  '',
  '',
  '',
  'endif',
  'm30',
  '',
}, '\n')

local function buffer_text(buf)
  return table.concat(vim.api.nvim_buf_get_lines(buf, 0, -1, false), '\n') .. '\n'
end

local function format(buf)
  if vim.lsp.buf.format then
    vim.lsp.buf.format({ async = false, bufnr = buf, timeout_ms = 5000 })
  else
    vim.lsp.buf.formatting_sync(nil, 5000) -- Neovim 0.7
  end
end

local function run()
  local isofmt = assert(os.getenv('ISOFMT'), 'ISOFMT is not set')
  local dir = assert(os.getenv('ISO_LSP_DIR'), 'ISO_LSP_DIR is not set')
  write(dir .. '/isotools.toml', '[format]\nindent = 4\nnumbers = "normalised"\n')
  local file = dir .. '/messy.mpf'
  write(file, messy)
  local expected = vim.fn.system({ isofmt, file })
  if not check(vim.v.shell_error == 0, 'isofmt failed: ' .. expected) then return end
  check(expected ~= messy, 'isofmt did not change the program')
  check(expected:find('\n    G1 X=R1 + 2 Y-0.5\n', 1, true) ~= nil, 'isofmt ignored isotools.toml: ' .. expected)

  vim.cmd('edit ' .. vim.fn.fnameescape(file))
  local buf = vim.api.nvim_get_current_buf()
  local client, exit_code = util.start(buf, dir)
  if not client then return end
  local ready = vim.wait(10000, function()
    local caps = client.server_capabilities
    return caps ~= nil and caps.documentFormattingProvider ~= nil
  end, 20)
  if not check(ready, 'the server did not initialize (or does not advertise formatting) within 10 s') then return end
  check(client.server_capabilities.documentRangeFormattingProvider == true, 'no range formatting advertised')

  format(buf)
  local got = buffer_text(buf)
  check(got == expected, ('buffer after formatting:\n%s\nisofmt prints:\n%s'):format(got, expected))
  check(vim.bo[buf].modified, 'the buffer is not marked modified')
  check(read(file) == messy, 'the file on disk changed (only the buffer should)')

  format(buf)
  check(buffer_text(buf) == expected, 'a second format changed the buffer: ' .. buffer_text(buf))

  util.stop(client, exit_code)
end

util.finish(run, 'nvim LSP client: format through isolint --lsp equals isofmt ok')
