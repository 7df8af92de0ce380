#!/usr/bin/env bash
# Issue 49: `solve --frames N` on a moving target scene (docs/target-format.md,
# "Moving scenes"): frames.csv with a row per frame and units in its header,
# frames.txt, the last frame's solution; a still scene, a light-field folder
# and bad counts refused by name with the output folder left as it was. On the
# reduced example: a few seconds.
# Usage: moving_target.sh LAYERLAB EXAMPLES_DIR WORK_DIR
source "$(dirname "$0")/common.sh"
rm -rf "$work" && mkdir -p "$work"
scene="$examples/small/hybrid_small.json"
moving="$examples/small/small_dice_turning.json"
"$layerlab" solve "$scene" --target-scene "$moving" --frames 4 --frame-iterations 2 --cold-every 3 \
  --out "$work/a" >"$work/log" 2>&1 || fail "solve --frames failed"
for f in frames.csv frames.txt report.json trace.csv patterns; do
  [ -e "$work/a/$f" ] || fail "no $f"
done
[ "$(wc -l <"$work/a/frames.csv")" -eq 5 ] || fail "frames.csv: not a header and 4 frames"
head -1 "$work/a/frames.csv" | grep -q '^frame,time_s,render_s,solve_s,iterations,psnr_db,cold_psnr_db,' \
  || fail "frames.csv: the header has changed"
# frame 3 is compared with its cold solve; frames 1 and 2 are not; frame 2 runs 2 iterations at 2/30 s.
awk -F, 'NR == 4 && ($5 != 2 || $2 + 0 < 0.0666 || $2 + 0 > 0.0667) { exit 1 }
         NR == 3 && $7 != "nan" { exit 1 }
         NR == 5 && ($7 == "nan" || $9 + 0 > 0.5) { exit 1 }' "$work/a/frames.csv" \
  || fail "frames.csv: the frames' times, iterations or cold references are wrong"
grep -q "frames/s of factorization" "$work/a/frames.txt" || fail "frames.txt: no frame rate"
mkdir -p "$work/kept" && echo keep >"$work/kept/mark"
refused() {  # $1: what the log must name; the rest: the solve's arguments
  local name=$1
  shift
  "$layerlab" solve "$scene" "$@" --out "$work/kept" >"$work/log" 2>&1 && fail "accepted: $*"
  grep -q -- "$name" "$work/log" || fail "$*: the error does not name $name"
  [ "$(cat "$work/kept/mark")" = keep ] && [ "$(ls "$work/kept")" = mark ] || fail "$*: touched the output folder"
}
refused "does not move" --frames 2
refused "--frames" --target-scene "$moving" --frames -1
refused "--frame-iterations" --target-scene "$moving" --frames 2 --frame-iterations 0
refused "a light-field folder" --target "$work/a" --frames 2
refused "--cold-every" --target-scene "$moving" --cold-every 2
echo "moving target: frames.csv, frames.txt, the last solution; still scenes and bad counts refused"
