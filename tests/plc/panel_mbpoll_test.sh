#!/usr/bin/env bash
# The bottling line's operator panel over Modbus (plants/bottling_plc.plant, issue #32):
# mbpoll holds Stop down (coil 31 ON, then OFF) and the running lamp (input register 100)
# goes out; it holds Start down (coil 30) and the lamp lights again; the emergency stop
# (coil 32) latches (discrete input 32) and the fault lamp blinks (input register 101 = 2)
# until a reset (coil 33).
#   tests/plc/panel_mbpoll_test.sh PLANT SOURCE_DIR
# Every wait is bounded; the plant runs 40 s of real time at most.
set -euo pipefail
plant="$1" src="$2"
work=$(mktemp -d) pid=""
trap 'kill "$pid" 2>/dev/null || true; rm -rf "$work"' EXIT
. "$(dirname "$0")/start_plant.sh"
start_plant "" "$src/plants/bottling_plc.plant" --realtime --for 40s --modbus-port 0

mb() { mbpoll -m tcp -p "$port" -0 -1 -o 2 "$@" 127.0.0.1; }
coil() { mbpoll -m tcp -p "$port" -0 -1 -o 2 -t 0 -r "$1" 127.0.0.1 "$2" >/dev/null; }   # coil ADDRESS 0|1
# Reads one address of table $1 (1 discrete input, 3 input register) until it holds $3,
# for at most 5 s: the plant takes a few steps to act.
expect() {
  local table="$1" ref="$2" want="$3" what="$4"
  for _ in $(seq 50); do
    if mb -t "$table" -r "$ref" -c 1 | grep -q "^\[$ref\]:[[:space:]]*$want\$"; then
      echo "$what: $want"
      return 0
    fi
    sleep 0.1
  done
  echo "$what never read $want"
  mb -t "$table" -r "$ref" -c 1
  exit 1
}
expect 3 100 1 "running lamp at the start"
coil 31 1       # Stop held down ...
expect 1 31 1 "stop button down"
coil 31 0       # ... and let go
expect 1 31 0 "stop button up"
expect 3 100 0 "running lamp after Stop"
coil 30 1       # Start
coil 30 0
expect 3 100 1 "running lamp after Start"
coil 32 1       # the emergency stop latches ...
expect 1 32 1 "emergency stop engaged"
expect 3 101 2 "fault lamp"
expect 3 100 0 "running lamp after the emergency stop"
coil 30 1       # ... Start does nothing while it is latched
coil 30 0
sleep 0.3
expect 3 100 0 "running lamp after Start while latched"
coil 33 1       # reset, then Start
expect 1 32 0 "emergency stop after reset"
expect 3 101 0 "fault lamp after reset"
coil 30 1
coil 30 0
expect 3 100 1 "running lamp after reset and Start"
kill -INT "$pid"
wait "$pid" || true
echo "mbpoll: the panel's Start, Stop and emergency stop work over Modbus"
