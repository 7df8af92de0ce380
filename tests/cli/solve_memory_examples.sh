#!/bin/sh
# The memory estimate ("the solve needs about X", what --max-memory refuses
# by) is an upper bound of the solve's peak, and not far above it, for every
# shipped example that solves, as its solve section configures it (its
# target scene rendered, its solver), a few iterations each (quasi-newton:
# one warm-start iteration, then steps), and the reduced example with the
# retinal objective. The peak is the command's own
# (ru_maxrss of the child, its VmHWM), rendering and writing included.
# Usage: solve_memory_examples.sh LAYERLAB EXAMPLES_DIR WORK_DIR [SCENE.json ...]
set -u
layerlab=$1 examples=$2 work=$3
shift 3
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" || fail "cannot make $work"
# The estimate may be at most this fraction above the peak: at this size the program (58 of 70 MB) is most of
# the peak, so the margin's fixed part weighs more than in tests/solve_memory_test.cpp (10 %).
above_at_most=0.12
if [ $# -eq 0 ]; then
  for scene in "$examples"/*.json "$examples"/small/*.json; do
    grep -q '"solve"' "$scene" && set -- "$@" "$scene"
  done
fi
[ $# -gt 0 ] || fail "no example with a solve section in $examples"
failed=0
# check NAME SCENE [SOLVE OPTIONS...]: one solve, its estimate against its peak.
check() {
  name=$1 scene=$2
  shift 2
  # The child's peak resident memory (ru_maxrss, KiB) from wait4.
  peak_kib=$(python3 -c '
import os, subprocess, sys
with open(sys.argv[1], "w") as log:
    child = subprocess.Popen(sys.argv[2:], stdout=log, stderr=subprocess.STDOUT)
    _, status, usage = os.wait4(child.pid, 0)
print(usage.ru_maxrss if os.waitstatus_to_exitcode(status) == 0 else -1)
' "$work/$name.log" "$layerlab" solve "$scene" "$@" --out "$work/$name")
  [ "$peak_kib" != -1 ] || fail "$name: the solve failed: $(tail -n 5 "$work/$name.log")"
  estimate=$(sed -n 's/.*the solve needs about \([0-9.]* [MG]B\).*/\1/p' "$work/$name.log" | head -n 1)
  [ -n "$estimate" ] || fail "$name: no \"the solve needs about\" note: $(tail -n 5 "$work/$name.log")"
  python3 -c '
import sys
name, estimate, peak_kib, above = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
value, unit = estimate.split()
estimate_bytes = float(value) * (1e9 if unit == "GB" else 1e6)
peak = peak_kib * 1024
print("%s: estimate %.1f MB, peak %.1f MB (%+.1f %%)" % (name, estimate_bytes / 1e6, peak / 1e6, 100 * (estimate_bytes - peak) / peak))
if peak > estimate_bytes:
    print("FAIL: %s: the peak %.1f MB exceeds the estimate %s" % (name, peak / 1e6, estimate)); sys.exit(1)
if estimate_bytes > (1 + above) * peak:
    print("FAIL: %s: the estimate %s is more than %d %% above the peak %.1f MB" % (name, estimate, 100 * above, peak / 1e6)); sys.exit(1)
' "$name" "$estimate" "$peak_kib" "$above_at_most" || failed=1
  rm -rf "$work/$name"
}
for scene in "$@"; do
  solver=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["solve"].get("solver", ""))' "$scene")
  if [ "$solver" = quasi-newton ]; then
    check "$(basename "$scene" .json)" "$scene" --warm-start-iterations 1 --iterations 3
  else
    check "$(basename "$scene" .json)" "$scene" --iterations 2
  fi
done
# The retinal objective (its operator's tables, retinal images and pass) on the reduced example.
check hybrid_small_retinal "$examples/small/hybrid_small.json" --solver quasi-newton --objective retinal \
  --warm-start-iterations 1 --iterations 3
[ "$failed" = 0 ] || fail "see above"
echo "PASS"
