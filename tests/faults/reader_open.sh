#!/usr/bin/env bash
# A forced fault on the bottling plant: S2's ID reader cut open from 20 s to 100 s.
# While it is open no bottle is sent into lane B (every one passes S2); after the release
# routing into lane B resumes; the summary lists the force and the trace marks it.
#   reader_open.sh PLANT_BINARY PLANT_FILE WORK_DIR
set -euo pipefail
plant="$1"; file="$2"; dir="$3"
rm -rf "$dir" && mkdir -p "$dir" && cd "$dir"
"$plant" run "$file" --for 150s --quiet --trace t.csv --trace-rate 1Hz \
  --event "20s force line[0].s2.bottle open" --event "100s release line[0].s2.bottle" > summary.txt
grep -q '^forced: *1$' summary.txt || { echo "FAIL: the summary lists no force"; cat summary.txt; exit 1; }
grep -q '^  line\[0\]\.s2\.bottle  open  *from 20\.000 s to 100\.000 s$' summary.txt ||
  { echo "FAIL: the summary's force line"; cat summary.txt; exit 1; }
awk -F, '
  NR == 1 { for (i = 1; i <= NF; i++) { if ($i == "s2 to lane B") lane = i; if ($i == "forced") forced = i }; next }
  { t = $1 + 0; n = $lane + 0
    if (t > 20.5 && t < 99.5) { during += n; if ($forced != "line[0].s2.sw.reader.volume.object=open") unmarked++ }
    else if (t >= 99.5) after += n
    else before += n }
  END {
    if (!lane || !forced) { print "FAIL: no column \"s2 to lane B\" or \"forced\""; exit 1 }
    printf "into lane B: %d before 20 s, %d while the reader is open, %d after its release\n", before, during, after
    if (during != 0) { print "FAIL: bottles went into lane B while the reader was open"; exit 1 }
    if (after < 1) { print "FAIL: routing into lane B did not resume"; exit 1 }
    if (unmarked) { print "FAIL: " unmarked " trace rows while forced do not mark the force"; exit 1 }
    print "reader_open: ok" }' t.csv
