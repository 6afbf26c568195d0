#!/usr/bin/env bash
# Builds the VS Code extension's package, editors/vscode/plant-language.vsix, with npm's
# @vscode/vsce from the committed lockfile (npm ci when node_modules is missing). Nothing
# is published. Install it with: code --install-extension editors/vscode/plant-language.vsix
set -euo pipefail
cd "$(dirname "$0")"
[ -f node_modules/.package-lock.json ] || npm ci --no-audit --no-fund --loglevel=error
node_modules/.bin/vsce package --skip-license --allow-missing-repository -o plant-language.vsix
