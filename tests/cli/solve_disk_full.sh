#!/usr/bin/env bash
# A disk that fills up (simulated with a file-size limit, RLIMIT_FSIZE) makes
# `layerlab solve` fail with a message naming the file, and leaves no partial
# or temporary file: every output is written to a temporary file and renamed.
# Usage: solve_disk_full.sh LAYERLAB SCENE TARGET_DIR OUT_DIR
set -u
layerlab=$1 scene=$2 target=$3 out=$4
fail() { echo "FAIL: $*"; cat "$out.log" 2>/dev/null; exit 1; }
rm -rf "$out" "$out.log"
mkdir -p "$out"
# 64 blocks of 512 bytes (bash's ulimit -f unit for most shells is 1024; either way far below a pattern EXR).
(ulimit -f 64; exec "$layerlab" solve "$scene" --target "$target" --iterations 1 --out "$out") 2>"$out.log"
code=$?
[ "$code" -ne 0 ] || fail "exit code 0 although nothing could be written"
[ "$code" -lt 128 ] || fail "killed by a signal ($code) instead of a clean error"
grep -q "layerlab: error: .*\(write\|disk\|File too large\)" "$out.log" || fail "no clear error message"
if find "$out" -name '.*.tmp-*' | grep -q .; then fail "temporary files left behind"; fi
# Every file that exists is complete: it is one of the small ones that fit, not a truncated large one.
while IFS= read -r f; do
  size=$(stat -c %s "$f")
  [ "$size" -lt 65536 ] || fail "$f has $size bytes, beyond the limit"
done < <(find "$out" -type f)
echo "PASS: refused with: $(grep 'layerlab: error' "$out.log")"
