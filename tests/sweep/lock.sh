#!/usr/bin/env bash
# One sweep at a time in an --out folder: while a sweep runs, a second one there (with or
# without --resume) is refused and names the first; once the first is killed (SIGKILL: its
# lock file stays), --resume takes the folder over and completes the sweep. The log shows
# progress lines.
#   lock.sh PLANT SPEC WORKDIR
set -euo pipefail
plant="$1" spec="$2" dir="$3"
rm -rf "$dir" "$dir".*
# Runs of 1000 s: the first sweep is still at its first run whatever the machine's speed.
"$plant" sweep "$spec" -j 1 --for 1000s --out "$dir" > /dev/null 2> "$dir.first" &
first=$!
for _ in $(seq 1 200); do  # up to 10 s for it to take the folder
  [ -s "$dir/.lock" ] && [ -s "$dir/results.csv" ] && break
  sleep 0.05
done
[ -s "$dir/.lock" ] || { echo "lock: the first sweep made no lock"; kill "$first"; exit 1; }
code=0
"$plant" sweep "$spec" --out "$dir" --resume > /dev/null 2> "$dir.second" || code=$?
cat "$dir.second"
[ "$code" -eq 2 ] && grep -q "is in use by another sweep (pid $first on " "$dir.second" ||
  { echo "lock: a --resume beside a running sweep was not refused (exit $code)"; kill "$first"; exit 1; }
code=0
"$plant" sweep "$spec" --out "$dir" > /dev/null 2> "$dir.third" || code=$?
[ "$code" -eq 2 ] && grep -q "is in use by another sweep" "$dir.third" ||
  { echo "lock: a second sweep beside a running one was not refused (exit $code)"; kill "$first"; exit 1; }
kill -KILL "$first"
wait "$first" || true
[ -e "$dir/.lock" ] || { echo "lock: expected the killed sweep's lock file to stay"; exit 1; }
"$plant" sweep "$spec" -j 2 --out "$dir" --resume > /dev/null 2> "$dir.resume"
cat "$dir.resume"
grep -q "was left by a sweep that did not end (pid $first on .*): taken over" "$dir.resume" ||
  { echo "lock: the stale lock was not taken over"; exit 1; }
grep -q "^plant sweep: 4/4 runs done, 0 not ok, in " "$dir.resume" || { echo "lock: no closing progress line"; exit 1; }
ok=$(grep -c ',ok,' "$dir/results.csv" || true)
[ "$ok" -eq 4 ] && [ ! -e "$dir/.lock" ] && [ ! -e "$dir/work" ] || { cat "$dir/results.csv"; ls -a "$dir"; exit 1; }
echo "lock: ok"
