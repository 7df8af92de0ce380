#!/bin/sh
# layerlab sweep: a run killed (kill -9, the pool and its job processes) in
# the middle leaves every finished job whole; the same command again skips
# them, untouched, and runs only the rest.
. "$(dirname "$0")/sweep_common.sh"
sweep=$work/sweep.json out=$work/out
# wait_for_first_job DIR: until job 000 of the sweep started as $pid is complete.
wait_for_first_job() {
  i=0
  until [ "$(state "$1" 000)" = complete ]; do
    i=$((i + 1)); [ $i -lt 3000 ] || { kill -KILL -$pid; fail "job 000 did not finish in 60 s"; }
    sleep 0.02
  done
}
# Six jobs of 60 iterations (about half a second each), one at a time: the kill comes after the first.
write_sweep "$sweep" '["solve"]' '[{ "name": "pupil", "pointer": "/elements/0/pupil_diameter", "values": ["3 mm", "4 mm", "5 mm"] }, '"$COMBINERS]" 60
setsid "$layerlab" sweep "$sweep" --out "$out" --local -j 1 >"$work/log" 2>&1 &
pid=$!
wait_for_first_job "$out"
kill -KILL -$pid 2>/dev/null; wait $pid 2>/dev/null
# The job process is gone only once reaped: until then it counts as alive and its staging folder as in use.
i=0
while ps -o pid= -s $pid >/dev/null 2>&1; do
  i=$((i + 1)); [ $i -lt 500 ] || fail "the killed job processes are still there after 10 s"
  sleep 0.02
done
done_before=0
for id in 000 001 002 003 004 005; do
  if [ "$(state "$out" $id)" = complete ]; then
    done_before=$((done_before + 1))
    [ -f "$out/jobs/$id/out/index.html" ] && [ -f "$out/jobs/$id/out/solve/report.json" ] || fail "job $id is complete but not whole"
  fi
done
[ $done_before -lt 6 ] || fail "every job finished before the kill; the test needs slower jobs"
[ ! -e "$out/table.csv" ] || fail "a killed sweep wrote its table"
stamp=$(ls -l --time-style=+%s.%N "$out/jobs/000/job.json" "$out/jobs/000/out/solve/report.json" | awk '{print $6, $7}')
"$layerlab" sweep "$sweep" --out "$out" --local -j 2 >"$work/log" 2>&1 || fail "the resumed sweep failed"
grep -q "sweep: $done_before of 6 jobs already complete, skipped" "$work/log" || fail "did not skip the $done_before finished jobs"
[ "$(grep -c 'complete in' "$work/log")" -eq $((6 - done_before)) ] || fail "ran other than the unfinished jobs"
[ "$(ls -l --time-style=+%s.%N "$out/jobs/000/job.json" "$out/jobs/000/out/solve/report.json" | awk '{print $6, $7}')" = "$stamp" ] ||
  fail "the resumed sweep touched a finished job"
for id in 000 001 002 003 004 005; do [ "$(state "$out" $id)" = complete ] || fail "job $id not complete"; done
ls -a "$out/jobs"/*/out | grep -q layerlab-staging && fail "a killed job's staging folder is left"
[ "$(wc -l <"$out/table.csv")" -eq 7 ] || fail "the table does not have 6 rows"
grep -q "^job,pupil (mm),combiner,state,runner,job time (s),PSNR (dB),solve time (s),iterations$" "$out/table.csv" ||
  fail "the table's header: $(head -1 "$out/table.csv")"
[ -f "$out/plots/psnr_db.svg" ] && [ -f "$out/table.html" ] || fail "no plot or HTML table"
# Ctrl-C (SIGINT to the process group, as a terminal sends it): exit 130, the running job is
# interrupted, not failed, and nothing of it is recorded; the finished ones stay complete.
out2=$work/out2
setsid "$layerlab" sweep "$sweep" --out "$out2" --local -j 1 >"$work/log" 2>&1 &
pid=$!
wait_for_first_job "$out2"
kill -INT -$pid
wait $pid
status=$?
[ $status -eq 130 ] || fail "an interrupted sweep exited $status, not 130"
grep -q "sweep: interrupted; the finished jobs are kept" "$work/log" || fail "no word of the interruption"
grep -q "failed" "$work/log" && fail "an interrupted job was reported as failed: $(grep failed "$work/log")"
for id in 001 002 003 004 005; do
  s=$(state "$out2" $id)
  [ "$s" = none ] || [ "$s" = complete ] || fail "job $id after Ctrl-C: $s"
done
echo "PASS"
