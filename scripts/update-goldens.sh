#!/usr/bin/env bash
# Regenerates every golden file (compiled graphs, diagnostics, runtime traces, and the
# compiled graphs of the shipped plants in tests/plants/) and docs/language.md's slot
# tables (from graph/kinds.h) from the current build. Review the result with
# `git diff tests/golden docs` before committing.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh ci >/dev/null
build/ci/tests/plant_golden --update tests/golden
mkdir -p tests/plants
build/ci/tests/plant_golden --update --sources=plants tests/plants
build/ci/tests/plant_slot_docs --update docs/language.md
git --no-pager diff --stat -- tests/golden tests/plants docs/language.md || true
