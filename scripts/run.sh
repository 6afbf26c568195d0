#!/usr/bin/env bash
# The main job: install what is missing, build optimised, and run the bundled bottling
# plant (plants/bottling.plant) headless for 120 simulated seconds, with a summary.
# Extra arguments go to `plant run`, e.g. `--trace bottling.csv --trace-rate 10Hz` or
# `--for 300s`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh release
exec build/release/app/plant run plants/bottling.plant --for "${PLANT_RUN_FOR:-120s}" "$@"
