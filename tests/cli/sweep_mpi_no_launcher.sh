#!/bin/sh
# layerlab sweep --mpi without an MPI launcher (no mpirun, no srun): one
# layerlab line naming --mpi and what to do, none of Open MPI's pages of
# text, a non-zero exit, and nothing written.
. "$(dirname "$0")/sweep_common.sh"
write_sweep "$work/sweep.json" '["solve"]' "[$PUPILS]"
# Whatever launched ctest: this process is not an MPI rank.
if env -u OMPI_COMM_WORLD_SIZE -u PMIX_RANK -u PMI_SIZE -u PMI_RANK timeout 60 \
  "$layerlab" sweep "$work/sweep.json" --out "$work/out" --mpi >"$work/log" 2>&1; then
  fail "--mpi without a launcher exited 0"
fi
grep -q "^layerlab: error: --mpi: this process was not started by an MPI launcher; run it as \`mpirun -np N layerlab sweep" "$work/log" ||
  fail "no layerlab line naming --mpi: $(head -n 5 "$work/log")"
[ "$(wc -l <"$work/log")" -eq 1 ] || fail "more than the one line: $(head -n 5 "$work/log")"
[ ! -e "$work/out" ] || fail "--mpi without a launcher wrote $work/out"
echo "PASS"
