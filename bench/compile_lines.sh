#!/usr/bin/env bash
# The compiler on the bottling plant at lines = 1, 10, 100, 400 (`plant check --set lines=N`):
# wall time and peak memory, median of 3; prints one row of bench/run.sh's table. Linear means
# the time per line stays flat as the plant grows (dynamic slots `(ref as T).member` included).
# The sizes are taken in turns (1, 10, 100, 400, then again), and the ratio of the time per
# line at 400 to that at 100 is the median of the three rounds' ratios: this VM's speed drifts
# by 2x within minutes, and sizes measured one after the other read that drift as growth.
#   bash bench/compile_lines.sh [PLANT_BINARY]
set -euo pipefail
cd "$(dirname "$0")/.."
plant="${1:-build/release/app/plant}"
sizes=(1 10 100 400)
declare -A runs  # "size round" -> "seconds kilobytes"
for r in 1 2 3; do
  for n in "${sizes[@]}"; do
    runs[$n $r]="$( { /usr/bin/time -f '%e %M' "$plant" check plants/bottling.plant --set "lines=$n" > /dev/null; } 2>&1 | tail -1)"
  done
done
cells=()
per=()
for n in "${sizes[@]}"; do
  med=$(printf '%s\n' "${runs[$n 1]}" "${runs[$n 2]}" "${runs[$n 3]}" | sort -n | sed -n 2p)
  s=${med% *}; kb=${med#* }
  cells+=("$n: ${s} s, $((kb / 1024)) MiB")
  per+=("$(awk -v s="$s" -v n="$n" 'BEGIN { printf "%.1f", 1000 * s / n }')")
done
ratios=()
for r in 1 2 3; do
  a=${runs[100 $r]% *}; b=${runs[400 $r]% *}
  ratios+=("$(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.2f", (b / 400) / (a / 100) }')")
done
ratio=$(printf '%s\n' "${ratios[@]}" | sort -n | sed -n 2p)
range="$(printf '%s\n' "${ratios[@]}" | sort -n | sed -n 1p) to $(printf '%s\n' "${ratios[@]}" | sort -n | sed -n 3p)"
met=$(awk -v r="$ratio" 'BEGIN { print (r <= 1.3) ? "yes" : "**no**" }')
echo "| compiler | plants/bottling.plant by lines (plant check; ms per line at 100 and 400: ${per[2]}, ${per[3]}; sizes in turns, 3 rounds) | $(IFS=';'; echo "${cells[*]}" | sed 's/;/; /g') | linear (ms per line at 400 / at 100, median of the rounds' ratios ${range}: ${ratio}; <= 1.3) | $met |"
