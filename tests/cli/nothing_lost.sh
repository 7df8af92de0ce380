#!/usr/bin/env bash
# Issue 17, "Nothing lost, ever", end to end on the reduced example (a
# rendered 5 x 5-view target, about 2 s a run):
#   1. a second `run` into the same folder that fails at a file-size limit
#      (ulimit -f, at several points of the run) leaves the folder byte for byte;
#   2. a `run` whose target is a symbolic link into its own solve/ folder, and
#      a `solve` whose --out contains its --target, are refused before any work,
#      and the target stays whole;
#   3. the stale-file sweep removes what an earlier run recorded and no longer
#      writes, never a file of the user's;
#   4. `kill -9` during `solve --write-lightfield` leaves the earlier result or
#      the new one, never a mix (a kill inside the switch-over is finished by
#      the next reader), and the next run clears what the killed one left;
#   5. `--resume` refuses a checkpoint made for another target of the same geometry;
#   6. a second process writing into a folder in use is refused, naming the first.
# Usage: nothing_lost.sh LAYERLAB EXAMPLES_DIR WORK_DIR
set -u
layerlab=$1 examples=$2 work=$3
fail() { echo "FAIL: $*"; [ -f "$work/log" ] && tail -n 5 "$work/log"; exit 1; }
rm -rf "$work"
mkdir -p "$work"
cp -r "$examples/small" "$examples/targets" "$work/"
scene=$work/small/hybrid_small.json
sed -i 's#"run": {#"run": { "write_lightfield": true,#' "$scene"
# Everything in a folder, hidden files included: path, type, and a file's hash or a link's target.
snapshot() { (cd "$1" && find . -printf '%p %y %l\n' | sort && find . -type f -print0 | sort -z | xargs -0 -r sha256sum); }
clean_error() {  # $1: exit code; the log must end in one clear error, never an internal error or a signal
  [ "$1" -ne 0 ] || fail "exit code 0"
  [ "$1" -lt 128 ] || fail "killed by a signal ($1)"
  grep -q "internal error" "$work/log" && fail "an internal error"
  grep -q "layerlab: error:" "$work/log" || fail "no error message"
}

# 1. Failed runs leave the earlier results whole.
"$layerlab" run "$scene" --out "$work/a" >"$work/log" 2>&1 || fail "the first run failed"
echo mine >"$work/a/notes.txt"
before=$(snapshot "$work/a")
for limit in 4 16 40 80; do
  (ulimit -f "$limit"; exec "$layerlab" run "$scene" --iterations 3 --out "$work/a") >"$work/log" 2>&1
  code=$?
  clean_error "$code"
  [ "$(snapshot "$work/a")" = "$before" ] || fail "a run failing at ulimit -f $limit changed the earlier results: $(diff <(echo "$before") <(snapshot "$work/a") | head -5)"
  grep -q "staging" "$work/log" && fail "the message names the staging folder, not the output"
  grep -q "the earlier results in $work/a are unchanged" "$work/log" || fail "the message does not say the earlier results are unchanged"
  echo "ulimit -f $limit: $(grep 'layerlab: error' "$work/log" | cut -c1-150)...; folder unchanged"
done

# 2. Outputs never overwrite inputs, by real path.
lf=$work/a/solve/lightfield
sed 's#"target_scene": "small_dice_target.json"#"target": "../linked_target"#' "$scene" >"$work/small/linked.json"
ln -s "$lf" "$work/linked_target"
"$layerlab" run "$work/small/linked.json" --out "$work/a" >"$work/log" 2>&1
clean_error $?
grep -q "the output contains the target .*linked_target (real paths" "$work/log" || fail "the run into its own target was not refused as such"
"$layerlab" solve "$scene" --target "$lf" --out "$work/a/solve" --write-lightfield --iterations 1 >"$work/log" 2>&1
clean_error $?
grep -q "the output is the target $lf" "$work/log" || fail "solve onto its own target was not refused as such"
"$layerlab" solve "$scene" --target "$work/a/solve/../solve/lightfield" --out "$work/a/solve/lightfield/views" --iterations 1 >"$work/log" 2>&1
clean_error $?
grep -q "lies inside the target" "$work/log" || fail "solve into its own target's views was not refused as such"
[ "$(snapshot "$work/a")" = "$before" ] || fail "a refused command changed the folder"
echo "outputs overlapping inputs: refused, folder unchanged"

# 3. The sweep: what the earlier run recorded and this one does not write goes; the user's files stay.
echo mine >"$work/a/solve/my_notes.txt"
sed 's#"write_lightfield": true,##' "$scene" >"$work/small/no_lightfield.json"
"$layerlab" run "$work/small/no_lightfield.json" --out "$work/a" >"$work/log" 2>&1 || fail "the run without a light field failed"
[ ! -e "$lf" ] || fail "the light field the earlier run wrote and this one did not is still there"
[ -s "$work/a/solve/my_notes.txt" ] && [ -s "$work/a/notes.txt" ] || fail "a file of the user's was removed"
grep -q "run: removed 26 files an earlier run wrote" "$work/log" || fail "the sweep did not say what it removed: $(grep removed "$work/log")"
echo "sweep: $(grep 'run: removed' "$work/log")"

