#!/usr/bin/env bash
# The main job: install what is missing, build optimised, and run the bundled bottling
# plant headless with a summary. Until the bottling plant exists, it checks and compiles
# every bundled example and prints what each one holds.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh release
plant=build/release/compiler/plant

if [ -f plants/bottling.plant ] && "$plant" run --help >/dev/null 2>&1; then
  exec "$plant" run plants/bottling.plant --for "${PLANT_RUN_FOR:-120s}" "$@"
fi

echo
echo "== bundled examples (checked and compiled)"
status=0
for f in examples/*.plant; do
  "$plant" info "$f" || status=1
done
exit $status
