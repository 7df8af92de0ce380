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
  # The summary leads the page with the numbers the files hold (issue 50).
  /usr/bin/python3 - "$out" <<'PY' || fail "the page's summary disagrees with the files"
import csv, html, json, re, sys
out = sys.argv[1]
page = open(out + "/index.html").read()
main = page[page.index("<main>"):]
assert main.index('<section id="summary">') < main.index('<section id="steps">'), "the summary is not first"
summary = page[page.index('<section id="summary">'):]
summary = summary[:summary.index("</section>")]
rows = {html.unescape(re.sub("<[^>]*>", "", a)): html.unescape(b)
        for a, b in re.findall(r"<tr><th[^>]*>(.*?)</th><td>(.*?)</td></tr>", summary)}
report = json.load(open(out + "/solve/report.json"))
assert rows["light-field PSNR"] == "%.2f dB" % report["final_psnr_db"], rows["light-field PSNR"]
states = list(csv.DictReader(open(out + "/retina/retina.csv")))
mean = sum(float(r["psnr_db"]) for r in states) / len(states)
key = "retinal PSNR against natural viewing (mean of %d accommodation states)" % len(states)
assert rows[key] == "%.2f dB" % mean, (rows.get(key), mean)
assert any(k.startswith("contrast peak minus target depth: ") for k in rows), sorted(rows)
system = json.load(open(out + "/system.json"))
print("e2e: the summary's %d numbers agree with report.json, retina.csv and system.json" % len(rows))
# The pattern previews are in the eye's orientation: a mirror-reversed layer's preview is its panel-order
# image turned back (compared by correlation, the panel-ready image being gamma-encoded).
import numpy
from skimage import io
for layer in system["layers"]:
    eye = io.imread(out + "/solve/pattern_previews/%s.png" % layer["name"]).astype(float).mean(axis=2)
    panel = io.imread(out + "/solve/panel_previews/%s.png" % layer["name"]).astype(float).mean(axis=2)
    flip_x, flip_y = layer["flip"]
    turned = panel[::-1 if flip_y else 1, ::-1 if flip_x else 1]
    same = numpy.corrcoef(eye.ravel(), turned.ravel())[0, 1]
    other = numpy.corrcoef(eye.ravel(), panel[:, ::-1].ravel() if not flip_x else panel.ravel())[0, 1]
    assert same > 0.9 and same > other + 0.05, (layer["name"], same, other)
print("e2e: the pattern previews are as the eye sees each layer")
PY
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
