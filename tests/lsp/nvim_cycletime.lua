-- nvim_cycletime.lua: the cycle time in a real client (headless Neovim 0.7): a sample opened
-- from the samples folder gets its dry run; Neovim's own code lens shows the cycle time and
-- blocks of `isosim --summary`; inlay hints (requested as Neovim 0.7 has no display for them)
-- give the line times; the hover adds the line's share; folding ranges and semantic tokens
-- answer for the same buffer. Exits non-zero, naming each failure.
-- Environment: ISOLINT, ISOSIM (the binaries), ISO_SAMPLES (the samples folder),
-- ISO_LSP_DIR (an empty directory). Helpers: nvim_util.lua.
local util = dofile(debug.getinfo(1, 'S').source:sub(2):match('^(.*)/[^/]*$') .. '/nvim_util.lua')
local check = util.check

local function run()
  local samples = assert(os.getenv('ISO_SAMPLES'), 'ISO_SAMPLES is not set')
  local isosim = assert(os.getenv('ISOSIM'), 'ISOSIM is not set')
  local path = samples .. '/drilling_when/foratura_piastra.mpf'
  local summary = vim.fn.system({ isosim, '--summary', path })
  local cycle = tonumber(summary:match('cycle_time_s: ([%d%.]+)'))
  local blocks = summary:match('blocks: (%d+)')
  local want = ('cycle %.3f s · %s blocks'):format(cycle, blocks)

  -- The server says when a dry run is done (isotools/dryRun); as a user's init.lua would, the
  -- handler then asks for the code lens again.
  local states = {}
  vim.lsp.handlers['isotools/dryRun'] = function(_, result)
    table.insert(states, result.state)
    if result.state ~= 'running' then vim.lsp.codelens.refresh() end
  end
  vim.cmd('edit ' .. vim.fn.fnameescape(path))
  local buf = vim.api.nvim_get_current_buf()
  local client, exit_code = util.start(buf, samples .. '/drilling_when')
  if not client then return end

  -- 1. The code lens.
  local title
  local got = vim.wait(15000, function()
    local lenses = vim.lsp.codelens.get(buf)
    title = lenses[1] and lenses[1].command and lenses[1].command.title
    return title ~= nil
  end, 50)
  if check(got, 'no code lens within 15 s; dry run states: ' .. vim.inspect(states)) then
    check(title == want, ('code lens: expected %q, got %q'):format(want, tostring(title)))
  end

  local uri = vim.uri_from_bufnr(buf)
  local n = vim.api.nvim_buf_line_count(buf)
  -- 2. Inlay hints: one per line that took time, at its end; their sum is the cycle time
  -- (within the rounding of each label to the millisecond).
  local r = client.request_sync('textDocument/inlayHint', {
    textDocument = { uri = uri },
    range = { start = { line = 0, character = 0 }, ['end'] = { line = n, character = 0 } },
  }, 5000, buf)
  local hints = r and r.result or {}
  local sum, count = 0, 0
  local function add(b, list)
    for _, h in ipairs(list) do
      local line = vim.api.nvim_buf_get_lines(b, h.position.line, h.position.line + 1, false)[1]
      check(h.position.character == #line, 'a hint not at the end of line ' .. h.position.line)
      sum = sum + tonumber(h.label:match('^([%d%.]+) s$') or 0)
      count = count + 1
    end
  end
  add(buf, hints)
  check(#hints > 3, 'inlay hints: ' .. vim.inspect(r))
  -- the subprogram's lines have the rest: with them the hints add up to the cycle time (within
  -- the rounding of each label to the millisecond)
  local sub = samples .. '/drilling_when/foratura.spf'
  local sbuf = vim.fn.bufadd(sub)
  vim.fn.bufload(sbuf)
  vim.lsp.buf_attach_client(sbuf, client.id)
  local srange = { start = { line = 0, character = 0 }, ['end'] = { line = vim.api.nvim_buf_line_count(sbuf), character = 0 } }
  local sh = {}
  vim.wait(10000, function()
    local sr = client.request_sync('textDocument/inlayHint', { textDocument = { uri = vim.uri_from_bufnr(sbuf) },
                                                              range = srange }, 5000, sbuf)
    sh = sr and sr.result or {}
    return #sh > 0
  end, 100)
  add(sbuf, sh)
  check(#sh > 0, 'no inlay hints in the subprogram')
  check(math.abs(sum - cycle) < 0.0005 * count + 1e-9, ('the hints add up to %f, the cycle is %f'):format(sum, cycle))

  -- 3. The hover on a line that ran has its time.
  local line = hints[1] and hints[1].position.line or 0
  r = client.request_sync('textDocument/hover', { textDocument = { uri = uri }, position = { line = line, character = 0 } },
                          5000, buf)
  local value = r and r.result and r.result.contents and r.result.contents.value or ''
  check(value:find('Dry run', 1, true) ~= nil and value:find('% of the cycle', 1, true) ~= nil,
        'hover with the line time: ' .. vim.inspect(r))

  -- 4. Folding ranges: the WHEN ... CANCEL of lines 38-40 folds to its CANCEL (0-based 37-38).
  r = client.request_sync('textDocument/foldingRange', { textDocument = { uri = uri } }, 5000, buf)
  local folds = r and r.result or {}
  local when = false
  for _, f in ipairs(folds) do
    if f.startLine == 37 and f.endLine == 38 then when = true end
  end
  check(when, 'folding ranges lack the WHEN of line 38: ' .. vim.inspect(folds))

  -- 5. Semantic tokens: a whole number of 5-number tokens, the first one on line 13 (R40).
  r = client.request_sync('textDocument/semanticTokens/full', { textDocument = { uri = uri } }, 5000, buf)
  local data = r and r.result and r.result.data or {}
  check(#data > 0 and #data % 5 == 0 and data[1] == 12, 'semantic tokens: ' .. vim.inspect(data):sub(1, 200))

  util.stop(client, exit_code)
end

util.finish(run, 'nvim LSP client: cycle time lens, inlay hints, hover, folding, semantic tokens ok')
