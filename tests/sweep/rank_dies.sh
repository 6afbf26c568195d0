#!/usr/bin/env bash
# Under mpirun (with orte_enable_recovery), SIGKILL to one worker rank mid-sweep: rank 0
# reports that rank's run lost, the other ranks finish every other run, and --resume
# completes the sweep.
#   rank_dies.sh PLANT SPEC WORKDIR
set -euo pipefail
plant="$1" spec="$2" dir="$3"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
rm -rf "$dir"
mpirun --mca orte_enable_recovery 1 --oversubscribe -n 3 "$plant" sweep "$spec" --out "$dir" > /dev/null 2> "$dir.log" &
job=$!
victim=""
for _ in $(seq 1 200); do  # up to 10 s for rank 2 to start its first run
  for pid in $(pgrep -f "plant-sweep-mpi $spec --out $dir" || true); do
    if tr '\0' '\n' < "/proc/$pid/environ" 2>/dev/null | grep -qx 'OMPI_COMM_WORLD_RANK=2' && pgrep -P "$pid" > /dev/null; then
      victim=$pid
    fi
  done
  [ -n "$victim" ] && break
  sleep 0.05
done
[ -n "$victim" ] || { echo "rank_dies: rank 2 never ran"; kill "$job"; exit 1; }
kill -KILL "$victim"
wait "$job" || true
cat "$dir.log"
csv="$dir/results.csv"
rows=$(($(wc -l < "$csv") - 1))
lost=$(grep -c ',lost,MPI rank 2 died during the run' "$csv" || true)
ok=$(grep -c ',ok,' "$csv" || true)
echo "rank_dies: after the kill: $rows rows, $ok ok, $lost lost"
[ "$rows" -eq 4 ] && [ "$lost" -eq 1 ] && [ "$ok" -eq 3 ] || { cat "$csv"; exit 1; }
"$plant" sweep "$spec" -j 2 --out "$dir" --resume > /dev/null
ok=$(grep -c ',ok,' "$csv" || true)
echo "rank_dies: after --resume: $ok ok"
[ "$ok" -eq 4 ] || { cat "$csv"; exit 1; }
echo "rank_dies: ok"
