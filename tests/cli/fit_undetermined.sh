#!/usr/bin/env bash
# Issue 18: `fit` writes no calibrated scene when the data leave a parameter
# undetermined (here: panel rear_a's markers shrunk by 5 % about the camera's
# principal point, smaller than the panel can look anywhere inside the focal
# length, so its distance ends at the bound, the focal length) and exits 1;
# --force writes it, with a warning. The focal length and eye relief are held (as
# the scene has them): fitted, they would take up the shrink instead.
# Usage: fit_undetermined.sh LAYERLAB EXAMPLES_DIR WORK_DIR
source "$(dirname "$0")/common.sh"
rm -rf "$work" && mkdir -p "$work"
# The example's markers are one per line; scale rear_a's camera pixels (cx 2000, cy 1500 in its "camera").
grep -q '"cx": 2000, "cy": 1500' "$examples/paper_prototype_measurements.json" || fail "the example's camera changed; update this test"
awk '
  /"rear_a": \[/ { inside = 1 }
  inside && /\]$|\],$/ && !/camera_pixel/ { inside = 0 }
  inside && /camera_pixel/ {
    match($0, /"camera_pixel": \[[-0-9.e]+, [-0-9.e]+\]/)
    split(substr($0, RSTART + 17, RLENGTH - 18), xy, ", ")
    $0 = substr($0, 1, RSTART - 1) sprintf("\"camera_pixel\": [%.6f, %.6f]", 2000 + (xy[1] - 2000) * 0.95, 1500 + (xy[2] - 1500) * 0.95) substr($0, RSTART + RLENGTH)
    changed++
  }
  { print }
  END { if (changed < 30) exit 1 }' "$examples/paper_prototype_measurements.json" >"$work/shrunk.json" || fail "could not shrink rear_a's markers"
"$layerlab" fit "$examples/paper_prototype.json" "$work/shrunk.json" --focal-length hold --lens-gaps hold --out "$work/calibrated.json" >"$work/log" 2>&1
code=$?
[ "$code" -eq 1 ] || fail "exit status $code, expected 1"
grep -q 'rear_a distance .* undetermined by the fit' "$work/log" || fail "the table does not mark the distance undetermined"
grep -qF 'layerlab: error: the data do not determine the distance of panel "rear_a": it ends at a bound of the model (75.0000 mm: the focal length, where its image is at infinity, 0 D) (undetermined: a parameter at a bound of the model, or with a standard deviation above 10 % of its value; docs/measurements-format.md). The calibrated scene was not written' "$work/log" || fail "not the expected refusal"
[ -e "$work/calibrated.json" ] && fail "the calibrated scene was written"
echo "refused: $(grep 'layerlab: error' "$work/log" | cut -c1-120)..."
"$layerlab" fit "$examples/paper_prototype.json" "$work/shrunk.json" --focal-length hold --lens-gaps hold --out "$work/calibrated.json" --force >"$work/log" 2>&1 || fail "--force failed"
grep -q "; --force: writing the calibrated scene anyway" "$work/log" || fail "--force did not warn"
[ -f "$work/calibrated.json" ] || fail "--force wrote nothing"
echo "--force: written, with a warning"
echo PASS
