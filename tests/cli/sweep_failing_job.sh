#!/bin/sh
# layerlab sweep: a job that fails (here an unknown solver) is reported with
# its error, in the log, its job.json and the table; the other jobs run; the
# sweep exits non-zero. Run again, the finished job is skipped and the failed
# one is tried again.
. "$(dirname "$0")/sweep_common.sh"
sweep=$work/sweep.json out=$work/out
write_sweep "$sweep" '["solve"]' '[{ "name": "solver", "pointer": "/solve/solver", "values": ["no-such-solver", "hybrid"] }]'
if "$layerlab" sweep "$sweep" --out "$out" -j 2 >"$work/log" 2>&1; then fail "a sweep with a failed job exited 0"; fi
grep -q "sweep: job 000 (solver no-such-solver) failed: .*no-such-solver" "$work/log" || fail "the failure is not reported"
grep -q "sweep: job 001 (solver hybrid) complete" "$work/log" || fail "the other job did not run"
grep -q "sweep: 2 jobs: 1 complete, 1 failed, 0 not run" "$work/log" || fail "no summary"
[ "$(state "$out" 000)" = failed ] && [ "$(state "$out" 001)" = complete ] || fail "the job records"
field "$out" 000 error | grep -q "no-such-solver" || fail "the failed job's record has no error"
grep -q "^000,no-such-solver,failed," "$out/table.csv" || fail "the table does not list the failed job"
grep -q "job 000 failed: <code>.*no-such-solver" "$out/table.html" || fail "the HTML table does not show the error"
if "$layerlab" sweep "$sweep" --out "$out" >"$work/log" 2>&1; then fail "the second run exited 0"; fi
grep -q "sweep: 1 of 2 jobs already complete, skipped" "$work/log" || fail "the finished job was not skipped"
grep -q "sweep: job 000 (solver no-such-solver) failed" "$work/log" || fail "the failed job was not tried again"
echo "PASS"
