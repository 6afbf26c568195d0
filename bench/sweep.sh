#!/usr/bin/env bash
# The sweep's throughput: plants/sweeps/feed.sweep (60 runs) with -j 1, then -j 2, on this
# machine; prints one row of bench/run.sh's table. The ratio is what the second core is worth.
#   bash bench/sweep.sh PLANT_BINARY [SIMULATED_TIME_PER_RUN]   (default 30s)
set -euo pipefail
cd "$(dirname "$0")/.."
plant="${1:-build/release/app/plant}"
for="${2:-30s}"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
rate() {  # runs per minute with -j $1
  local start end runs
  start=$(date +%s.%N)
  "$plant" sweep plants/sweeps/feed.sweep -j "$1" --for "$for" --out "$dir/j$1" > /dev/null 2>&1
  end=$(date +%s.%N)
  runs=$(($(wc -l < "$dir/j$1/results.csv") - 1))
  awk -v n="$runs" -v s="$start" -v e="$end" 'BEGIN { printf "%.1f", n * 60 / (e - s) }'
}
r1=$(rate 1)
r2=$(rate 2)
ratio=$(awk -v a="$r1" -v b="$r2" 'BEGIN { printf "%.2f", b / a }')
met=$(awk -v r="$ratio" 'BEGIN { print (r >= 1.8) ? "yes" : "**no**" }')
echo "| sweep | plant sweep feed.sweep (60 runs of $for), runs per minute, -j 1 vs -j 2 | $r1 vs $r2 (x$ratio) | x1.8 or more | $met |"
