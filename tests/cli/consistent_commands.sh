#!/usr/bin/env bash
# Issue 18, "Consistent commands", on the rendered grating target (paper
# prototype, two iterations a solve):
#   1. --quiet silences progress and notes, never an error; --verbose prints
#      every iteration; compare prints one progress line per run;
#   2. values with units on the command line ("0.4 D", "5 s", "3 arcmin") give
#      what the bare numbers give, and a bad one names the option and the value;
#   3. solve, retina, contrast and compare each write an index.html whose every
#      linked or shown file exists, with the version in it;
#   4. compare runs like for like ("shared") unless --scene-options ("scene").
# Usage: consistent_commands.sh LAYERLAB EXAMPLES_DIR TARGET_LF WORK_DIR
set -u
layerlab=$1 examples=$2 target=$3 work=$4
fail() { echo "FAIL: $*"; for f in "$work"/*.err; do [ -f "$f" ] && { echo "== $f"; tail -n 8 "$f"; }; done; exit 1; }
rm -rf "$work"
mkdir -p "$work"
scene=$examples/paper_prototype.json
version=$("$layerlab" --version) || fail "--version exited non-zero"

# Every file an index.html names (href or src, not a link to a place in the page or the web) must exist.
check_page() {  # $1: output folder, $2: a section id the page must have
  local page=$1/index.html
  [ -s "$page" ] || fail "$page missing"
  grep -q "id=\"$2\"" "$page" || fail "$page has no section \"$2\""
  grep -qF "$version" "$page" || fail "$page does not name the version ($version)"
  local n=0
  for ref in $(grep -o -E '(href|src)="[^"#][^"]*"' "$page" | sed -E 's/^(href|src)="//; s/"$//' | sort -u); do
    case $ref in http:* | https:* | data:*) continue ;; esac
    [ -e "$1/$ref" ] || fail "$page links to $ref, which $1 does not hold"
    n=$((n + 1))
  done
  [ "$n" -ge 2 ] || fail "$page links to only $n files"
  echo "ok: $page links to $n files, all present"
}

# 1. Quiet, normal, verbose.
"$layerlab" solve "$scene" --target "$target" --iterations 2 --quiet --out "$work/solve" >"$work/quiet.out" 2>"$work/quiet.err" ||
  fail "solve --quiet failed"
[ -s "$work/quiet.err" ] && fail "solve --quiet wrote to stderr: $(head -n 3 "$work/quiet.err")"
grep -q "hybrid: iteration limit after 2 iterations" "$work/quiet.out" || fail "solve --quiet lost its result on stdout"
"$layerlab" solve "$scene" --target "$target" --iterations 2 --out "$work/solve" >/dev/null 2>"$work/normal.err" || fail "solve failed"
grep -q "^hybrid: done in [0-9.]* s: iteration limit" "$work/normal.err" || fail "solve: no summary progress line"
grep -q "the solve needs about" "$work/normal.err" || fail "solve: the memory note is gone"
"$layerlab" solve "$scene" --target "$target" --iterations 2 --verbose --out "$work/solve" >/dev/null 2>"$work/verbose.err" ||
  fail "solve --verbose failed"
for k in 1 2; do grep -q "^hybrid: $k/2 .*PSNR" "$work/verbose.err" || fail "solve --verbose: no line for iteration $k"; done
# Errors are never silenced.
if "$layerlab" solve "$scene" --target "$work/no_such_lf" --quiet --out "$work/never" 2>"$work/quiet_error.err"; then
  fail "solve of a missing target succeeded"
fi
grep -q "layerlab: error:" "$work/quiet_error.err" || fail "--quiet silenced an error"
if "$layerlab" solve "$scene" --quiet --verbose --target "$target" --out "$work/never" 2>"$work/both.err"; then
  fail "--quiet and --verbose together were accepted"
fi

"$layerlab" compare "$scene" "$examples/multiplicative_2layer.json" --solvers hybrid,joint --iterations 2 --time-budget "30 s" \
  --target "$target" --out "$work/compare" >"$work/compare.out" 2>"$work/compare.err" || fail "compare failed"
lines=$(grep -c "^compare " "$work/compare.err")
[ "$lines" -eq 4 ] || fail "compare printed $lines progress lines for 4 runs (one each expected)"
grep -q "iterations  PSNR" "$work/compare.err" && fail "compare printed iteration lines without --verbose"
grep -q -E "^paper_prototype +hybrid .* shared +iteration limit" "$work/compare.out" || fail "compare: no shared options row"
head -n 1 "$work/compare/compare.csv" | grep -q ",solver_options$" || fail "compare.csv has no solver_options column"
grep -q ",shared$" "$work/compare/compare.csv" || fail "compare.csv does not say shared"
"$layerlab" compare "$scene" --iterations 2 --scene-options --target "$target" --out "$work/compare_own" \
  >"$work/compare_own.out" 2>"$work/compare_own.err" || fail "compare --scene-options failed"
grep -q -E "^paper_prototype +hybrid .* scene +iteration limit" "$work/compare_own.out" || fail "compare --scene-options: no scene row"
grep -q "<td class=\"l\">scene</td>" "$work/compare_own/index.html" || fail "compare's page does not say scene"

# 2. Units on the command line.
"$layerlab" solve "$scene" --target "$target" --iterations 2 --time-budget "2 min" --quiet --out "$work/solve_units" >/dev/null ||
  fail "solve --time-budget \"2 min\" failed"
"$layerlab" retina "$scene" --patterns "$work/solve" --accommodation "0.4 D,1.3 D" --focal-stack "1.0 D:1.6 D:0.3 D" \
  --resolution "15 arcmin" --out "$work/retina" >"$work/retina.out" 2>"$work/retina.err" || fail "retina with units failed"
ls "$work/retina/display" | tr '\n' ' ' | grep -q "^0.40D.exr 0.40D.png 1.00D.exr 1.00D.png 1.30D.exr 1.30D.png 1.60D.exr 1.60D.png $" ||
  fail "retina with units wrote $(ls "$work/retina/display" | tr '\n' ' ')"
if "$layerlab" solve "$scene" --target "$target" --time-budget "5 parsecs" --out "$work/never" 2>"$work/bad_unit.err"; then
  fail "--time-budget \"5 parsecs\" was accepted"
fi
grep -q -- "--time-budget: \"5 parsecs\" is not a number or a duration" "$work/bad_unit.err" ||
  fail "the bad unit's error does not name the option and value: $(cat "$work/bad_unit.err")"
if "$layerlab" contrast "$scene" --depths "1.3 D,2 deg" --out "$work/never" 2>"$work/bad_depth.err"; then
  fail "--depths with an angle was accepted"
fi
grep -q -- "--depths: \"2 deg\"" "$work/bad_depth.err" || fail "the bad depth's error: $(cat "$work/bad_depth.err")"
if "$layerlab" compare "$scene" --objectives "lightfield,retina" --target "$target" --out "$work/never" 2>"$work/bad_objective.err"; then
  fail "--objectives retina was accepted"
fi
grep -q -- "--objectives: \"retina\" is not one of lightfield or retinal" "$work/bad_objective.err" ||
  fail "the bad objective's error: $(cat "$work/bad_objective.err")"
"$layerlab" contrast "$scene" --depths "1.3 D" --frequencies "1 cpd" --accommodation "0.5 D:2 D:0.5 D" --no-peak-uncertainty \
  --resolution "3 arcmin" --strip-rows 4 --out "$work/contrast" >"$work/contrast.out" 2>"$work/contrast.err" ||
  fail "contrast with units failed"
grep -q -E "^paper_prototype +1.30 +1.0 " "$work/contrast.out" || fail "contrast with units: no 1.30 D, 1 cpd curve"
grep -qF "# $version" "$work/contrast/peaks.txt" || fail "peaks.txt does not name the version"

# 3. Each command's own page.
check_page "$work/solve" solve
check_page "$work/retina" retina
check_page "$work/contrast" contrast
check_page "$work/compare" compare
# The panel-ready previews are the active region (the layer's pixels), linked to the full panel.
png_size() { od -An -tu1 -j16 -N8 "$1" | awk '{print $1*16777216+$2*65536+$3*256+$4 "x" $5*16777216+$6*65536+$7*256+$8}'; }
for preview in "$work"/solve/panel_previews/*.png; do
  name=$(basename "$preview")
  pattern=$work/solve/pattern_previews/$name full=$work/solve/panels/$name
  [ "$(png_size "$preview")" = "$(png_size "$pattern")" ] ||
    fail "$name: the panel preview is $(png_size "$preview"), the layer $(png_size "$pattern")"
  [ "$(png_size "$preview")" != "$(png_size "$full")" ] || fail "$name: the preview is the full panel"
  grep -q "href=\"panels/$name\"><img src=\"panel_previews/$name\"" "$work/solve/index.html" ||
    fail "$name: the preview does not link to the full panel"
done
# The slider's declared states are labelled under it.
grep -q '<div class="ticks"><span style="left:calc(0.000% + 8.00px)">0.40 D</span>' "$work/retina/index.html" ||
  fail "the retina slider's ticks are not labelled"
grep -q "\"layerlab\": \"$version\"" "$work/solve/report.json" || fail "report.json does not name the version"
tail -n 1 "$work/solve/report.txt" | grep -qF "written by $version" || fail "report.txt does not name the version"
echo "PASS"
