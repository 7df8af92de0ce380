#!/usr/bin/env bash
# `layerlab psf` (docs/eye-model.md, "Wave optics"): its files, the in-focus
# OTF equal by both paths, a defocused one where the pupil function and the
# wave-optics retina agree and the geometric path does not, and bad values
# refused by name with the output folder left as it was.
# Usage: psf.sh LAYERLAB EXAMPLES_DIR WORK_DIR
source "$(dirname "$0")/common.sh"
rm -rf "$work" && mkdir -p "$work"
scene="$examples/paper_prototype.json"
"$layerlab" psf "$scene" --vergence "0,0.1 D" --frequencies 5,20 --size 65 --out "$work/a" >"$work/log" 2>&1 \
  || fail "psf failed"
for f in mtf.csv mtf.svg psf_0.00D.exr psf_0.00D.png psf_0.10D.exr psf_0.10D.png; do
  [ -s "$work/a/$f" ] || fail "no $f"
done
[ "$(wc -l <"$work/a/mtf.csv")" -eq 13 ] || fail "mtf.csv: not 3 channels x 2 vergences x 2 frequencies and a header"
# channel,wavelength_nm,vergence_D,frequency_cpd,otf_wave,otf_wave_retina,otf_geometric
awk -F, '$1 == "G" && $3 + 0 == 0 && $4 + 0 == 20 {
  if ($5 - $7 > 0.005 || $7 - $5 > 0.005) { print "in focus the paths differ: " $0; exit 1 } }' "$work/a/mtf.csv" \
  || fail "in focus the wave and geometric OTFs differ"
awk -F, '$1 == "G" && $3 + 0 == 0.1 && $4 + 0 == 20 {
  if ($5 - $6 > 0.01 || $6 - $5 > 0.01) { print "retina off the pupil function: " $0; exit 1 }
  if ($5 - $7 < 0.05) { print "the geometric path is not off at 20 cpd, 0.1 D: " $0; exit 1 } }' "$work/a/mtf.csv" \
  || fail "20 cpd at 0.1 D: the wave-optics retina and pupil function disagree, or the geometric path agrees"
mkdir -p "$work/kept" && echo keep >"$work/kept/mark"
for bad in "--size 1" "--frequencies -3" "--vergence nine" "--resolution 1"; do
  # shellcheck disable=SC2086
  "$layerlab" psf "$scene" $bad --out "$work/kept" >"$work/log" 2>&1 && fail "psf $bad was accepted"
  grep -q -- "${bad%% *}" "$work/log" || fail "psf $bad: the error does not name the option"
  [ "$(cat "$work/kept/mark")" = keep ] && [ "$(ls "$work/kept")" = mark ] || fail "psf $bad touched the output folder"
done
"$layerlab" contrast "$scene" --diffraction airy --out "$work/c" >"$work/log" 2>&1 && fail "--diffraction airy was accepted"
grep -q -- "--diffraction" "$work/log" || fail "--diffraction airy: not named"
echo "psf: files, in-focus agreement, 20 cpd at 0.1 D, bad values refused"
