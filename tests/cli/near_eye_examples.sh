#!/usr/bin/env bash
# Issue 51's near-eye and see-through examples (non-uniform backlights, the
# world behind a combiner, paths folded by polarization, a lens array), each through every
# command a user runs on it: info names the emission (or the world and the
# ambient contrast, or the ghosts), solve writes the panels and the
# backlight's layer (the LEDs' values, or the fixed pinlights unchanged),
# retina shows it (with the world and the ghosts added), run writes its report.
# Usage: near_eye_examples.sh LAYERLAB EXAMPLES_DIR WORK_DIR
set -u
layerlab=$1 examples=$2 work=$3
fail() { echo "FAIL: $*"; for f in "$work"/*.err; do [ -f "$f" ] && { echo "== $f"; tail -n 8 "$f"; }; done; exit 1; }
rm -rf "$work"
mkdir -p "$work"

check() {  # $1: example stem, $2: its backlight's name (or its element with a layer), $3: its panel's, $4: text info must print
  local scene=$examples/$1.json out=$work/$1
  "$layerlab" info "$scene" >"$out.info" 2>"$work/$1.info.err" || fail "info $1 exited non-zero"
  grep -qF "$4" "$out.info" || fail "info $1 does not say: $4"
  grep -qF "\"$2\"" "$out.info" || fail "info $1 does not place \"$2\" on the path"
  "$layerlab" solve "$scene" --out "$out.solve" 2>"$work/$1.solve.err" || fail "solve $1 exited non-zero"
  for f in patterns/$2.exr patterns/$3.exr panels/$2.png panels/$3.png index.html; do
    [ -s "$out.solve/$f" ] || fail "solve $1 wrote no $f"
  done
  "$layerlab" retina "$scene" --patterns "$out.solve" --accommodation 1.0 --resolution 0.5 --out "$out.retina" \
    2>"$work/$1.retina.err" || fail "retina $1 exited non-zero"
  [ -s "$out.retina/display/1.00D.exr" ] || fail "retina $1 wrote no display/1.00D.exr"
  "$layerlab" run "$scene" --out "$out.run" 2>"$work/$1.run.err" || fail "run $1 exited non-zero"
  [ -s "$out.run/index.html" ] || fail "run $1 wrote no index.html"
}

check pinlight pinlights lcd "pinlights emits an array of 24 x 16 pinlights 0.100 mm wide, 1.60 mm apart"
grep -qF "the backlight \"pinlights\" emits on" "$work/pinlight.solve.err" ||
  fail "solve pinlight does not name the pinlights as the cause of its low PSNR"
check local_dimming leds front "leds emits an array of 13 x 7 LEDs 4.00 mm apart, each spread over 6.00 mm (FWHM): their values are solved with the panels"
check see_through rear_b front_b "ambient contrast       2.286: the display's full white over the world, (270.00 + 210.00) / 210.00 cd/m2"
[ -s "$work/see_through.retina/see_through/1.00D.exr" ] || fail "retina see_through wrote no see_through/1.00D.exr"
head -1 "$work/see_through.retina/retina.csv" | grep -q ",world_cd_m2,contrast_against_world" ||
  fail "retina see_through's retina.csv has no world columns"
check pancake rear front "folded paths: each stack placed and solved by its brightest route; 2 ghosts by other routes"
grep -qF "by reflective_polarizer.transmitted/half_mirror.transmitted" "$work/pancake.info" ||
  fail "info pancake does not list the ghost straight through its half mirror"
check birdbath rear front "splitter.transmitted/bath.reflected/splitter.reflected"
check integral_imaging panel panel "lens array: 16 x 12 square lenslets 1.00 mm apart before \"panel\""
echo "near-eye examples: info, solve, retina and run ok"
