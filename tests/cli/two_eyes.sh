#!/usr/bin/env bash
# Issue 44: two eyes. On the reduced example made a near-eye pair (a display
# per eye, 63 mm apart, fixating 0.5 m ahead): each eye's display is solved
# for the target scene seen from that eye (the scene, given from the midpoint
# between the pupils, moved by ipd/2 for each), and `retina --eyes both`
# writes both eyes' retinal images, each the one-eye command's bit for bit.
# A shared direct-view display shows one set of patterns to both. Bad
# requests are refused naming the option.
# Usage: two_eyes.sh LAYERLAB EXAMPLES_DIR WORK_DIR EXR_DIFFERENCE
source "$(dirname "$0")/common.sh"
exr_difference=$4
rm -rf "$work"
mkdir -p "$work"
cp -r "$examples/small" "$examples/targets" "$work/"
target=$work/small/small_dice_target.json
pair() {  # $1 side, $2 display (own or shared), $3 file
  /usr/bin/python3 - "$work/small/hybrid_small.json" "$1" "$2" "$3" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene.pop("run", None)
scene.pop("solve", None)
for e in scene["elements"]:
    if e["type"] == "eye":
        e["binocular"] = {"side": sys.argv[2], "ipd": "63 mm", "display": sys.argv[3],
                          "fixation": ["0 mm", "0 mm", "0.5 m"]}
json.dump(scene, open(sys.argv[4], "w"), indent=1)
PY
}
pair left own "$work/small/left.json"
pair right own "$work/small/right.json"
pair left shared "$work/small/shared.json"
plain=$work/small/plain.json
solve_only "$work/small/hybrid_small.json" "$plain"

for side in left right; do
  "$layerlab" solve "$work/small/$side.json" --target-scene "$target" --iterations 2 --out "$work/solve_$side" \
    >"$work/log" 2>&1 || fail "the $side eye's solve failed"
done
[ -f "$work/solve_left/patterns/rear_a.exr" ] || fail "no patterns"
cmp -s "$work/solve_left/patterns/rear_a.exr" "$work/solve_right/patterns/rear_a.exr" &&
  fail "the two eyes' displays were solved for the same target"

retina() { "$layerlab" retina "$@" --accommodation 1.0 --resolution 0.5 >"$work/log" 2>&1; }
retina "$work/small/left.json" --patterns "$work/solve_left" --partner-patterns "$work/solve_right" --eyes both \
  --target-scene "$target" --out "$work/both" || fail "retina --eyes both failed"
for side in left right; do
  for what in display natural; do
    [ -f "$work/both/$side/$what/1.00D.exr" ] || fail "no $side/$what/1.00D.exr"
  done
done
grep -q 'id="left"' "$work/both/index.html" && grep -q 'id="right"' "$work/both/index.html" ||
  fail "the pair's page has no section per eye"
cmp -s "$work/both/left/natural/1.00D.exr" "$work/both/right/natural/1.00D.exr" &&
  fail "both eyes saw the same target"
# Each eye as the one-eye command sees it.
retina "$work/small/right.json" --patterns "$work/solve_right" --target-scene "$target" --out "$work/right_alone" ||
  fail "retina of the right eye failed"
for what in display natural; do
  cmp -s "$work/both/right/$what/1.00D.exr" "$work/right_alone/$what/1.00D.exr" ||
    fail "the right eye's $what image differs from the one-eye command's"
done
echo "near-eye pair: both eyes' images, each the one-eye command's"

# A shared display: one set of patterns, both eyes 31.5 mm off its axis.
"$layerlab" solve "$work/small/shared.json" --target-scene "$target" --iterations 2 --out "$work/solve_shared" \
  >"$work/log" 2>&1 || fail "the shared display's solve failed"
retina "$work/small/shared.json" --patterns "$work/solve_shared" --eyes both --target-scene "$target" \
  --out "$work/shared" || fail "retina --eyes both of a shared display failed"
cmp -s "$work/shared/left/display/1.00D.exr" "$work/shared/right/display/1.00D.exr" &&
  fail "the two eyes saw the shared display alike from 63 mm apart"
echo "shared display: both eyes"
# The left eye of the near-eye pair sees the scene moved ipd/2 right on its own display's axis: what the left
# eye of the shared display sees from ipd/2 left of that axis, turned alike (to float rounding of the positions).
difference=$("$exr_difference" "$work/both/left/natural/1.00D.exr" "$work/shared/left/natural/1.00D.exr") ||
  fail "cannot compare the natural images"
/usr/bin/python3 -c 'import sys; sys.exit(0 if float(sys.argv[1]) < 1e-4 else 1)' "$difference" ||
  fail "the own display's left eye does not see the scene from where the shared display's does ($difference)"
echo "the near-eye left eye's target is the shared display's left view: difference $difference"

# compare sees the target from the displays' eye, and refuses displays seen by different eyes; a light field
# given for an eye with a display of its own is taken as it is, with a warning.
"$layerlab" compare "$work/small/left.json" --target-scene "$target" --iterations 2 --out "$work/compare_left" \
  >"$work/log" 2>&1 || fail "compare of the left eye's display failed"
solved=$(sed -n 's/.*"final_psnr_db": \([0-9.]*\).*/\1/p' "$work/solve_left/report.json")
compared=$(sed -n 's/^left,hybrid,lightfield,\([0-9.]*\),.*/\1/p' "$work/compare_left/compare.csv")
/usr/bin/python3 -c 'import sys; sys.exit(0 if abs(float(sys.argv[1]) - float(sys.argv[2])) < 0.001 else 1)' \
  "$solved" "$compared" ||
  fail "compare solved the left eye's display for another target than solve did ($compared against $solved dB)"
if "$layerlab" compare "$work/small/left.json" "$work/small/right.json" --target-scene "$target" --iterations 1 \
  --out "$work/compare_both" >"$work/log" 2>&1; then fail "compare accepted displays seen by different eyes"; fi
grep -q "see the target scene from different places" "$work/log" || fail "compare does not say why: $(tail -n 1 "$work/log")"
"$layerlab" render-target "$target" --out "$work/lf" >"$work/log" 2>&1 || fail "render-target failed"
"$layerlab" solve "$work/small/left.json" --target "$work/lf" --iterations 1 --out "$work/solve_lf" >"$work/log" 2>&1 ||
  fail "the solve on a light field failed"
grep -q "is taken as it is, for an eye of a binocular pair with a display of its own" "$work/log" ||
  fail "no warning for a light field given to one eye of a pair"
echo "compare and light fields: per eye"

refused() {  # $1: what stderr must say; the rest: retina's arguments
  local says=$1
  shift
  if retina "$@" --out "$work/refused"; then fail "accepted: $*"; fi
  grep -q -- "$says" "$work/log" || fail "does not say \"$says\": $(tail -n 2 "$work/log")"
}
refused "--eyes both: the scene's eye is not one of a binocular pair" "$plain" --patterns "$work/solve_left" \
  --eyes both --target-scene "$target"
refused "--eyes both: each eye has a display of its own" "$work/small/left.json" --patterns "$work/solve_left" \
  --eyes both --target-scene "$target"
refused "--partner-patterns: the two eyes share one display" "$work/small/shared.json" \
  --patterns "$work/solve_shared" --partner-patterns "$work/solve_left" --eyes both --target-scene "$target"
refused "--eyes: \"three\" is not scene or both" "$work/small/left.json" --patterns "$work/solve_left" --eyes three
[ -e "$work/refused" ] && fail "a refused command wrote its folder"
echo "PASS"
