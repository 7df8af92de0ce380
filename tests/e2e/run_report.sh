#!/usr/bin/env bash
# End to end: `layerlab run` on the reduced example, then its index.html in
# headless Chromium. Usage:
#   run_report.sh run    LAYERLAB SCENE OUT_DIR   runs the main job and checks what it wrote
#   run_report.sh browse OUT_DIR                  opens OUT_DIR/index.html?selftest=1, greps the page's
#                                                 verdict, saves OUT_DIR/screenshot.png
# The browse step exits 77 (ctest: skipped) when no Chromium is installed.
set -euo pipefail

fail() { echo "FAIL: $*" >&2; exit 1; }

case "${1:-}" in
run)
  layerlab=$2 scene=$3 out=$4
  rm -rf "$out"
  # Files layerlab did not record writing stay, in a step folder or beside them (the sweep of what an
  # earlier run recorded and this one no longer writes: tests/cli/nothing_lost.sh).
  mkdir -p "$out/retina"
  echo stale > "$out/retina/9.99.png"
  echo mine > "$out/notes.txt"
  start=$(date +%s%N)
  "$layerlab" run "$scene" --out "$out"
  ms=$(( ($(date +%s%N) - start) / 1000000 ))
  echo "e2e: layerlab run took $((ms / 1000)).$(printf '%03d' $((ms % 1000))) s"
  for f in index.html system.txt system.json target/center_view.png solve/trace.csv solve/report.json \
           solve/psnr_vs_time.svg retina/retina.csv contrast/contrast.svg contrast/contrast.csv \
           compare/compare.csv compare/psnr_vs_time.svg; do
    [ -s "$out/$f" ] || fail "$out/$f is missing or empty"
  done
  [ -s "$out/retina/9.99.png" ] || fail "a file no run recorded writing was removed from a step folder"
  [ -s "$out/notes.txt" ] || fail "a file of the user's beside the step folders was removed"
  n_display=$(ls "$out"/retina/display/*.png | wc -l)
  n_natural=$(ls "$out"/retina/natural/*.png | wc -l)
  [ "$n_display" -ge 2 ] || fail "only $n_display retinal images of the display"
  [ "$n_display" -eq "$n_natural" ] || fail "$n_display display but $n_natural natural retinal images"
  # Every local file the page refers to exists.
  grep -o '\(src\|href\)="[^"#:]*"' "$out/index.html" | sed 's/^[a-z]*="//; s/"$//' | sort -u | while read -r path; do
    [ -e "$out/$path" ] || fail "index.html refers to $path, which is not in $out"
  done
  grep -q 'type="range"' "$out/index.html" || fail "index.html has no accommodation slider"
  grep -q 'hybrid_pbs_hwp_small' "$out/index.html" || fail "index.html has no comparison with the PBS/HWP hybrid"
  if grep -q 'https\?://' "$out/index.html"; then fail "index.html refers to the network"; fi
  echo "e2e: run output complete ($n_display accommodation states)"
  ;;
browse)
  out=$(cd "$2" && pwd)
  chromium=""
  for c in chromium chromium-browser google-chrome; do
    if command -v "$c" >/dev/null 2>&1; then chromium=$(command -v "$c"); break; fi
  done
  if [ -z "$chromium" ]; then
    echo "SKIP: no Chromium found (install Debian's chromium package: scripts/setup.sh does)"
    exit 77
  fi
  profile=$(mktemp -d)
  trap 'rm -rf "$profile"' EXIT
  flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run --no-default-browser-check
         --disable-background-networking --disable-component-update --disable-sync --disable-extensions
         --user-data-dir="$profile" --virtual-time-budget=10000)
  dom=$(timeout 120 "$chromium" "${flags[@]}" --dump-dom "file://$out/index.html?selftest=1" 2>"$out/chromium.log") ||
    fail "chromium failed (see $out/chromium.log)"
  verdict=$(printf '%s' "$dom" | tr '\n' ' ' | grep -o '<pre id="selftest"[^>]*>[^<]*</pre>' | sed 's/<[^>]*>//g')
  echo "e2e: page self-test: $verdict"
  case "$verdict" in
    PASS*) ;;
    *) fail "the page's self-test did not pass: ${verdict:-no verdict (did the script run?)}" ;;
  esac
  rm -f "$out/screenshot.png"
  timeout 120 "$chromium" "${flags[@]}" --hide-scrollbars --window-size=1400,4800 \
    --screenshot="$out/screenshot.png" "file://$out/index.html" 2>>"$out/chromium.log" >/dev/null ||
    fail "chromium could not take a screenshot (see $out/chromium.log)"
  [ -s "$out/screenshot.png" ] || fail "no screenshot written"
  echo "e2e: screenshot in $out/screenshot.png"
  ;;
*)
  echo "usage: $0 run LAYERLAB SCENE OUT_DIR | browse OUT_DIR" >&2
  exit 2
  ;;
esac
