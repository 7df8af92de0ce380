#!/bin/sh
# mpirun -np N layerlab sweep --mpi: job i runs on rank i mod N (with 3 ranks
# and 4 jobs the split is uneven), rank 0 gathers, and every result equals
# the process pool's, bit for bit (each job is the same deterministic solve).
# Expects: $1 LAYERLAB, $2 EXAMPLES_DIR, $3 WORK_DIR, $4 MPIEXEC, $5 RANKS.
. "$(dirname "$0")/sweep_common.sh"
mpiexec=$4 ranks=$5
sweep=$work/sweep.json
write_sweep "$sweep" '["solve"]' "[$PUPILS, $COMBINERS]"
"$mpiexec" --oversubscribe --allow-run-as-root -np "$ranks" "$layerlab" sweep "$sweep" --out "$work/mpi" --mpi \
  >"$work/log" 2>&1 || fail "the MPI sweep failed"
grep -q "sweep: 4 jobs ran on $ranks ranks" "$work/log" || fail "no summary from rank 0"
# The summary every runner prints (a local sweep's: tests/cli/sweep_failing_job.sh), once, from rank 0.
[ "$(grep -c "^sweep: 4 jobs: 4 complete, 0 failed, 0 not run; table" "$work/log")" -eq 1 ] ||
  fail "the MPI sweep's summary is not the local one's, or not printed once"
for i in 0 1 2 3; do
  id=00$i
  [ "$(state "$work/mpi" $id)" = complete ] || fail "job $id is not complete"
  [ "$(field "$work/mpi" $id runner)" = "mpi rank $((i % ranks)) of $ranks" ] || fail "job $id ran on $(field "$work/mpi" $id runner)"
done
"$layerlab" sweep "$sweep" --out "$work/local" -j 2 >"$work/log.local" 2>&1 || fail "the local sweep failed"
# The results (PSNR, iterations), not the times or the runner.
cut -d, -f1-4,7,9 "$work/mpi/table.csv" >"$work/mpi.cut"
cut -d, -f1-4,7,9 "$work/local/table.csv" >"$work/local.cut"
cmp -s "$work/mpi.cut" "$work/local.cut" || fail "MPI and local results differ: $(diff "$work/mpi.cut" "$work/local.cut")"
# Again: every job complete, nothing runs.
"$mpiexec" --oversubscribe --allow-run-as-root -np "$ranks" "$layerlab" sweep "$sweep" --out "$work/mpi" --mpi \
  >"$work/log" 2>&1 || fail "the resumed MPI sweep failed"
grep -q "sweep: 0 jobs ran on $ranks ranks, 4 skipped as complete" "$work/log" || fail "the resumed MPI sweep ran jobs again"
# A failing job: the other ranks go on, every rank exits non-zero.
write_sweep "$sweep" '["solve"]' '[{ "name": "solver", "pointer": "/solve/solver", "values": ["hybrid", "no-such-solver"] }]'
if "$mpiexec" --oversubscribe --allow-run-as-root -np "$ranks" "$layerlab" sweep "$sweep" --out "$work/fail" --mpi \
  >"$work/log" 2>&1; then fail "an MPI sweep with a failed job exited 0"; fi
grep -q "rank 1: sweep: job 001 (solver no-such-solver) failed" "$work/log" || fail "rank 1 did not report its failed job"
[ "$(state "$work/fail" 000)" = complete ] || fail "the other job did not complete"
grep -q "^001,no-such-solver,failed," "$work/fail/table.csv" || fail "the table does not list the failed job"
echo "PASS"
