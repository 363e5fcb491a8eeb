-- nvim_util.lua: what the headless Neovim clients of `isolint --lsp` share (nvim_client.lua,
-- nvim_format.lua): collecting failures, writing files, starting the server on a buffer,
-- stopping it, and ending Neovim with the result. Loaded with dofile() from the same folder.
local M = { failures = {} }

function M.check(ok, what)
  if not ok then table.insert(M.failures, what) end
  return ok
end

function M.write(path, text)
  local f = assert(io.open(path, 'wb'))
  f:write(text)
  f:close()
end

-- Starts `ISOLINT --lsp` in `dir` and attaches it to `buf`. Returns the client (nil on failure)
-- and a function that tells the server's exit code once it has exited (else nil).
function M.start(buf, dir)
  local isolint = assert(os.getenv('ISOLINT'), 'ISOLINT is not set')
  local exit_code = nil
  local id = vim.lsp.start_client({
    name = 'isolint',
    cmd = { isolint, '--lsp' },
    root_dir = dir,
    on_exit = function(code) exit_code = code end,
  })
  if not M.check(id ~= nil, 'start_client failed') then return nil end
  vim.lsp.buf_attach_client(buf, id)
  return vim.lsp.get_client_by_id(id), function() return exit_code end
end

-- Shutdown and exit: the server must end with status 0.
function M.stop(client, exit_code)
  client.stop()
  M.check(vim.wait(10000, function() return exit_code() ~= nil end, 20), 'the server did not exit')
  M.check(exit_code() == 0, 'server exit status: ' .. tostring(exit_code()))
end

-- Runs `body` and ends Neovim: status 1 naming each failure, else 0 after printing `passed`.
function M.finish(body, passed)
  local ok, err = pcall(body)
  if not ok then table.insert(M.failures, 'lua error: ' .. tostring(err)) end
  if #M.failures > 0 then
    for _, f in ipairs(M.failures) do io.stderr:write('FAIL: ' .. f .. '\n') end
    vim.cmd('cquit 1')
  else
    io.stdout:write(passed .. '\n')
    vim.cmd('qall!')
  end
end

return M
