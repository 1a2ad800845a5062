-- Driven by script/cli/tests/lsp_neovim.rs: Neovim's own LSP client (0.7 and later), attached
-- by the README's set-up, asks `blocksmith lsp` for the open recipe's diagnostics, hover on
-- `cube` (line 1) and completion after `m.` (line 2), and writes what it received as JSON to
-- $BLOCKSMITH_NVIM_OUT, then quits.
local out = vim.env.BLOCKSMITH_NVIM_OUT
local buf = vim.api.nvim_get_current_buf()
local result = { filetype = vim.bo[buf].filetype }
result.attached = vim.wait(30000, function() return #vim.lsp.buf_get_clients(buf) > 0 end, 50)
vim.wait(30000, function() return #vim.diagnostic.get(buf) > 0 end, 50)
result.diagnostics = {}
for _, d in ipairs(vim.diagnostic.get(buf)) do
  table.insert(result.diagnostics, { line = d.lnum, col = d.col, message = d.message })
end
local function request(method, line, character)
  local params = {
    textDocument = vim.lsp.util.make_text_document_params(buf),
    position = { line = line, character = character },
  }
  local answers = vim.lsp.buf_request_sync(buf, method, params, 20000) or {}
  for _, a in pairs(answers) do
    if a.result then return a.result end
  end
  return vim.NIL
end
result.hover = request("textDocument/hover", 0, 9)
result.completion = request("textDocument/completion", 1, 10)
vim.fn.writefile({ vim.fn.json_encode(result) }, out)
vim.cmd("qa!")
