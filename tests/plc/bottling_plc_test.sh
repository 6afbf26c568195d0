#!/usr/bin/env bash
# Issue #15 §4 in the suite: plants/bottling_plc.plant under the example controller
# (examples/plc/router.py) in lock-step for 120 s of plant time: at least 20 bottles
# commissioned, none lost, none in a wrong lane; a second run gives the same trace.
# With --realtime: once, paced to the wall clock (120 s), the controller polling. With
# --once: one lock-step run (under the sanitizers; the ci build compares two).
#   tests/plc/bottling_plc_test.sh PLANT SOURCE_DIR [--realtime | --once]
set -euo pipefail
plant="$1" src="$2" mode="${3:-}"
work=$(mktemp -d) pid=""
trap 'kill "$pid" 2>/dev/null || true; rm -rf "$work"' EXIT
. "$(dirname "$0")/start_plant.sh"
run() {
  if [ "$mode" = --realtime ]; then
    start_plant "$1" "$src/plants/bottling_plc.plant" --realtime --modbus-port 0 --for 120s
    timeout 300 /usr/bin/python3 "$src/examples/plc/router.py" "$port" > "$work/router$1" ||
      { echo "FAIL: the controller"; tail -5 "$work/router$1"; exit 1; }
  else
    start_plant "$1" "$src/plants/bottling_plc.plant" --lockstep --modbus-port 0 --for 120s --trace "$work/trace$1.csv"
    timeout 300 /usr/bin/python3 "$src/examples/plc/router.py" "$port" --lockstep 18000 > "$work/router$1" ||
      { echo "FAIL: the controller"; tail -5 "$work/router$1"; exit 1; }
  fi
  wait "$pid"
  tail -1 "$work/router$1"
  grep -q '^steps: *18000 at 150 Hz' "$work/out$1" || { echo "FAIL: not 18000 steps"; cat "$work/out$1"; exit 1; }
  # The plant's own count of what its exits took, and what left the world otherwise.
  awk '/^  commissioned [A-E] / { n += $3 } END { print "commissioned: " n; exit !(n >= 20) }' "$work/out$1" ||
    { echo "FAIL: fewer than 20 bottles commissioned"; cat "$work/out$1"; exit 1; }
  grep -q '^  lost (left the world): 0$' "$work/out$1" || { echo "FAIL: bottles lost"; cat "$work/out$1"; exit 1; }
}
run 1
if [ "$mode" = --realtime ]; then
  echo "bottling_plc: in real time with the controller polling: ok"
  exit 0
fi
if [ "$mode" = --once ]; then
  echo "bottling_plc: one lock-step run, the same trace not compared ($(wc -l < "$work/trace1.csv") rows)"
  exit 0
fi
run 2
cmp "$work/trace1.csv" "$work/trace2.csv"
echo "bottling_plc: two lock-step runs, the same trace ($(wc -l < "$work/trace1.csv") rows)"
