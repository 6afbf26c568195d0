#!/usr/bin/env bash
# Debian's mbpoll against the link plants/bottling_plc.plant declares (issue #15): it reads
# S2's ID reader as a discrete input while a bottle passes it, and writing a coil stops
# belt B1 (the plant's record of b1.stop counts one; B1 then reads not running, 0 mm/s).
#   tests/plc/mbpoll_test.sh PLANT SOURCE_DIR
# Every wait is bounded; the plant runs 90 s of real time at most (the first bottle reaches
# S2 after about 25 s: it goes round the stations first).
set -euo pipefail
plant="$1" src="$2"
work=$(mktemp -d) pid=""
trap 'kill "$pid" 2>/dev/null || true; rm -rf "$work"' EXIT
. "$(dirname "$0")/start_plant.sh"
start_plant "" "$src/plants/bottling_plc.plant" --realtime --for 90s --modbus-port 0

# Poll discrete input 0 every 10 ms (mbpoll's fastest) for at most 75 s, until it reads 1:
# a bottle in S2's ID reader. (No controller: every bottle passes S2 straight on.)
set +o pipefail
timeout 75 stdbuf -oL mbpoll -m tcp -p "$port" -0 -t 1 -r 0 -c 1 -l 10 -o 2 127.0.0.1 2>&1 |
  tee "$work/poll" | grep -q -m1 '^\[0\]:[[:space:]]*1' ||
  { echo "mbpoll never saw a bottle at S2's reader"; tail -5 "$work/poll"; exit 1; }
set -o pipefail
echo "discrete input 0: 1 after $(grep -c '^\[0\]:' "$work/poll") polls"

# Belt B1 runs at 500 mm/s (input register 5, discrete input 1: running); coil 20 (b1.stop)
# written ON with mbpoll stops it: then it reads 0 mm/s and not running.
mbpoll -m tcp -p "$port" -0 -1 -o 2 -t 3 -r 5 -c 1 127.0.0.1 | tee "$work/speed"
grep -q '^\[5\]:[[:space:]]*500' "$work/speed"
mbpoll -m tcp -p "$port" -0 -1 -o 2 -t 1 -r 1 -c 1 127.0.0.1 | tee "$work/running"
grep -q '^\[1\]:[[:space:]]*1' "$work/running" || { echo "b1 does not read running"; exit 1; }
mbpoll -m tcp -p "$port" -0 -1 -o 2 -t 0 -r 20 127.0.0.1 1
sleep 0.5
mbpoll -m tcp -p "$port" -0 -1 -o 2 -t 3 -r 5 -c 1 127.0.0.1 | tee "$work/speed"
grep -q '^\[5\]:[[:space:]]*0' "$work/speed" || { echo "a stopped b1 does not read 0 mm/s"; exit 1; }
mbpoll -m tcp -p "$port" -0 -1 -o 2 -t 1 -r 1 -c 1 127.0.0.1 | tee "$work/running"
grep -q '^\[1\]:[[:space:]]*0' "$work/running" || { echo "a stopped b1 reads running"; exit 1; }
kill -INT "$pid"
wait "$pid" || true
# The plant's own count of b1.stop's activations (a record of the plant).
grep -q '^  b1 stopped  *1 events' "$work/out" || { echo "b1.stop was not driven once"; cat "$work/out"; exit 1; }
echo "mbpoll: a bottle seen at S2, b1 stopped by coil 20"
