#!/bin/sh
# layerlab sweep --slurm: the job-array script run as Slurm would, with
# SLURM_ARRAY_TASK_ID set (no cluster here): the task id selects the job;
# the gather script makes the table, non-zero while a job has not run.
. "$(dirname "$0")/sweep_common.sh"
sweep=$work/sweep.json out=$work/out
write_sweep "$sweep" '["solve"]' "[$PUPILS]"
"$layerlab" sweep "$sweep" --out "$out" --slurm >"$work/log" 2>&1 || fail "--slurm failed"
array=$out/slurm/array.sbatch gather=$out/slurm/gather.sbatch
[ -x "$array" ] && [ -x "$gather" ] && [ -x "$out/slurm/submit.sh" ] || fail "the scripts are missing or not executable"
grep -q "^#SBATCH --array=0-1$" "$array" || fail "the array does not cover jobs 0 to 1"
grep -q "sbatch --dependency=afterany:" "$out/slurm/submit.sh" || fail "the gather step does not wait for the array"
if "$array" >"$work/log" 2>&1; then fail "the task script ran without SLURM_ARRAY_TASK_ID"; fi
grep -q "SLURM_ARRAY_TASK_ID" "$work/log" || fail "the task script does not say what it needs"
SLURM_ARRAY_TASK_ID=1 "$array" >"$work/log" 2>&1 || fail "task 1 failed"
[ "$(state "$out" 001)" = complete ] && [ "$(state "$out" 000)" = none ] || fail "task 1 did not run job 001 alone"
[ "$(field "$out" 001 runner)" = "slurm task 1" ] || fail "job 001's runner: $(field "$out" 001 runner)"
if "$gather" >"$work/log" 2>&1; then fail "the gather step exited 0 with a job not run"; fi
grep -q "2 jobs: 1 complete, 0 failed, 1 not run" "$work/log" || fail "the gather step's summary"
grep -q "^000,3,not run," "$out/table.csv" || fail "the table does not list the job not run"
SLURM_ARRAY_TASK_ID=0 "$array" >"$work/log" 2>&1 || fail "task 0 failed"
SLURM_ARRAY_TASK_ID=1 "$array" >"$work/log" 2>&1 || fail "task 1 again failed"
grep -q "already complete" "$work/log" || fail "task 1 run again did not skip its finished job"
"$gather" >"$work/log" 2>&1 || fail "the gather step failed with every job complete"
[ "$(grep -c ',complete,slurm task' "$out/table.csv")" -eq 2 ] || fail "the table: $(cat "$out/table.csv")"
SLURM_ARRAY_TASK_ID=2 "$array" >"$work/log" 2>&1 && fail "task 2 of a 2-job array ran"
grep -q "the sweep has jobs 0 to 1" "$work/log" || fail "task 2's error"
echo "PASS"
