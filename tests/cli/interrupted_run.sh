#!/bin/sh
# plant run stopped by a signal: SIGINT (then SIGTERM) during a long run with --trace. The run
# stops at the end of a step, prints its summary marked as interrupted and exits with
# 128 + the signal (130, 143); every row of the trace has the header's column count.
# usage: interrupted_run.sh PLANT_BINARY PLANT_FILE
set -u
plant=$1
file=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*"; cat "$dir/out" "$dir/err" 2>/dev/null; exit 1; }

for sig in INT TERM; do
    "$plant" run "$file" --for 100h --quiet --trace "$dir/trace.csv" --trace-rate 1Hz >"$dir/out" 2>"$dir/err" &
    pid=$!
    sleep 3  # well into the run: at least one 64 KiB block of rows written
    kill -s "$sig" "$pid"
    wait "$pid"
    code=$?
    want=130
    [ "$sig" = TERM ] && want=143
    [ "$code" -eq "$want" ] || fail "SIG$sig: exit code $code, not $want"
    grep -q "^interrupted: *by SIG$sig after " "$dir/out" || fail "SIG$sig: no 'interrupted' line in the summary"
    grep -q "^simulated time:" "$dir/out" || fail "SIG$sig: no summary"
    rows=$(wc -l <"$dir/trace.csv")
    [ "$rows" -gt 100 ] || fail "SIG$sig: only $rows trace rows"
    awk -F, 'NR == 1 { n = NF } NF != n { print "row " NR ": " NF " columns, the header has " n; bad = 1 } END { exit bad }' \
        "$dir/trace.csv" || fail "SIG$sig: a trace row is cut"
    tail -c 1 "$dir/trace.csv" | od -c | grep -q '\\n' || fail "SIG$sig: the trace does not end with a whole row"
    echo "SIG$sig: exit $code, $rows rows, summary: $(grep '^interrupted' "$dir/out")"
done
