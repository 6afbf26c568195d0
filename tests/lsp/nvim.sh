#!/usr/bin/env bash
# Debian's Neovim, headless, opens a broken plant file with `plant lsp` attached (its
# built-in LSP client) and reports the diagnostic it received; the test checks it is the
# one `plant check` reports. Usage: tests/lsp/nvim.sh PLANT REPO_DIR
set -euo pipefail
plant="$1"
repo="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cat > "$work/broken.plant" <<'PLANT'
import std.belts

plant Broken {
    b1: Belt(length = 1 m)
    flow b1.speed_now -> b1.set_sped
}
PLANT
PLANT_LSP_BIN="$plant" PLANT_LSP_FILE="$work/broken.plant" PLANT_LSP_OUT="$work/out.txt" \
PLANT_LSP_STDLIB="$repo/stdlib" HOME="$work" XDG_CONFIG_HOME="$work" XDG_DATA_HOME="$work" XDG_STATE_HOME="$work" \
  timeout 60 nvim --headless -u NONE -i NONE -c "luafile $repo/tests/lsp/nvim.lua" < /dev/null > /dev/null 2>&1 || true
echo "Neovim received:"
cat "$work/out.txt" 2>/dev/null || { echo "(nothing: nvim wrote no report)"; exit 1; }
# The same diagnostic as `plant check` (line:col and code).
json="$("$plant" check --stdlib "$repo/stdlib" --diagnostics=json "$work/broken.plant" 2>&1 >/dev/null || true)"
code="$(printf '%s\n' "$json" | sed -n 's/^ *"code": "\([A-Z0-9]*\)",$/\1/p' | head -1)"
line="$(printf '%s\n' "$json" | sed -n 's/^ *"line": \([0-9]*\),$/\1/p' | head -1)"
col="$(printf '%s\n' "$json" | sed -n 's/^ *"col": \([0-9]*\),$/\1/p' | head -1)"
expected="$line:$col $code"
# Its note without a place of its own ("did you mean 'set_speed'?"), which Neovim 0.7 shows
# only as part of the message (it drops related information).
note="$(printf '%s\n' "$json" | sed -n 's/^ *"message": "\(did you mean [^"]*\)"$/\1/p' | head -1)"
echo "plant check: $expected ... $note"
[ -n "$code" ] && [ -n "$line" ] && [ -n "$note" ] && grep "^$expected " "$work/out.txt" | grep -qF "; $note"
