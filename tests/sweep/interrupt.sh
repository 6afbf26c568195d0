#!/usr/bin/env bash
# Ctrl-C (SIGINT) during a sweep: the runs going on are stopped and written as lost, the
# sweep says how many runs finished and the command that completes it, exits 130; that
# command (--resume) then runs the rest. While it ran, the log had a progress line with
# the time left.
#   interrupt.sh PLANT SPEC WORKDIR
set -euo pipefail
plant="$1" spec="$2" dir="$3"
rm -rf "$dir" "$dir".*
"$plant" sweep "$spec" -j 2 --out "$dir" > /dev/null 2> "$dir.log" &
sweep=$!
for _ in $(seq 1 400); do  # up to 20 s for a first run to end
  [ "$(cat "$dir/results.csv" 2>/dev/null | wc -l)" -ge 2 ] && break
  sleep 0.05
done
kill -INT "$sweep"
code=0
wait "$sweep" || code=$?
cat "$dir.log"
[ "$code" -eq 130 ] || { echo "interrupt: exit code $code, expected 130"; exit 1; }
grep -q "^plant sweep: 1/4 runs done, 0 not ok, 1 running, about [0-9].* left$" "$dir.log" ||
  { echo "interrupt: no progress line"; exit 1; }
line=$(grep "^plant sweep: interrupted (Ctrl-C, SIGINT): [1-4] of 4 runs finished, in $dir/results.csv; \`plant sweep .* --out $dir --resume\` runs the other [0-3]$" "$dir.log") ||
  { echo "interrupt: no closing message"; exit 1; }
finished=$(echo "$line" | sed 's/.*: \([1-4]\) of 4 runs finished.*/\1/')
ok=$(grep -c ',ok,' "$dir/results.csv" || true)
[ "$ok" -eq "$finished" ] || { echo "interrupt: $finished finished, $ok rows ok"; cat "$dir/results.csv"; exit 1; }
if grep -v '^run,' "$dir/results.csv" | grep -v ',ok,' | grep -qv ',lost,the sweep was interrupted (Ctrl-C; SIGINT),'; then
  echo "interrupt: a row neither ok nor lost by the interruption"; cat "$dir/results.csv"; exit 1
fi
[ ! -e "$dir/summary.md" ] && [ ! -e "$dir/.lock" ] || { echo "interrupt: summary or lock left"; ls -a "$dir"; exit 1; }
again=$(echo "$line" | sed 's/.*`\(plant sweep .*\)`.*/\1/')
"$plant" ${again#plant } -j 2 > /dev/null 2>&1
ok=$(grep -c ',ok,' "$dir/results.csv" || true)
[ "$ok" -eq 4 ] && [ -s "$dir/summary.md" ] || { echo "interrupt: --resume did not complete it"; cat "$dir/results.csv"; exit 1; }
echo "interrupt: ok"
