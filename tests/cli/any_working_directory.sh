#!/usr/bin/env bash
# Issue 18: relative paths of every kind work from any working directory.
# Every command (info, render-target, solve, retina, contrast, compare, fit,
# run) runs inside the examples folder with bare file names, and from a
# sibling folder with ../ paths; each must succeed without an internal error,
# and what it writes must name the files it read correctly (the calibrated
# scene's target follows it). Then the target options' errors are asserted by
# their text. On the reduced example (seconds a command).
# Usage: any_working_directory.sh LAYERLAB EXAMPLES_DIR WORK_DIR
source "$(dirname "$0")/common.sh"
rm -rf "$work"
mkdir -p "$work/elsewhere"
cp -r "$examples" "$work/examples"
ok() {  # runs "$@" in the current folder; it must succeed and print no internal error
  "$layerlab" "$@" >"$work/log" 2>&1 || fail "($(pwd)) layerlab $* exited with $?"
  grep -q "internal error" "$work/log" && fail "($(pwd)) layerlab $*: an internal error"
  echo "ok ($(basename "$(pwd)")): layerlab $*"
}
refused() {  # $1: the message the refusal must contain; runs the rest
  local message=$1
  shift
  "$layerlab" "$@" >"$work/log" 2>&1 && fail "layerlab $* succeeded"
  grep -q "internal error" "$work/log" && fail "layerlab $*: an internal error"
  grep -qF -- "$message" "$work/log" || fail "layerlab $*: the message does not say: $message"
  echo "refused as expected: layerlab $*"
}
quick_retina=(--accommodation 1.0 --resolution 0.5)
quick_contrast=(--depths 1.3 --frequencies 1 --accommodation 0.5:2.0:0.25 --no-peak-uncertainty)

# Bare file names, inside examples/small.
cd "$work/examples/small" || fail "no examples/small"
ok info hybrid_small.json
ok render-target small_dice_target.json --out lf
ok solve hybrid_small.json --target lf --iterations 2 --out s1
ok solve hybrid_small.json --target-scene small_dice_target.json --iterations 2 --out s2
ok solve hybrid_small.json --iterations 2 --out s3
ok retina hybrid_small.json --patterns s1 --target lf "${quick_retina[@]}" --out r1
ok retina hybrid_small.json --patterns s2 --target-scene small_dice_target.json "${quick_retina[@]}" --out r2
ok contrast hybrid_small.json "${quick_contrast[@]}" --out c1
ok compare hybrid_small.json hybrid_pbs_hwp_small.json --target lf --iterations 2 --out m1
ok compare hybrid_small.json --target-scene small_dice_target.json --iterations 2 --out m2
solve_only hybrid_small.json solve_only.json
ok run solve_only.json --iterations 2 --out run1
[ -f run1/target/render.json ] || fail "run1 kept no render of its target"

# Bare file names, inside examples: fit writes a scene whose paths still resolve.
cd "$work/examples" || fail "no examples"
ok fit paper_prototype.json paper_prototype_measurements.json --out calibrated.json --report report.json
grep -q '"target_scene": "targets/dice.json"' calibrated.json || fail "calibrated.json lost its target scene"
grep -q '"hybrid_pbs_hwp.json"' calibrated.json || fail "calibrated.json lost its compared scene"
ok info calibrated.json
mkdir -p fitted
ok fit paper_prototype.json paper_prototype_measurements.json --out fitted/calibrated.json
grep -q '"target_scene": "../targets/dice.json"' fitted/calibrated.json || fail "fitted/calibrated.json: the target scene did not follow"
grep -q '"../hybrid_pbs_hwp.json"' fitted/calibrated.json || fail "fitted/calibrated.json: the compared scene did not follow"

# ../ paths, from a sibling folder.
cd "$work/elsewhere" || fail "no elsewhere"
small=../examples/small
ok info "$small/hybrid_small.json"
ok render-target "$small/small_dice_target.json" --out lf
ok solve "$small/hybrid_small.json" --target lf --iterations 2 --out s1
ok solve "$small/hybrid_small.json" --target-scene "$small/small_dice_target.json" --iterations 2 --out s2
ok solve "$small/hybrid_small.json" --iterations 2 --out s3
ok retina "$small/hybrid_small.json" --patterns s1 --target ../elsewhere/lf "${quick_retina[@]}" --out r1
ok retina "$small/hybrid_small.json" --patterns ./s2 --target-scene "$small/small_dice_target.json" "${quick_retina[@]}" --out r2
ok contrast "$small/hybrid_small.json" "$small/hybrid_pbs_hwp_small.json" "${quick_contrast[@]}" --out c1
ok compare "$small/hybrid_small.json" --target lf --iterations 2 --out m1
ok compare "$small/hybrid_small.json" --target-scene "$small/small_dice_target.json" --iterations 2 --out m2
ok run "$small/solve_only.json" --iterations 2 --out run1
ok run "$small/solve_only.json" --iterations 2 --out run1
grep -q "reusing the render of $small/small_dice_target.json in run1/target" "$work/log" || fail "the second run did not reuse its render"
ok run "$small/hybrid_small.json" --iterations 2 --out full  # retina, contrast and compare with its compared scene
ok fit ../examples/paper_prototype.json ../examples/paper_prototype_measurements.json --out calibrated.json
grep -q '"target_scene": "../examples/targets/dice.json"' calibrated.json || fail "calibrated.json: the target scene did not follow"
ok info calibrated.json
ok fit ../examples/paper_prototype.json ../examples/paper_prototype_measurements.json --out ../examples/small/c.json
grep -q '"target_scene": "../targets/dice.json"' ../examples/small/c.json || fail "small/c.json: the target scene did not follow"

# The target options: a folder that is not a light field points to render-target.
render_hint="Render one from a target scene with \`layerlab render-target TARGET.json --out LF_DIR\`, or give the target scene itself (--target-scene TARGET.json"
refused "$small/small_dice_target.json: not a light-field folder (a file). $render_hint" \
  solve "$small/hybrid_small.json" --target "$small/small_dice_target.json" --out bad
mkdir -p empty
refused "empty: not a light-field folder (no lightfield.json). $render_hint" \
  compare "$small/hybrid_small.json" --target empty --out bad
refused "no_such_folder: not a light-field folder (no such directory). $render_hint" \
  retina "$small/hybrid_small.json" --patterns s1 --target no_such_folder --out bad
refused "give --target or --target-scene, not both" \
  solve "$small/hybrid_small.json" --target lf --target-scene "$small/small_dice_target.json" --out bad
refused "compare: give the target: --target LF_DIR or --target-scene TARGET.json" \
  compare "$small/hybrid_small.json" --out bad
[ -e bad ] && fail "a refused command wrote its output folder"
echo PASS
