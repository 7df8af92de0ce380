#!/usr/bin/env bash
# Issue 18: `run` keeps the render of its target scene in OUT/target and reuses
# it while the scene, the files it reads and the geometry are unchanged; it
# renders again when any of them changed, when the kept render was altered,
# and never reuses what a killed run left. On the reduced example (a 5 x 5-view
# target, its solve only: a fraction of a second a run).
# Usage: target_cache.sh LAYERLAB EXAMPLES_DIR WORK_DIR
source "$(dirname "$0")/common.sh"
rm -rf "$work"
mkdir -p "$work"
cp -r "$examples/small" "$examples/targets" "$work/"
# The render and a 2-iteration solve, a fraction of a second a run.
scene=$work/small/solve_only.json
solve_only "$work/small/hybrid_small.json" "$scene"
out=$work/out
run() { "$layerlab" run "$scene" --iterations 2 --out "$out" >"$work/log" 2>&1 || fail "the run failed"; }
expect() {  # $1: what the log must say
  grep -q -- "$1" "$work/log" || fail "the log does not say \"$1\""
}

run
expect "target: rendering .*small_dice_target.json: no earlier render in $out/target"
grep -q '"digest"' "$out/target/render.json" || fail "no render record"
key=$(sed -n 's/.*"digest": "\([0-9a-f]*\)".*/\1/p' "$out/target/render.json")
grep -q "rendered from .*small_dice_target.json (key $key): 5 x 5 views of 80 x 40 pixels" "$out/index.html" ||
  fail "the report does not say what the target is"
echo "first run: rendered, key $key"

run
expect "target: reusing the render of .*small_dice_target.json in $out/target (key $key"
grep -q "(key $key, the render of an earlier run reused)" "$out/index.html" || fail "the report does not say it reused the render"
[ -f "$out/target/lightfield/views/r00_c00.exr" ] || fail "the reused render is not in the output folder"
echo "unchanged: reused"

# --quiet keeps the results (stdout) and silences the notes about the render.
"$layerlab" run "$scene" --iterations 2 --out "$out" --quiet >/dev/null 2>"$work/log" || fail "the quiet run failed"
[ ! -s "$work/log" ] || fail "--quiet still printed on stderr: $(head -3 "$work/log")"
echo "quiet: no notes"

# A mesh the target scene reads changes (a comment line: the geometry is the same, the bytes are not).
echo "# changed" >>"$work/targets/die.obj"
run
expect "target: rendering .*: the target scene, a file it reads or its geometry changed since the render in $out/target (key $key, now "
new=$(sed -n 's/.*"digest": "\([0-9a-f]*\)".*/\1/p' "$out/target/render.json")
[ "$new" != "$key" ] || fail "the key did not change with the mesh"
echo "mesh changed: rendered again, key $new"

run
expect "reusing the render"
sed -i 's#"samples_per_pixel": [0-9]*#"samples_per_pixel": 2#' "$work/small/small_dice_target.json"
grep -q '"samples_per_pixel": 2' "$work/small/small_dice_target.json" || fail "the test could not edit the target scene"
run
expect "target: rendering .*: the target scene, a file it reads or its geometry changed"
echo "target scene changed: rendered again"

# A kept view altered after it was written (another view's bytes): rendered again, not reused.
cp "$out/target/lightfield/views/r00_c01.exr" "$out/target/lightfield/views/r00_c00.exr"
run
expect "target: rendering .*: the render in $out/target was changed after it was written"
echo "kept render altered: rendered again"

# A run killed before its switch-over (here: during a long solve, its render complete in its staging
# folder) leaves nothing that is reused.
rm -rf "$out"
"$layerlab" run "$scene" --iterations 100000 --out "$out" >"$work/log" 2>&1 &
pid=$!
staged() { compgen -G "$out/.layerlab-staging-run-*/target/render.json" >/dev/null; }
for _ in $(seq 1 200); do staged && break; sleep 0.1; done
staged || { kill -9 $pid; fail "the run to be killed never kept its render in its staging folder"; }
sleep 0.3  # into the solve
kill -9 $pid
wait $pid 2>/dev/null
[ -e "$out/target/render.json" ] && fail "a killed run left a render record in place"
run
expect "target: rendering .*: no earlier render in $out/target"
expect "removed .*left by a layerlab process that no longer works there"
echo "killed run: its render was not reused"
echo "PASS"
