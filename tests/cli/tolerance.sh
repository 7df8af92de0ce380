#!/usr/bin/env bash
# `layerlab tolerance` on the reduced main job (examples/small/hybrid_small.json):
# its outputs, the same numbers from the same seed and others from another,
# the dominant tolerance named, and hostile tolerances refused by file and
# pointer with the output folder left as it was.
# Usage: tolerance.sh LAYERLAB EXAMPLES_DIR WORK_DIR
source "$(dirname "$0")/common.sh"
rm -rf "$work" && mkdir -p "$work"
scene="$examples/small/hybrid_small.json"
cat >"$work/tol.json" <<'JSON'
{"panel_decentre": "0.2 mm", "panel_tilt": "0.2 deg", "gap": "0.05 mm", "focal_length": "0.5 %"}
JSON
"$layerlab" tolerance "$scene" --tolerances "$work/tol.json" --samples 4 --seed 3 --iterations 2 --out "$work/a" \
  >"$work/log" 2>&1 || fail "tolerance failed"
for f in tolerance.md tolerance.json samples.csv draws.csv sensitivity.csv; do
  [ -s "$work/a/$f" ] || fail "no $f"
done
grep -q "Dominant tolerance: panel_decentre by misregistration; panel_decentre by PSNR" "$work/log" \
  || fail "0.2 mm of decentre (0.48 px at 585 um) is not named the dominant tolerance"
grep -q "tolerance: done in" "$work/log" || fail "no progress on stderr"
[ "$(wc -l <"$work/a/samples.csv")" -eq 17 ] || fail "samples.csv: not 4 samples x 4 layers and a header"
grep -q '| panel_tilt | 0.200 deg | 8 | no: ' "$work/a/tolerance.md" || fail "panel tilt not said unmeasurable by calibration"
"$layerlab" tolerance "$scene" --tolerances "$work/tol.json" --samples 4 --seed 3 --iterations 2 --out "$work/b" \
  >"$work/log" 2>&1 || fail "second run failed"
cmp -s "$work/a/samples.csv" "$work/b/samples.csv" || fail "the same seed gave other numbers"
cmp -s "$work/a/draws.csv" "$work/b/draws.csv" || fail "the same seed gave other draws"
"$layerlab" tolerance "$scene" --tolerances "$work/tol.json" --samples 4 --seed 4 --no-psnr --out "$work/c" \
  >"$work/log" 2>&1 || fail "--no-psnr run failed"
cmp -s "$work/a/draws.csv" "$work/c/draws.csv" && fail "another seed gave the same draws"
echo "same seed, same numbers; another seed, other draws"

# Hostile tolerances: refused naming the file and pointer, nothing written.
ls -lR "$work/a" >"$work/before"
refused() {  # JSON, expected message
  printf '%s\n' "$1" >"$work/bad.json"
  if "$layerlab" tolerance "$scene" --tolerances "$work/bad.json" --no-psnr --out "$work/a" >"$work/log" 2>&1; then
    fail "accepted $1"
  fi
  grep -qF "$2" "$work/log" || fail "for $1: not \"$2\""
}
refused '{"gap": "-0.1 mm"}' "$work/bad.json: /gap: a tolerance is a limit either way of the design, given positive"
refused '{"gap": "nan mm"}' "$work/bad.json: /gap: "
refused '{"panel_tilt": "0.2 mm"}' "$work/bad.json: /panel_tilt: "
refused '{"focal_lenght": "1 %"}' "did you mean \"focal_length\"?"
refused '{}' "$work/bad.json: /: no tolerances"
"$layerlab" tolerance "$scene" --samples 0 --no-psnr --out "$work/a" >"$work/log" 2>&1 && fail "--samples 0 accepted"
"$layerlab" tolerance "$scene" --no-psnr --out "$work/a" >"$work/log" 2>&1 && fail "a scene without tolerances accepted"
grep -qF 'no tolerances: give --tolerances FILE or a "tolerance" object in the scene' "$work/log" || fail "no reason given"
ls -lR "$work/a" >"$work/after"
cmp -s "$work/before" "$work/after" || fail "a refused run changed the output folder"
echo "hostile tolerances refused, the folder unchanged"
echo PASS
