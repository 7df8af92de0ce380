#!/usr/bin/env bash
# Issue 26: the whole loop on the command line (docs/calibration.md):
# calibration-patterns, photograph (synthetic photographs of the paper
# prototype as built: rear_a offset by (0.3, -0.2) mm and turned by 0.25 deg),
# detect and fit; the fitted offset is the built one. Then one photograph
# removed: detect names it, goes on with the rest and still writes the file.
# Usage: photo_calibration_loop.sh LAYERLAB EXAMPLES_DIR WORK_DIR
source "$(dirname "$0")/common.sh"
rm -rf "$work" && mkdir -p "$work"
echo '{ "fx": 760, "fy": 760, "cx": 359.5, "cy": 209.5, "k1": -0.05 }' >"$work/camera.json"
"$layerlab" calibration-patterns "$examples/paper_prototype.json" --out "$work/plan" --levels 0 64 128 192 255 \
  --camera "$work/camera.json" >"$work/log" 2>&1 || { cat "$work/log"; fail "calibration-patterns failed"; }
[ -f "$work/plan/captures.json" ] && [ -f "$work/plan/patterns/rear_a_chessboard.png" ] || fail "no plan or patterns"
# The display as built: the scene with rear_a moved (and without the solve and run sections, whose paths are relative).
python3 - "$examples/paper_prototype.json" "$work/built.json" <<'PY' || fail "could not write the built scene"
import json, sys
scene = json.load(open(sys.argv[1]))
for key in ("solve", "run"):
    scene.pop(key, None)
for e in scene["elements"]:
    if e["name"] == "rear_a":
        e["offset"] = ["0.3 mm", "-0.2 mm"]
        e["rotation"] = "0.25 deg"
json.dump(scene, open(sys.argv[2], "w"), indent=2)
PY
# photograph, detect and fit with --json (issue 50): each prints one object (json_result.py).
check="/usr/bin/python3 $(dirname "$0")/json_result.py"
"$layerlab" photograph "$work/plan" --scene "$work/built.json" --out "$work/photos" --size 720 420 --json \
  >"$work/photograph.json" 2>"$work/log" || { cat "$work/log"; fail "photograph failed"; }
$check "$work/photograph.json" photograph photographs=32 || fail "photograph --json"
"$layerlab" detect "$work/photos" --scene "$examples/paper_prototype.json" --out "$work/measurements.json" --json \
  >"$work/detect.json" 2>"$work/log" || { cat "$work/log"; fail "detect failed"; }
$check "$work/detect.json" detect corners=540 luminance_steps=20 photographs=32 failed=[] || fail "not every photograph used"
"$layerlab" fit "$examples/paper_prototype.json" "$work/measurements.json" --out "$work/calibrated.json" --json \
  >"$work/fit.json" 2>"$work/fit.log" || { cat "$work/fit.log"; fail "fit failed"; }
$check "$work/fit.json" fit "out=$work/calibrated.json" calibration || fail "fit --json"
python3 - "$work/calibrated.json" <<'PY' || fail "the calibrated scene does not hold the built placement"
import json, sys
rear_a = [e for e in json.load(open(sys.argv[1]))["elements"] if e["name"] == "rear_a"][0]
x, y = (float(v.split()[0]) * (1e3 if v.endswith(" m") else 1) for v in rear_a["offset"])
print("rear_a offset fitted: %.4f, %.4f mm (built 0.3, -0.2)" % (x, y))
sys.exit(0 if abs(x - 0.3) < 0.01 and abs(y + 0.2) < 0.01 else 1)
PY
rm "$work/photos/front_b_chessboard_1.exr"
"$layerlab" detect "$work/photos" --scene "$examples/paper_prototype.json" --out "$work/measurements2.json" \
  >"$work/log" 2>&1 || { cat "$work/log"; fail "detect stopped at a missing photograph"; }
grep -q "warning: front_b_chessboard_1.exr: .*front_b_chessboard_1.exr" "$work/log" || { cat "$work/log"; fail "the missing photograph is not named"; }
grep -q "in 31 of 32 photographs (1 failed, named above)" "$work/log" || { cat "$work/log"; fail "no summary"; }
# The camera's aperture and focus with units, as every command takes them: the same photograph as bare mm and D.
python3 - "$work/plan/captures.json" "$work/one/captures.json" <<'PY' || fail "could not write a one-capture plan"
import json, os, sys
plan = json.load(open(sys.argv[1]))
plan["captures"] = plan["captures"][:1]
os.makedirs(os.path.dirname(sys.argv[2]), exist_ok=True)
json.dump(plan, open(sys.argv[2], "w"), indent=2)
PY
photo=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["captures"][0]["photo"])' "$work/one/captures.json")
"$layerlab" photograph "$work/one" --scene "$work/built.json" --out "$work/bare" --size 72 42 --aperture 2 --focus 2 \
  >"$work/log" 2>&1 || { cat "$work/log"; fail "photograph with bare numbers failed"; }
"$layerlab" photograph "$work/one" --scene "$work/built.json" --out "$work/units" --size 72 42 --aperture "2 mm" \
  --focus "0.5 m" >"$work/log" 2>&1 || { cat "$work/log"; fail "photograph with units failed"; }
cmp -s "$work/bare/$photo" "$work/units/$photo" || fail "2 mm at 0.5 m is not the photograph of 2 at 2"
if "$layerlab" photograph "$work/one" --scene "$work/built.json" --out "$work/bad" --aperture "2 D" >"$work/log" 2>&1; then
  fail "an aperture in diopters was taken"
fi
grep -q -- '--aperture: "2 D" is not a number or a length' "$work/log" || { cat "$work/log"; fail "the refusal does not say why"; }
echo PASS
