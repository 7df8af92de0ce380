#!/usr/bin/env bash
# Issue 43: the camera's intrinsics on the command line (docs/calibration.md,
# step 1): camera-patterns, photograph (synthetic photographs of the printed
# board through a known camera), camera-intrinsics; the estimate holds the
# truth within 3 of its standard deviations, and calibration-patterns (whose
# reader detect --camera shares) takes the file it writes. Then too few
# photographs: refused, nothing written.
# Usage: camera_intrinsics_loop.sh LAYERLAB EXAMPLES_DIR WORK_DIR
source "$(dirname "$0")/common.sh"
rm -rf "$work" && mkdir -p "$work"
"$layerlab" camera-patterns --out "$work/plan" --squares 10 7 --square-size "20 mm" --poses 10 >"$work/log" 2>&1 ||
  fail "camera-patterns failed"
grep -q "print it at 20 mm per square" "$work/log" || fail "camera-patterns does not say the printed size"
python3 - "$work/plan" <<'PY' || fail "the plan or the board's image is not what was asked"
import json, struct, sys
plan = json.load(open(sys.argv[1] + "/camera_captures.json"))
assert plan["format"] == "layerlab-camera-captures/1", plan["format"]
assert plan["board"]["squares"] == [10, 7] and plan["board"]["square_size"] == "20 mm", plan["board"]
assert len(plan["photos"]) == 10 and all(p["advice"] for p in plan["photos"])
png = open(sys.argv[1] + "/" + plan["board"]["image"], "rb").read()
width, height = struct.unpack(">II", png[16:24])
assert (width, height) == (1200, 900), (width, height)  # 12 x 9 squares of 100 pixels, the margin included
at = png.index(b"pHYs")
x, y, unit = struct.unpack(">IIB", png[at + 4:at + 13])
assert (x, y, unit) == (5000, 5000, 1), (x, y, unit)  # 100 pixels per 20 mm, in pixels per meter
PY
echo '{ "fx": 360, "fy": 365, "cx": 203.3, "cy": 146.8, "k1": -0.05, "k2": 0.02 }' >"$work/truth.json"
"$layerlab" photograph "$work/plan" --camera "$work/truth.json" --out "$work/photos" --size 400 300 --aperture 0 \
  >"$work/log" 2>&1 || fail "photograph of the board failed"
"$layerlab" camera-intrinsics "$work/photos" --out "$work/camera.json" >"$work/log" 2>&1 || fail "camera-intrinsics failed"
grep -q "used 10 of 10 photographs; wrote" "$work/log" || fail "not every photograph used"
# The same with --json (issue 50): one object on stdout, the estimate in it.
"$layerlab" --json camera-intrinsics "$work/photos" --out "$work/camera_again.json" >"$work/intrinsics.json" 2>"$work/log" ||
  fail "camera-intrinsics --json failed"
/usr/bin/python3 "$(dirname "$0")/json_result.py" "$work/intrinsics.json" camera-intrinsics photographs_used=10 \
  photographs=10 camera.fx || fail "camera-intrinsics --json"
python3 - "$work/camera.json" "$work/truth.json" <<'PY' || fail "the estimate does not hold the truth"
import json, sys
est, truth = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
for key, std in (("fx", "fx_std_px"), ("fy", "fy_std_px"), ("cx", "cx_std_px"), ("cy", "cy_std_px"),
                 ("k1", "k1_std"), ("k2", "k2_std")):
    print("%s %.4f +- %.4f (truth %g)" % (key, est[key], est[std], truth[key]))
    assert 0 < est[std] and abs(est[key] - truth[key]) <= 3 * est[std], key
assert 0 < est["rms_reprojection_px"] < 0.3, est["rms_reprojection_px"]
PY
"$layerlab" calibration-patterns "$examples/paper_prototype.json" --out "$work/display_plan" --camera "$work/camera.json" \
  >"$work/log" 2>&1 || fail "calibration-patterns does not take the estimated camera"
grep -q '"fx_std_px"' "$work/display_plan/captures.json" || fail "the plan dropped the camera's uncertainty"
# Too few photographs: two left, refused, naming the rest.
# board_03 a FIFO (named, never opened: it would block), board_04 a folder, the rest missing.
mkdir -p "$work/few" && cp "$work/photos/camera_captures.json" "$work/photos/board_01.exr" "$work/photos/board_02.exr" "$work/few/"
mkfifo "$work/few/board_03.exr" && mkdir "$work/few/board_04.exr"
if timeout 60 "$layerlab" camera-intrinsics "$work/few" --out "$work/few.json" >"$work/log" 2>&1; then fail "two photographs were taken"; fi
grep -q "need the board in at least 3 photographs; 2 of 10 show it" "$work/log" || fail "the refusal does not say why"
grep -q "  board_03.exr: .*a FIFO" "$work/log" || fail "the FIFO is not named as such"
grep -q "  board_04.exr: .*folder" "$work/log" || fail "the folder is not named as such"
grep -q "  board_05.exr: " "$work/log" || fail "the missing photographs are not named"
[ -e "$work/few.json" ] && fail "a refused estimate wrote its file"
if "$layerlab" photograph "$work/plan" --camera "$work/truth.json" --scene "$examples/paper_prototype.json" \
  --out "$work/o" >"$work/log" 2>&1; then fail "photograph took a scene for a camera plan"; fi
grep -q "holds a camera capture plan" "$work/log" || fail "the refusal does not say why"
echo PASS
