#!/bin/sh
# layerlab sweep: two sweeps into one folder at once are refused (the second
# names the first), and a job another process is running is left to it: the
# job is not run twice, nor marked failed. This shell, locking with flock(1),
# stands in for the other process (it writes no pid, so none is named).
. "$(dirname "$0")/sweep_common.sh"
command -v flock >/dev/null || { echo "PASS (skipped: no flock(1) on this machine)"; exit 0; }
sweep=$work/sweep.json out=$work/out
write_sweep "$sweep" '["solve"]' "[$PUPILS]"
mkdir -p "$out/jobs/000"
exec 9>"$out/sweep.lock"
flock -n 9 || fail "cannot take the sweep lock"
if "$layerlab" sweep "$sweep" --out "$out" >"$work/log" 2>&1; then fail "a second sweep into a locked folder ran"; fi
grep -q "$out: another layerlab sweep is running into this folder; wait for it to end or give another --out" \
  "$work/log" || fail "the refusal does not say why: $(cat "$work/log")"
[ ! -e "$out/manifest.json" ] || fail "the refused sweep wrote its manifest"
exec 9>&-
exec 9>"$out/jobs/000/job.lock"
flock -n 9 || fail "cannot take the job lock"
"$layerlab" sweep "$sweep" --out "$out" --job 0 >"$work/log" 2>&1
status=$?
[ $status -eq 75 ] || fail "a held job exited $status, not 75"
grep -q "sweep: job 000 (pupil 3 mm) not run: running in another process; left to it" "$work/log" ||
  fail "the held job's message: $(cat "$work/log")"
[ "$(state "$out" 000)" = none ] || fail "the held job got a record"
if "$layerlab" sweep "$sweep" --out "$out" >"$work/log" 2>&1; then fail "a sweep with a held job exited 0"; fi
grep -q "sweep: job 001 (pupil 5 mm) complete" "$work/log" || fail "the other job did not run: $(cat "$work/log")"
grep -q "sweep: 2 jobs: 1 complete, 0 failed, 1 not run" "$work/log" || fail "no summary: $(cat "$work/log")"
exec 9>&-
"$layerlab" sweep "$sweep" --out "$out" >"$work/log" 2>&1 || fail "the sweep after the release failed: $(cat "$work/log")"
grep -q "sweep: job 000 (pupil 3 mm) complete" "$work/log" || fail "the released job did not run"
echo "PASS"
