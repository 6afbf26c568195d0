#!/usr/bin/env bash
# Debian's mbpoll against the PLC link (issue #15): it reads S2's ID reader as a discrete
# input while a bottle passes it, and writing a coil stops belt b1.
#   tests/plc/mbpoll_test.sh HARNESS
# Every wait is bounded; the harness runs 40 s of real time at most.
set -euo pipefail
harness="$1"
work=$(mktemp -d)
trap 'kill "$pid" 2>/dev/null || true; rm -rf "$work"' EXIT
"$harness" --warmup 20s --for 40s --port-file "$work/port" > "$work/out" 2>&1 &
pid=$!
for _ in $(seq 100); do [ -s "$work/port" ] && break; sleep 0.2; done
[ -s "$work/port" ] || { echo "the harness did not start serving"; cat "$work/out"; exit 1; }
port=$(cat "$work/port")

# Poll discrete input 0 every 10 ms (mbpoll's fastest) for at most 20 s, until it reads 1:
# a bottle in S2's ID reader.
set +o pipefail
timeout 20 stdbuf -oL mbpoll -m tcp -p "$port" -0 -t 1 -r 0 -c 1 -l 10 -o 2 127.0.0.1 2>&1 |
  tee "$work/poll" | grep -q -m1 '^\[0\]:[[:space:]]*1' ||
  { echo "mbpoll never saw a bottle at S2's reader"; tail -5 "$work/poll"; exit 1; }
set -o pipefail
echo "discrete input 0: 1 after $(grep -c '^\[0\]:' "$work/poll") polls"

# Belt b1 runs at 500 mm/s (input register 2); coil 0 (b1.stop) written ON with mbpoll stops it.
mbpoll -m tcp -p "$port" -0 -1 -o 2 -t 3 -r 2 -c 1 127.0.0.1 | tee "$work/speed"
grep -q '^\[2\]:[[:space:]]*500' "$work/speed"
mbpoll -m tcp -p "$port" -0 -1 -o 2 -t 0 -r 0 127.0.0.1 1
sleep 0.5
kill -INT "$pid"
wait "$pid" || true
cat "$work/out"
grep -q '^line\[0\].b1.drive: off' "$work/out"
grep -q ' 0 dropped' "$work/out"
echo "mbpoll: a bottle seen at S2, b1 stopped by coil 0"
