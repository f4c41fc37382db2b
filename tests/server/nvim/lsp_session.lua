-- Drives rdcd-lsp from a real Neovim (0.7 and newer) and writes what it saw as JSON.
--
-- Run headless by tests/server/test_neovim.py:
--   nvim --headless --clean -u NONE -n -c "luafile tests/server/nvim/lsp_session.lua"
-- Inputs (environment): RDCD_NVIM_FILE (a .rdcd file with one unknown name `turn_directon`),
-- RDCD_NVIM_OUT (the JSON written at the end), RDCD_NVIM_PYTHON (the interpreter that runs
-- `-m server`), RDCD_NVIM_ROOT (the project root, the server's working directory) and
-- RDCD_NVIM_TIMEOUT_MS (the bound of every single wait).
-- Only APIs present since 0.7 are used: vim.lsp.start_client, vim.lsp.buf_attach_client,
-- client.request_sync, vim.wait, nvim_buf_set_lines/nvim_buf_set_text, vim.diagnostic.get.

local out = { nvim_version = tostring(vim.version().major) .. "." .. tostring(vim.version().minor)
  .. "." .. tostring(vim.version().patch), steps = {} }
local timeout = tonumber(vim.env.RDCD_NVIM_TIMEOUT_MS) or 8000
local published = {} -- every textDocument/publishDiagnostics, in order

local function step(name)
  table.insert(out.steps, name)
end

local function encode(value)
  if vim.json and vim.json.encode then
    return vim.json.encode(value)
  end
  return vim.fn.json_encode(value)
end

local function write_out()
  local f = assert(io.open(vim.env.RDCD_NVIM_OUT, "w"))
  f:write(encode(out))
  f:close()
end

-- the first line (0-based) and byte column of `needle` in the buffer
local function find(bufnr, needle)
  for i, line in ipairs(vim.api.nvim_buf_get_lines(bufnr, 0, -1, false)) do
    local col = line:find(needle, 1, true)
    if col then
      return i - 1, col - 1
    end
  end
  error("not in buffer: " .. needle)
end

local function summarize(diagnostics)
  local result = {}
  for _, d in ipairs(diagnostics or {}) do
    table.insert(result, {
      code = d.code, message = d.message, source = d.source, severity = d.severity,
      line = d.range.start.line, character = d.range.start.character,
    })
  end
  return result
end

local function request(client, bufnr, method, params)
  local response, err = client.request_sync(method, params, timeout, bufnr)
  if not response then
    error(method .. " failed: " .. tostring(err))
  end
  if response.err then
    error(method .. " error: " .. vim.inspect(response.err))
  end
  return response.result
end

-- waits until the newest publish is for the buffer's current version and satisfies `accept`
local function wait_published(bufnr, accept, what)
  local ok = vim.wait(timeout, function()
    local last = published[#published]
    if not last then
      return false
    end
    local version = vim.lsp.util.buf_versions[bufnr]
    if last.version ~= nil and last.version ~= vim.NIL and version ~= nil and last.version ~= version then
      return false
    end
    return accept(last.diagnostics)
  end, 20)
  if not ok then
    error("timed out waiting for " .. what .. " (publishes seen: " .. #published .. ")")
  end
  return published[#published]
end

local function run()
  local file = assert(vim.env.RDCD_NVIM_FILE, "RDCD_NVIM_FILE")
  local root = assert(vim.env.RDCD_NVIM_ROOT, "RDCD_NVIM_ROOT")
  vim.cmd("silent edit! " .. vim.fn.fnameescape(file))
  vim.bo.filetype = "rdcd"
  local bufnr = vim.api.nvim_get_current_buf()
  out.filetype = vim.bo[bufnr].filetype
  step("opened")

  local client_id = vim.lsp.start_client({
    name = "rdcd",
    cmd = { vim.env.RDCD_NVIM_PYTHON or "python3", "-m", "server", "--debounce-ms", "10", "--log-level", "ERROR" },
    cmd_cwd = root,
    root_dir = root,
    flags = { debounce_text_changes = 0 },
    init_options = { rdcd = { inlayHints = { fragmentSizes = true } } },
    handlers = {
      ["textDocument/publishDiagnostics"] = function(err, result, ctx, config)
        table.insert(published, { version = result.version, diagnostics = result.diagnostics })
        return vim.lsp.diagnostic.on_publish_diagnostics(err, result, ctx, config)
      end,
    },
    on_exit = function(code, signal)
      out.server_exit = { code = code, signal = signal }
    end,
  })
  assert(client_id, "vim.lsp.start_client returned nil")
  assert(vim.lsp.buf_attach_client(bufnr, client_id), "buf_attach_client failed")
  local client
  if not vim.wait(timeout, function()
    client = vim.lsp.get_client_by_id(client_id)
    return client ~= nil and client.initialized == true
  end, 20) then
    error("the server did not initialize")
  end
  out.server_name = client.server_info and client.server_info.name or vim.NIL
  step("initialized")

  -- 1. diagnostics of the unknown name, as published and as Neovim stores them
  local first = wait_published(bufnr, function(d) return #d > 0 end, "the first diagnostics")
  out.diagnostics = summarize(first.diagnostics)
  out.diagnostics_version = first.version
  vim.wait(timeout, function() return #vim.diagnostic.get(bufnr) > 0 end, 20)
  out.vim_diagnostics = {}
  for _, d in ipairs(vim.diagnostic.get(bufnr)) do
    table.insert(out.vim_diagnostics, { lnum = d.lnum, col = d.col, code = d.code, message = d.message })
  end
  step("diagnostics")

  -- 2. hover on a role name
  local uri = vim.uri_from_bufnr(bufnr)
  local line, col = find(bufnr, "role RightWheel")
  local hover = request(client, bufnr, "textDocument/hover", {
    textDocument = { uri = uri }, position = { line = line, character = col + #"role " + 2 },
  })
  out.hover = hover and hover.contents or vim.NIL
  step("hover")

  -- 3. type `self.` on a new line (a buffer edit, sent as didChange) and complete after it
  local typo_line = find(bufnr, "turn_directon")
  vim.api.nvim_buf_set_lines(bufnr, typo_line, typo_line, false, { "    self." })
  local completion = request(client, bufnr, "textDocument/completion", {
    textDocument = { uri = uri }, position = { line = typo_line, character = #"    self." },
  })
  local items = completion and (completion.items or completion) or {}
  out.completion = {}
  for _, item in ipairs(items) do
    table.insert(out.completion, item.label)
  end
  step("completion")

  -- 4. undo the `self.` line and fix the unknown name with buffer edits; diagnostics must clear
  vim.api.nvim_buf_set_lines(bufnr, typo_line, typo_line + 1, false, {})
  local row, start = find(bufnr, "turn_directon")
  vim.api.nvim_buf_set_text(bufnr, row, start, row, start + #"turn_directon", { "turn_direction" })
  out.fixed_line = vim.api.nvim_buf_get_lines(bufnr, row, row + 1, false)[1]
  local last = wait_published(bufnr, function(d) return #d == 0 end, "the diagnostics to clear")
  out.final_diagnostics = summarize(last.diagnostics)
  out.final_version = last.version
  out.buffer_version = vim.lsp.util.buf_versions[bufnr]
  vim.wait(timeout, function() return #vim.diagnostic.get(bufnr) == 0 end, 20)
  out.final_vim_diagnostics = #vim.diagnostic.get(bufnr)
  out.publish_count = #published
  step("fixed")

  -- 5. a clean shutdown
  client.stop()
  out.stopped = vim.wait(timeout, function() return client.is_stopped() end, 20)
  step("stopped")
end

local ok, err = xpcall(run, debug.traceback)
if not ok then
  out.error = tostring(err)
end
local written, write_err = pcall(write_out)
if not written then
  io.stderr:write("could not write the result: " .. tostring(write_err) .. "\n")
end
vim.cmd(ok and written and "qall!" or "1cquit!")
