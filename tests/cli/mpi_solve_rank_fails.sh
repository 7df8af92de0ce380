#!/bin/sh
# Ranks that fail: a view that is not an EXR, which every rank's tile (a band
# of pixel rows of every view) reads. Every rank ends, the exit is non-zero,
# rank 0 alone reports, naming the first rank that failed and the file, and the earlier results in OUT are left as
# they were (nothing half-written, no staging folder left behind).
. "$(dirname "$0")/mpi_solve_common.sh"
"$layerlab" solve "$small" --target "$work/lf" --iterations 1 --threads 1 --out "$work/out" -q >"$work/log" 2>&1 ||
  fail "the first solve failed"
before=$(cd "$work/out" && find . -type f | sort | xargs md5sum)
echo "not an EXR" >"$work/lf/views/r04_c02.exr"
if mpi "$ranks" "$layerlab" solve "$small" --target "$work/lf" --iterations 2 --threads 1 --out "$work/out" \
  >"$work/log" 2>&1; then fail "a solve with a rank that failed exited 0"; fi
grep -q "layerlab: error: rank 0 of $ranks: .*r04_c02.exr" "$work/log" || fail "no error naming rank 0 and the file"
[ "$(grep -c 'layerlab: error' "$work/log")" = 1 ] || fail "more than one rank reported the error"
after=$(cd "$work/out" && find . -type f | sort | xargs md5sum)
[ "$before" = "$after" ] || fail "the failed solve changed $work/out"
[ "$(ls -A "$work/out" | grep -c staging)" = 0 ] || fail "a staging folder was left in $work/out"
# A fresh output folder is not created.
if mpi "$ranks" "$layerlab" solve "$small" --target "$work/lf" --iterations 2 --threads 1 --out "$work/fresh" \
  >"$work/log" 2>&1; then fail "a solve with a rank that failed exited 0"; fi
[ ! -e "$work/fresh" ] || fail "the failed solve left $work/fresh: $(ls -A "$work/fresh")"
echo "PASS"
