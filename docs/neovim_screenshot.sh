#!/usr/bin/env bash
# Makes docs/neovim.png: Neovim (0.7 or later) in tmux with the README's "Neovim 0.7 to 0.9"
# set-up, a recipe with a misspelt method (the server's diagnostic) and hover on a call, the
# terminal captured with its colours (tmux), turned to HTML (aha) and drawn by chromium.
# Needs nvim, tmux, aha, chromium and a built target/debug/blocksmith.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
work=$(mktemp -d)
trap 'tmux kill-session -t blocksmith-shot 2>/dev/null || true; rm -rf "$work"' EXIT
awk '/\*\*Neovim 0.7 to 0.9\*\*/{f=1} f&&/^```lua/{p=1;next} p&&/^```/{exit} p' README.md > "$work/init.lua"
cat >> "$work/init.lua" <<'LUA'
vim.o.termguicolors = true
vim.o.number = true
vim.cmd("hi NormalFloat guibg=#2b2b33 guifg=#e0e0e0")
vim.cmd("hi SignColumn guibg=NONE")
vim.cmd("hi LineNr guifg=#707070")
vim.cmd("hi StatusLine guibg=#3a3a48 guifg=#e0e0e0 gui=NONE")
LUA
cat > "$work/die.rhai" <<'RHAI'
// A die: a cube with one pip cut out (Leblanc et al., Fig. 13).
let body = cube(2);
let v = body.volum();
let pip = uv_sphere(0.15, 24, 12);
let die = body - pip.translate([0, 0, 1]);
die
RHAI
tmux new-session -d -s blocksmith-shot -x 100 -y 16 \
  "cd $work && PATH=$root/target/debug:\$PATH TERM=xterm-256color nvim -n -i NONE -u init.lua die.rhai"
sleep 4
tmux send-keys -t blocksmith-shot "4G"; sleep 0.3
tmux send-keys -t blocksmith-shot "13|"; sleep 0.3
tmux send-keys -t blocksmith-shot ":lua vim.lsp.buf.hover()" Enter; sleep 2
tmux capture-pane -t blocksmith-shot -p -e > "$work/screen.ansi"
aha --black --title "blocksmith lsp in Neovim" < "$work/screen.ansi" \
  | sed 's|<pre>|<pre style="font-family: DejaVu Sans Mono, monospace; font-size: 14px; line-height: 1.25; margin: 8px">|; s|application/xml+xhtml|text/html|; s|background-color:black|background-color:#1c1c22|' \
  > "$work/screen.html"
chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=860,365 \
  --screenshot="$root/docs/neovim.png" "file://$work/screen.html"
