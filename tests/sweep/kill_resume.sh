#!/usr/bin/env bash
# SIGKILL to one run mid-sweep: every other row is intact, the killed run's row says lost,
# and --resume runs it again and completes the sweep.
#   kill_resume.sh PLANT SPEC WORKDIR
set -euo pipefail
plant="$1" spec="$2" dir="$3"
here="$(cd "$(dirname "$0")" && pwd)"
rm -rf "$dir"
"$plant" sweep "$spec" -j 2 --out "$dir" > /dev/null 2> "$dir.log" &
sweep=$!
victim=""
for _ in $(seq 1 200); do  # up to 10 s for a run to start
  victim=$(pgrep -P "$sweep" | head -1 || true)
  [ -n "$victim" ] && break
  sleep 0.05
done
[ -n "$victim" ] || { echo "kill_resume: no run started"; kill "$sweep"; exit 1; }
kill -KILL "$victim"
wait "$sweep"
cat "$dir.log"
csv="$dir/results.csv"
rows=$(($(wc -l < "$csv") - 1))
lost=$(grep -c ',lost,killed by signal 9' "$csv" || true)
ok=$(grep -c ',ok,' "$csv" || true)
echo "kill_resume: after the kill: $rows rows, $ok ok, $lost lost"
[ "$rows" -eq 4 ] && [ "$lost" -eq 1 ] && [ "$ok" -eq 3 ] || { cat "$csv"; exit 1; }
"$here/strip.sh" "$csv" | grep ',ok,' > "$dir.before"
"$plant" sweep "$spec" -j 2 --out "$dir" --resume > /dev/null
rows=$(($(wc -l < "$csv") - 1))
ok=$(grep -c ',ok,' "$csv" || true)
echo "kill_resume: after --resume: $rows rows, $ok ok"
[ "$rows" -eq 4 ] && [ "$ok" -eq 4 ] || { cat "$csv"; exit 1; }
# The three rows that were there are unchanged.
"$here/strip.sh" "$csv" | grep -F -x -f "$dir.before" | wc -l | grep -qx 3 || { echo "kill_resume: rows changed"; exit 1; }
echo "kill_resume: ok"
