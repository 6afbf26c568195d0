-- Run by tests/lsp/nvim.sh: Neovim's own LSP client (0.7: vim.lsp.start_client) attached
-- to `plant lsp` on one file; writes every diagnostic it receives for that file to
-- $PLANT_LSP_OUT as "line:col code message" (1-based), or "none" after 20 s.
local plant = os.getenv('PLANT_LSP_BIN')
local file = os.getenv('PLANT_LSP_FILE')
local out = os.getenv('PLANT_LSP_OUT')
local stdlib = os.getenv('PLANT_LSP_STDLIB')

vim.cmd('edit ' .. vim.fn.fnameescape(file))
local buf = vim.api.nvim_get_current_buf()
local received = nil
local client = vim.lsp.start_client({
  name = 'plant',
  cmd = { plant, 'lsp', '--stdlib', stdlib },
  root_dir = vim.fn.fnamemodify(file, ':p:h'),
  handlers = {
    ['textDocument/publishDiagnostics'] = function(err, result, ctx, config)
      vim.lsp.diagnostic.on_publish_diagnostics(err, result, ctx, config)
      if result and #result.diagnostics > 0 then received = result end
    end,
  },
})
vim.lsp.buf_attach_client(buf, client)
vim.wait(20000, function() return received ~= nil end, 50)

local lines = {}
if received then
  -- What Neovim itself now holds for the buffer (its diagnostic API), not just the message.
  for _, d in ipairs(vim.diagnostic.get(buf)) do
    table.insert(lines, string.format('%d:%d %s %s', d.lnum + 1, d.col + 1, tostring(d.code), d.message))
  end
  if #lines == 0 then table.insert(lines, 'received, but vim.diagnostic.get is empty') end
else
  table.insert(lines, 'none')
end
vim.fn.writefile(lines, out)
vim.lsp.stop_client(client)
vim.wait(2000, function() return vim.lsp.client_is_stopped(client) end, 50)
vim.cmd('qa!')
