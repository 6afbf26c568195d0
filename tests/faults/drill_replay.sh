#!/usr/bin/env bash
# A conditional drill in `plant run` (docs/training.md, "Drills"): S2's reader is cut when
# the third bottle reaches S2, and repaired when Start is pressed. What fired is written
# as the timed events it became (--drill-events); replaying those with --events, without
# the drill, gives the same trace byte for byte and the same counters.
#   drill_replay.sh PLANT_BINARY PLANT_FILE WORK_DIR
set -euo pipefail
plant="$1"; file="$2"; dir="$3"
rm -rf "$dir" && mkdir -p "$dir" && cd "$dir"
cat > s2.drill <<'DRILL'
# S2's reader goes blind when the third bottle reaches S2; Start repairs it.
when line[0].s2.seen >= 3 force line[0].s2.sw.reader.bottle open repaired by line[0].ops.start.press
DRILL
common=(--for 50s --quiet --trace-rate 10Hz --summary=json --event "45s line[0].ops.start.press")
"$plant" run "$file" "${common[@]}" --drill s2.drill --drill-events fired.events --trace live.csv > live.json
grep -q '^[0-9.]*s force line\[0\]\.s2\.sw\.reader\.bottle open$' fired.events ||
  { echo "FAIL: the drill's force is not in fired.events"; cat fired.events; exit 1; }
grep -q '^45\.007s release line\[0\]\.s2\.sw\.reader\.bottle$' fired.events ||
  { echo "FAIL: the repair's release is not at the step after Start (45.007 s)"; cat fired.events; exit 1; }
grep -q '^# drill 1 by drill file: when line\[0\]\.s2\.seen >= 3 force ' fired.events ||
  { echo "FAIL: fired.events does not say the drill as scheduled"; cat fired.events; exit 1; }
grep -q '^# end 50\.000s$' fired.events || { echo "FAIL: no '# end' line"; cat fired.events; exit 1; }
"$plant" run "$file" "${common[@]}" --events fired.events --trace replay.csv > replay.json
cmp live.csv replay.csv || { echo "FAIL: the replay's trace differs from the drilled run's"; exit 1; }
strip() { grep -v '"wall_time_s"\|"real_time_factor"' "$1"; }
diff <(strip live.json) <(strip replay.json) || { echo "FAIL: the replay's summary differs"; exit 1; }
grep -q '"path": "line\[0\].s2.sw.reader.bottle"' live.json || { echo "FAIL: the summary lists no force"; exit 1; }
# A bad drill line is refused with FILE:LINE:COL.
printf '\n  when line[0].s2.seen >= x force line[0].s2.sw.reader.bottle open\n' > bad.drill
if "$plant" run "$file" --for 1s --quiet --drill bad.drill 2> bad.err; then echo "FAIL: a bad drill ran"; exit 1; fi
grep -q "bad.drill:2:3: 'when line\[0\].s2.seen >= x': 'x' is not a number" bad.err ||
  { echo "FAIL: the bad drill's message"; cat bad.err; exit 1; }
echo "drill fired at $(grep -m1 'force' fired.events | cut -d' ' -f1), released at 45.007s; replay identical"
echo "drill_replay: ok"
