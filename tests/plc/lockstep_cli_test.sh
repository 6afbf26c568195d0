#!/usr/bin/env bash
# `plant run --lockstep` driven by a pymodbus client (lockstep_client.py): the run steps
# only as granted, and two runs with the same client sequence write the same trace.
#   tests/plc/lockstep_cli_test.sh PLANT SOURCE_DIR
set -euo pipefail
plant="$1" src="$2"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
run() {
  : > "$work/err$1"  # before the background run's own redirection makes it: sed below must find it
  "$plant" run "$src/plants/bottling.plant" --lockstep --modbus-port 0 --for 2s --quiet \
    --trace "$work/trace$1.csv" --trace-bodies > "$work/out$1" 2> "$work/err$1" &
  local pid=$! port=""
  for _ in $(seq 150); do
    port=$(sed -n 's/.*Modbus TCP on 127\.0\.0\.1:\([0-9]*\).*/\1/p' "$work/err$1")
    [ -n "$port" ] && break
    sleep 0.2
  done
  [ -n "$port" ] || { echo "plant run did not start its Modbus server"; cat "$work/err$1"; kill "$pid"; exit 1; }
  /usr/bin/python3 "$src/tests/plc/lockstep_client.py" "$port" 300 37
  wait "$pid"
  grep -q '^steps: *300 at 150 Hz' "$work/out$1"
}
run 1
run 2
cmp "$work/trace1.csv" "$work/trace2.csv"
echo "lock-step: two runs, the same trace ($(wc -l < "$work/trace1.csv") rows)"
