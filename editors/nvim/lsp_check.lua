-- CI check of `rtlang lsp` with Neovim's built-in LSP client (run by
-- .ci/run): open error.rt, wait for the server's error on the line with the
-- misspelt constructor, ask for completions after `material ` (values such
-- as `lambertian`, not properties such as `radius`), then go to the
-- definition of `ball` from its `place` and land on the `let`. Exits
-- non-zero on any failure.
--
--   RTLANG=target/release/rtlang nvim --headless -u NONE -l editors/nvim/lsp_check.lua
-- (Neovim 0.7, Debian 12's, has no `-l`: use `-c "luafile editors/nvim/lsp_check.lua"`.)

local here = debug.getinfo(1, "S").source:sub(2):match("(.*/)") or "./"
local rtlang = os.getenv("RTLANG") or "rtlang"

local function fail(message)
  io.stderr:write("nvim lsp check: " .. message .. "\n")
  vim.cmd("cquit 1")
end

local function line_of(pattern)
  for i, text in ipairs(vim.api.nvim_buf_get_lines(0, 0, -1, false)) do
    local col = text:find(pattern)
    if col then
      return i, col
    end
  end
  fail("no line matches " .. pattern)
end

vim.cmd("edit " .. vim.fn.fnameescape(vim.fn.fnamemodify(here .. "error.rt", ":p")))
local buf = vim.api.nvim_get_current_buf()
local client = vim.lsp.start_client({
  name = "rtlang",
  cmd = { rtlang, "lsp" },
  root_dir = vim.fn.getcwd(),
})
if not client then
  fail("`" .. rtlang .. " lsp` did not start")
end
vim.lsp.buf_attach_client(buf, client)

local errors = function()
  return vim.diagnostic.get(buf, { severity = vim.diagnostic.severity.ERROR })
end
if not vim.wait(20000, function() return #errors() > 0 end, 50) then
  fail("no diagnostic arrived")
end
local want = line_of("lambertain") - 1
local got = errors()[1]
if got.lnum ~= want then
  fail(string.format("the error is on line %d, not %d: %s", got.lnum + 1, want + 1, got.message))
end
print(string.format("diagnostic on line %d: %s", got.lnum + 1, got.message:gsub("\n.*", "")))

local mat_line, mat_col = line_of("material lambertain")
local replies = vim.lsp.buf_request_sync(buf, "textDocument/completion", {
  textDocument = { uri = vim.uri_from_bufnr(buf) },
  position = { line = mat_line - 1, character = mat_col - 1 + #"material " },
}, 10000)
local labels = {}
for _, reply in pairs(replies or {}) do
  for _, item in ipairs((reply.result or {}).items or reply.result or {}) do
    labels[item.label] = true
  end
end
if not labels["lambertian"] or labels["radius"] then
  fail("completion after `material ` is not the values: " .. vim.inspect(vim.tbl_keys(labels)))
end
print("completion after `material `: lambertian, no radius")

local use_line, use_col = line_of("place ball")
vim.api.nvim_win_set_cursor(0, { use_line, use_col + #"place " })
vim.lsp.buf.definition()
local let_line = line_of("^let ball")
if not vim.wait(10000, function() return vim.api.nvim_win_get_cursor(0)[1] == let_line end, 50) then
  fail(string.format("go to definition left the cursor on line %d, not %d",
    vim.api.nvim_win_get_cursor(0)[1], let_line))
end
print(string.format("definition of `ball`: line %d", let_line))
vim.lsp.stop_client(client)
if not vim.wait(10000, function() return vim.lsp.get_client_by_id(client) == nil end, 50) then
  fail("the server did not shut down")
end
vim.cmd("qall!")
