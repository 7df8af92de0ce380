#!/usr/bin/env bash
# Issue 49: `layerlab run` with "run": {"frames": ...} on the reduced example
# and its turning dice: OUT/frames/frames.{csv,txt,svg} and the page's Frames
# section; a still target scene and a missing count refused at /run/frames
# before anything runs, the output folder left as it was.
# Usage: run_frames.sh LAYERLAB EXAMPLES_DIR WORK_DIR
source "$(dirname "$0")/common.sh"
rm -rf "$work" && mkdir -p "$work"
# scene TARGET_SCENE FRAMES_JSON OUT_SCENE: the reduced example with only a frames step.
scene() {
  /usr/bin/python3 - "$examples/small/hybrid_small.json" "$1" "$2" "$3" <<'PY'
import json, os, sys
doc = json.load(open(sys.argv[1]))
doc["solve"]["target_scene"] = os.path.abspath(sys.argv[2])
doc["solve"]["iterations"] = 2
doc["run"] = {"frames": json.loads(sys.argv[3])}
json.dump(doc, open(sys.argv[4], "w"))
PY
}
scene "$examples/small/small_dice_turning.json" '{"count": 3, "frame_iterations": 1, "cold_every": 2}' "$work/moving.json"
"$layerlab" run "$work/moving.json" --out "$work/out" >"$work/log" 2>&1 || fail "run with frames failed: $(tail -5 "$work/log")"
for f in frames/frames.csv frames/frames.txt frames/frames.svg index.html solve/report.json; do
  [ -s "$work/out/$f" ] || fail "no $f"
done
[ "$(wc -l <"$work/out/frames/frames.csv")" -eq 4 ] || fail "frames.csv: not a header and 3 frames"
awk -F, 'NR == 3 && $5 != 1 { exit 1 } NR == 4 && $7 == "nan" { exit 1 }' "$work/out/frames/frames.csv" ||
  fail "frames.csv: frame 1 did not run 1 iteration, or frame 2 has no cold reference"
grep -q 'id="frames"' "$work/out/index.html" || fail "the page has no Frames section"
grep -q "frames/frames.svg" "$work/out/index.html" || fail "the page does not show frames.svg"
grep -q "<svg" "$work/out/frames/frames.svg" || fail "frames.svg is not an SVG"
mkdir -p "$work/kept" && echo keep >"$work/kept/mark"
refused() {  # $1: what the log must name; $2: the scene
  "$layerlab" run "$2" --out "$work/kept" >"$work/log" 2>&1 && fail "accepted: $2"
  grep -q -- "$1" "$work/log" || fail "$2: the error does not name $1: $(cat "$work/log")"
  [ "$(ls "$work/kept")" = mark ] || fail "$2: touched the output folder"
}
scene "$examples/small/small_dice_target.json" '{"count": 3}' "$work/still.json"
refused "/run/frames: .*does not move" "$work/still.json"
scene "$examples/small/small_dice_turning.json" '{"frame_iterations": 1}' "$work/no_count.json"
refused "/run/frames/count: is required" "$work/no_count.json"
echo "PASS"
