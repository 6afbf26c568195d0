#!/usr/bin/env bash
# The compiler on the bottling plant at lines = 1, 10, 100, 400 (`plant check --set lines=N`):
# wall time and peak memory, median of 3; prints one row of bench/run.sh's table. Linear means
# the time per line stays flat as the plant grows (dynamic slots `(ref as T).member` included).
#   bash bench/compile_lines.sh [PLANT_BINARY]
set -euo pipefail
cd "$(dirname "$0")/.."
plant="${1:-build/release/app/plant}"
cells=()
per=()
for n in 1 10 100 400; do
  runs=()
  for r in 1 2 3; do
    runs+=("$( { /usr/bin/time -f '%e %M' "$plant" check plants/bottling.plant --set "lines=$n" > /dev/null; } 2>&1 | tail -1)")
  done
  med=$(printf '%s\n' "${runs[@]}" | sort -n | sed -n 2p)
  s=${med% *}; kb=${med#* }
  cells+=("$n: ${s} s, $((kb / 1024)) MiB")
  per+=("$(awk -v s="$s" -v n="$n" 'BEGIN { printf "%.1f", 1000 * s / n }')")
done
ratio=$(awk -v a="${per[2]}" -v b="${per[3]}" 'BEGIN { printf "%.2f", b / a }')
met=$(awk -v r="$ratio" 'BEGIN { print (r <= 1.3) ? "yes" : "**no**" }')
echo "| compiler | plants/bottling.plant by lines (plant check; ms per line at 100 and 400: ${per[2]}, ${per[3]}) | $(IFS=';'; echo "${cells[*]}" | sed 's/;/; /g') | linear (ms per line at 400 / at 100 <= 1.3: ${ratio}) | $met |"
