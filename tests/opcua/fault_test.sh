#!/usr/bin/env bash
# Issue #33: a Force open on S2's reader through the OPC UA link, as the Modbus fault test
# does (tests/plc/bottling_plc_fault_test.sh): the example controller
# (examples/plc/router_opcua.mjs) calls Link.Force(ns=2;i=2, "open") — node 2 is S2's reader
# (`line[0].s2.seen`) — at step 2250 (15 s) and Link.Release at step 9750 (65 s). While it
# is open the controller sees no bottle at S2, so none goes into lane B; the summary lists
# the forced slot (from 15.007 s: a call between steps applies in the next step) and the
# trace's `forced` column marks it; after the release routing into lane B resumes. (Without
# the force three bottles go into lane B in that window; 150 s with the force from 20 s to
# 100 s took 64 s in the ci build.)
#   tests/opcua/fault_test.sh PLANT SOURCE_DIR
set -euo pipefail
plant="$1" src="$2"
work=$(mktemp -d) pid=""
trap 'kill "$pid" 2>/dev/null || true; rm -rf "$work"' EXIT
. "$(dirname "$0")/start_plant.sh"
start_plant "" run "$src/plants/bottling_opcua.plant" --lockstep --opcua-port 0 --for 85s \
  --trace "$work/t.csv" --trace-rate 1Hz
timeout 400 node "$src/examples/plc/router_opcua.mjs" "$url" --lockstep 12750 --fault 2 2250 9750 \
  > "$work/router" || { echo "FAIL: the controller"; tail -5 "$work/router"; exit 1; }
wait "$pid"
grep -q '^  line\[0\]\.s2\.seen  open  *from 15\.007 s to 65\.007 s$' "$work/out" ||
  { echo "FAIL: the summary does not list the forced slot"; cat "$work/out"; exit 1; }
awk -F, '
  NR == 1 { for (i = 1; i <= NF; i++) { if ($i == "s2 to lane B") lane = i; if ($i == "forced") forced = i }; next }
  { t = $1 + 0; if (t > 15.5 && t < 64.5) during += $lane; else if (t >= 64.5) after += $lane; else before += $lane }
  forced && t > 15.5 && t < 64.5 && $forced ~ /line\[0\]\..*=open/ { marked++ }
  END {
    if (!lane) { print "FAIL: no column \"s2 to lane B\""; exit 1 }
    if (marked < 49) { printf "FAIL: the trace marks the link'"'"'s force in %d of the 49 rows from 16 s to 64 s\n", marked; exit 1 }
    printf "into lane B: %d before 15 s, %d while S2'"'"'s reader is open, %d after its release\n", before, during, after
    if (during != 0) { print "FAIL: bottles went into lane B while the reader was open"; exit 1 }
    if (after < 1) { print "FAIL: routing into lane B did not resume"; exit 1 }
    print "bottling_opcua fault: ok" }' "$work/t.csv"
