#!/usr/bin/env bash
# Runs on the many-core machine from the folder bench/many_core.sh bundled (copied there as
# run.sh): the bottling plant's thread table, Markdown on stdout, everything in log.txt beside it.
#   bash run.sh [--quick]
set -uo pipefail
cd "$(dirname "$0")"
quick=0
case "${1:-}" in
  "") ;;
  --quick) quick=1 ;;
  *) echo "usage: run.sh [--quick]" >&2; exit 2 ;;
esac
log=$PWD/log.txt
: > "$log"
who=(this)
[[ -d base ]] && who=(this base)
cores=$(nproc)
counts=()
for ((t = 1; t <= cores; t *= 2)); do counts+=("$t"); done
((counts[${#counts[@]} - 1] == cores)) || counts+=("$cores")
if ((quick)); then
  size=(--counts=200 --warmup=5 --window=2) big=(--counts=1000 --warmup=5 --window=2)
else
  size=(--counts=1000 --warmup=20 --window=5) big=(--counts=5000 --warmup=20 --window=5)
fi

# One run of one binary; prints its table row (the bench's own Markdown row).
bench() {  # name args...
  local name=$1
  shift
  echo "== $name $* [load $(cut -d' ' -f1-3 /proc/loadavg)]" >> "$log"
  local out
  out=$(PLANT_STDLIB="$PWD/$name/stdlib" timeout 600 ./ld.so --library-path ./lib "./$name/plant_bench_bottling" \
          --plant="$PWD/$name/plants/bottling.plant" --runs=1 --no-memory "$@" 2>&1)
  local rc=$?
  echo "$out" >> "$log"
  ((rc == 0)) || { echo "many_core: $name $* failed (rc $rc; $log)" >&2; return 1; }
  grep -m1 -E '^\| *[0-9]+ \|' <<< "$out"
}
# A row's fields: wall s, CPU s, real-time factor, CPU us per bottle-step (the bench's columns
# counted from the right: peak RSS and allocations come last).
field() { awk -F'|' -v k="$2" '{print $(NF - k)}' <<< "$1" | sed 's/^ *//; s/ *$//'; }

bench this --counts=10 --warmup=1 --window=1 --threads="$cores" > /dev/null || exit 1
echo "# The bottling plant on 1 to $cores threads"
echo
echo "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), $cores cores," \
     "$(date -u +%Y-%m-%d), load before $(cut -d' ' -f1-3 /proc/loadavg); $(paste -sd, what.txt);" \
     "plant_bench_bottling ${size[*]} --runs=1 --no-memory, single runs, the binaries in turns."
echo
head="| threads |" rule="|---:|"
for w in "${who[@]}"; do
  head+=" $w: real-time factor (CPU µs per bottle-step) | $w: speed-up on 1 thread's |"
  rule+="---:|---:|"
done
echo "$head"
echo "$rule"
declare -A one
for t in "${counts[@]}"; do
  line="| $t |"
  for w in "${who[@]}"; do
    row=$(bench "$w" "${size[@]}" --threads="$t") || exit 1
    wall=$(field "$row" 6) rtf=$(field "$row" 4) cpu=$(field "$row" 3)
    [[ -n "${one[$w]:-}" ]] || one[$w]=$wall
    line+=" ${rtf}x ($cpu) | $(awk -v a="${one[$w]}" -v b="$wall" 'BEGIN{printf "%.1fx", a / b}') |"
  done
  echo "$line"
done
echo
row=$(bench this "${big[@]}" --threads="$cores") || exit 1
echo "$(field "$row" 13) bottles wanted, $(field "$row" 9) in circulation, on $cores threads:" \
     "$(field "$row" 4)x real time ($(field "$row" 3) CPU µs per bottle-step)."
echo
bench this "${size[@]}" --threads="$cores" --profile > /dev/null || exit 1
awk '/^Where a step goes/,0' <(sed -n '/^== this.*--profile/,$p' "$log")
