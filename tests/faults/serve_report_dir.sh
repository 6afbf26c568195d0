#!/usr/bin/env bash
# `plant serve --drill FILE --report-dir DIR` (docs/training.md): a served session, as fast as
# the machine goes, whose drill fires on a condition; stopped with SIGTERM, the server writes
# the session's report and events into DIR, the drill's force among them as the timed event
# it became. Bounded: at most 20 s for the URL, 120 s for the drill to fire (the session's
# events polled with curl), 60 s to stop.
#   serve_report_dir.sh PLANT_BINARY PLANT_FILE WORK_DIR
set -euo pipefail
plant="$1"; file="$2"; dir="$3"
rm -rf "$dir" && mkdir -p "$dir" && cd "$dir"
echo 'when line[0].s2.seen >= 2 force line[0].s2.sw.reader.bottle open' > s2.drill
: > out.txt
"$plant" serve "$file" --port 0 --speed 0 --drill s2.drill --report-dir rep > out.txt 2> err.txt &
pid=$!
for _ in $(seq 200); do grep -q 'plant serve: trainees:' out.txt && break; sleep 0.1; done
grep -q 'plant serve: trainees:' out.txt || { echo "FAIL: no URL"; cat out.txt err.txt; kill $pid; exit 1; }
url=$(sed -n 's/^plant serve: instructor: //p' out.txt)
events="${url%%\?*}events?${url#*\?}"
for _ in $(seq 600); do
  curl -sf "$events" > events.txt && grep -q '^[0-9.]*s force line\[0\]\.s2\.sw\.reader\.bottle open$' events.txt && break
  sleep 0.2
done
kill -TERM $pid
for _ in $(seq 600); do kill -0 $pid 2> /dev/null || break; sleep 0.1; done
if kill -0 $pid 2> /dev/null; then echo "FAIL: the server did not stop"; kill -KILL $pid; exit 1; fi
wait $pid || { echo "FAIL: the server's exit code"; cat out.txt err.txt; exit 1; }
cat out.txt
grep -q '^plant serve: report: rep/report.md, rep/report.html, rep/session.events (1 faults, 1 events, ' out.txt ||
  { echo "FAIL: no report line"; cat err.txt; exit 1; }
grep -q '^# by drill 1 at ' rep/session.events && grep -q '^[0-9.]*s force line\[0\]\.s2\.sw\.reader\.bottle open$' rep/session.events ||
  { echo "FAIL: the drill's force is not in session.events"; cat rep/session.events; exit 1; }
grep -q '^| set | [0-9.]* s by drill 1 |$' rep/report.md || { echo "FAIL: the report's fault"; cat rep/report.md; exit 1; }
grep -q '^| drill | 1 by drill file: when line\[0\]\.s2\.seen >= 2 force line\[0\]\.s2\.sw\.reader\.bottle open |$' rep/report.md ||
  { echo "FAIL: the report does not name the fault's drill"; cat rep/report.md; exit 1; }
test -s rep/report.html
echo "serve_report_dir: ok"
