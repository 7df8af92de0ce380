#!/usr/bin/env bash
# Ctrl-C during `layerlab solve`: the last complete iteration's outputs are
# written, the report says "interrupted", the exit code is 130, and no
# temporary file is left behind.
# Usage: solve_interrupted.sh LAYERLAB SCENE TARGET_DIR OUT_DIR
set -u
layerlab=$1 scene=$2 target=$3 out=$4
fail() { echo "FAIL: $*"; cat "$out.log" 2>/dev/null; exit 1; }
rm -rf "$out" "$out.log"
# 1000 iterations (a few minutes): off a terminal the first progress line
# comes after ten seconds of work; the signal comes then, long before the last.
"$layerlab" solve "$scene" --target "$target" --iterations 1000 --out "$out" 2>"$out.log" &
pid=$!
for _ in $(seq 1 2400); do
  grep -qE "hybrid: [0-9]+/1000" "$out.log" 2>/dev/null && break
  sleep 0.05
done
kill -INT "$pid"
wait "$pid"
code=$?
[ "$code" -eq 130 ] || fail "exit code $code, expected 130"
grep -q "interrupted: .* holds the patterns of iteration" "$out.log" || fail "no interruption message"
grep -q '"termination": "interrupted"' "$out/report.json" || fail "report.json does not say interrupted"
for f in "$out"/patterns/*.exr "$out"/panels/*.png "$out"/trace.csv; do [ -s "$f" ] || fail "missing $f"; done
if find "$out" -name '.*.tmp-*' | grep -q .; then fail "temporary files left behind"; fi
echo "PASS: interrupted after $(tail -n 1 "$out/trace.csv" | cut -d, -f1) iterations, outputs complete"
