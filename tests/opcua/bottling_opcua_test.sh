#!/usr/bin/env bash
# Issue #33 §4: plants/bottling_opcua.plant under the example controller
# (examples/plc/router_opcua.mjs, node-opcua-client in its own process) in lock-step for 120 s
# of plant time: at least 20 bottles commissioned, none lost, none in a wrong lane; and the
# same trace as the bottling line under router.py over Modbus (plants/bottling_plc.plant), bit
# for bit: the same results. That second run, another process with another link and another
# controller, is also the repeat that shows the run deterministic (a second OPC UA run, which
# this test made until 2026-11-27, only took 40 s more; tests/plc/bottling_plc_test.sh runs
# the Modbus one twice).
# With --realtime: once, paced to the wall clock for 60 s, the controller subscribed.
#   tests/opcua/bottling_opcua_test.sh PLANT SOURCE_DIR [--realtime]
set -euo pipefail
plant="$1" src="$2" mode="${3:-}"
work=$(mktemp -d) pid=""
trap 'kill "$pid" 2>/dev/null || true; rm -rf "$work"' EXIT
. "$(dirname "$0")/start_plant.sh"
check_summary() {  # the plant's own count of what its exits took, and what left the world otherwise
  awk -v least="$2" '/^  commissioned [A-E] / { n += $3 } END { print "commissioned: " n; exit !(n >= least) }' "$1" ||
    { echo "FAIL: fewer than $2 bottles commissioned"; cat "$1"; exit 1; }
  grep -q '^  lost (left the world): 0$' "$1" || { echo "FAIL: bottles lost"; cat "$1"; exit 1; }
}
if [ "$mode" = --realtime ]; then
  start_plant 1 run "$src/plants/bottling_opcua.plant" --realtime --opcua-port 0 --for 60s
  timeout 200 node "$src/examples/plc/router_opcua.mjs" "$url" > "$work/router1" ||
    { echo "FAIL: the controller"; tail -5 "$work/router1"; exit 1; }
  wait "$pid"
  tail -1 "$work/router1"
  check_summary "$work/out1" 8
  echo "bottling_opcua: in real time with the controller subscribed: ok"
  exit 0
fi
for run in 1; do
  start_plant $run run "$src/plants/bottling_opcua.plant" --lockstep --opcua-port 0 --for 120s --trace "$work/trace$run.csv"
  timeout 400 node "$src/examples/plc/router_opcua.mjs" "$url" --lockstep 18000 > "$work/router$run" ||
    { echo "FAIL: the controller"; tail -5 "$work/router$run"; exit 1; }
  wait "$pid"
  tail -1 "$work/router$run"
  grep -q '^steps: *18000 at 150 Hz' "$work/out$run" || { echo "FAIL: not 18000 steps"; cat "$work/out$run"; exit 1; }
  check_summary "$work/out$run" 20
done
echo "bottling_opcua: a lock-step run ($(wc -l < "$work/trace1.csv") rows of trace)"
# The Modbus link's controller on the same line (tests/plc/bottling_plc_test.sh's run). The
# err file exists before the child starts, so the first look for the port cannot race it.
: > "$work/err3"
"$plant" run "$src/plants/bottling_plc.plant" --lockstep --modbus-port 0 --for 120s --trace "$work/modbus.csv" \
  > "$work/out3" 2> "$work/err3" &
pid=$!
port=""
for _ in $(seq 150); do
  port=$(sed -n 's/.*Modbus TCP on 127\.0\.0\.1:\([0-9]*\).*/\1/p' "$work/err3")
  [ -n "$port" ] && break
  sleep 0.2
done
[ -n "$port" ] || { echo "FAIL: the Modbus run did not start"; cat "$work/err3"; exit 1; }
timeout 300 /usr/bin/python3 "$src/examples/plc/router.py" "$port" --lockstep 18000 > "$work/router3" ||
  { echo "FAIL: router.py"; tail -5 "$work/router3"; exit 1; }
wait "$pid"
cmp "$work/trace1.csv" "$work/modbus.csv" || { echo "FAIL: OPC UA and Modbus control gave different traces"; exit 1; }
echo "bottling_opcua: the same trace as router.py over Modbus"