# 4. kill -9 while the synthesized light field is written.
target=$work/a/target/lightfield
"$layerlab" solve "$scene" --target "$target" --iterations 4 --write-lightfield --out "$work/new" >"$work/log" 2>&1 || fail "the reference solve failed"
results() { (cd "$1" && find lightfield patterns panels -type f -print0 2>/dev/null | sort -z | xargs -0 -r sha256sum); }
new=$(results "$work/new")
kills=0 switched=0
# Killed at fixed delays, and (the "poll" runs) as soon as the new views are being written.
for delay in 0.01 0.02 0.03 0.05 0.08 0.1 0.15 0.2 poll poll poll poll poll; do
  rm -rf "$work/k"
  "$layerlab" solve "$scene" --target "$target" --iterations 1 --write-lightfield --out "$work/k" >"$work/log" 2>&1 || fail "the first solve failed"
  old=$(results "$work/k")
  "$layerlab" solve "$scene" --target "$target" --iterations 4 --write-lightfield --out "$work/k" >"$work/log" 2>&1 &
  pid=$!
  if [ "$delay" = poll ]; then
    views=$work/k/.layerlab-staging-solve-$pid/lightfield/views
    for _ in $(seq 1 20000); do [ -d "$views" ] && break; kill -0 "$pid" 2>/dev/null || break; done
  else
    sleep "$delay"
  fi
  kill -9 "$pid" 2>/dev/null && kills=$((kills + 1))
  wait "$pid" 2>/dev/null
  if ls -a "$work/k" | grep -q '^\.layerlab-solve-switch.json$'; then
    # Killed inside the switch-over: the first reader of anything in the folder finishes it.
    switched=$((switched + 1))
    "$layerlab" info "$scene" --target "$work/k/lightfield" >"$work/log" 2>&1 || fail "reading the half-switched light field failed: $(cat "$work/log")"
    grep -q "a layerlab solve was killed while switching its results into place; the switch-over is now finished" "$work/log" ||
      fail "the reader did not finish the switch-over: $(cat "$work/log")"
    [ "$(results "$work/k")" = "$new" ] || fail "after the reader finished the switch-over the folder is not the new result"
  else  # no switch-over under way: old or new, whole
    now=$(results "$work/k")
    [ "$now" = "$old" ] || [ "$now" = "$new" ] || fail "after kill -9 at $delay the folder is neither the old result nor the new one"
  fi
  "$layerlab" solve "$scene" --target "$target" --iterations 4 --write-lightfield --out "$work/k" >"$work/log" 2>&1 || fail "the solve after the kill failed"
  [ "$(results "$work/k")" = "$new" ] || fail "the solve after the kill did not leave the new result"
  left=$(find "$work/k" -name '.layerlab-staging-*' -o -name '.*.tmp-*' -o -name '.layerlab-*-switch.json')
  [ -z "$left" ] || fail "left behind after the next solve: $left"
done
[ "$kills" -ge 3 ] || fail "only $kills of 13 solves were killed before they ended: the test did not test"
echo "kill -9: $kills of 13 solves killed (0.01 to 0.2 s, or while writing views), $switched inside the switch-over (finished by the next reader); each folder was the old or the new result, and the next solve cleared the rest"

# 6. One writer at a time: a second process into a folder in use is refused, naming the first and its host.
"$layerlab" solve "$scene" --target "$target" --iterations 100000 --out "$work/w" >"$work/log1" 2>&1 &
pid=$!
for _ in $(seq 1 20000); do ls -a "$work/w" 2>/dev/null | grep -q '^\.layerlab-lock$' && break; kill -0 "$pid" 2>/dev/null || break; done
"$layerlab" retina "$scene" --patterns "$work/new" --out "$work/w" >"$work/log" 2>&1 && fail "a second writer into a folder in use was accepted"
kill -9 "$pid" 2>/dev/null
wait "$pid" 2>/dev/null
grep -q "$work/w: another layerlab process $pid on host $(hostname) is writing into this folder" "$work/log" ||
  fail "the second writer was not refused naming the first: $(cat "$work/log")"
"$layerlab" solve "$scene" --target "$target" --iterations 1 --out "$work/w" >"$work/log" 2>&1 || fail "the folder stayed locked after its writer was killed"
echo "one writer at a time: the second refused naming process $pid on $(hostname); free again once it was killed"

# 5. A checkpoint is for its own inputs.
"$layerlab" solve "$scene" --solver joint --target "$lf" --iterations 1 --checkpoint-every 1 --out "$work/c" >"$work/log" 2>&1 &&
  fail "solve from a removed light field succeeded"
"$layerlab" solve "$scene" --solver joint --target "$work/new/lightfield" --iterations 1 --checkpoint-every 1 --out "$work/c" >"$work/log" 2>&1 ||
  fail "the checkpointed solve failed"
"$layerlab" solve "$scene" --solver joint --target "$target" --iterations 2 --resume --out "$work/c" >"$work/log" 2>&1
clean_error $?
grep -q "checkpoint.json: /digest/target: the checkpoint was made for another target" "$work/log" || fail "resume with another target was not refused"
"$layerlab" solve "$scene" --solver joint --target "$work/new/lightfield" --iterations 2 --resume --initial-value 0.3 --out "$work/c" >"$work/log" 2>&1
clean_error $?
grep -q "/digest/options: the checkpoint was made for another solver options" "$work/log" || fail "resume with other options was not refused"
"$layerlab" solve "$scene" --solver joint --target "$work/new/lightfield" --iterations 2 --resume --out "$work/c" >"$work/log" 2>&1 ||
  fail "resume with the same inputs failed"
echo "resume: another target and other options refused, the same inputs resumed"
echo PASS
