#!/usr/bin/env bash
# plant sweep SPEC -j 2, mpirun -n 3 and mpirun -n 1 write the same rows (rtf and wall_s aside).
#   same_csv.sh PLANT SPEC FOR WORKDIR
set -euo pipefail
plant="$1" spec="$2" for="$3" dir="$4"
here="$(cd "$(dirname "$0")" && pwd)"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
rm -rf "$dir" && mkdir -p "$dir"
"$plant" sweep "$spec" -j 2 --for "$for" --out "$dir/j2" > /dev/null
mpirun --oversubscribe -n 3 "$plant" sweep "$spec" --for "$for" --out "$dir/mpi3" > /dev/null
mpirun -n 1 "$plant" sweep "$spec" --for "$for" --out "$dir/mpi1" > /dev/null
rows=$(($(wc -l < "$dir/j2/results.csv") - 1))
ok=$(grep -c ',ok,' "$dir/j2/results.csv" || true)
echo "same_csv: $rows runs, $ok ok"
[ "$rows" -gt 1 ] && [ "$ok" -eq "$rows" ] || { echo "same_csv: expected every run ok"; exit 1; }
"$here/strip.sh" "$dir/j2/results.csv" > "$dir/j2.csv"
for run in mpi3 mpi1; do
  "$here/strip.sh" "$dir/$run/results.csv" > "$dir/$run.csv"
  diff "$dir/j2.csv" "$dir/$run.csv" || { echo "same_csv: $run differs from -j 2"; exit 1; }
done
echo "same_csv: -j 2, mpirun -n 3 and mpirun -n 1 agree"
