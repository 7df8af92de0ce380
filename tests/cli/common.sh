# Sourced by the CLI test scripts: the usual arguments, a failure that shows
# the log's end, and the reduced example without its analyses.
# Expects: $1 LAYERLAB, $2 EXAMPLES_DIR, $3 WORK_DIR.
set -u
layerlab=$1 examples=$2 work=$3
fail() { echo "FAIL: $*"; [ -f "$work/log" ] && tail -n 8 "$work/log"; exit 1; }
# The reduced main job (examples/small/hybrid_small.json, $1) with an empty
# "run" section, written to $2: only the render and the solve, under a second.
solve_only() {
  awk '/^  "run": \{/{print "  \"run\": {}"; print "}"; exit} {print}' "$1" >"$2"
  grep -q '"target_scene": "small_dice_target.json"' "$2" || fail "the reduced example has changed; update tests/cli/common.sh"
}
