#!/bin/sh
# A rank that fails: the last rank's block of view rows holds a view that is
# not an EXR. Every rank ends, the exit is non-zero, rank 0 alone reports,
# naming the rank and the file, and the earlier results in OUT are left as
# they were (nothing half-written, no staging folder left behind).
. "$(dirname "$0")/mpi_solve_common.sh"
"$layerlab" solve "$small" --target "$work/lf" --iterations 1 --threads 1 --out "$work/out" -q >"$work/log" 2>&1 ||
  fail "the first solve failed"
before=$(cd "$work/out" && find . -type f | sort | xargs md5sum)
echo "not an EXR" >"$work/lf/views/r04_c02.exr"
if mpi "$ranks" "$layerlab" solve "$small" --target "$work/lf" --iterations 2 --threads 1 --out "$work/out" \
  >"$work/log" 2>&1; then fail "a solve with a rank that failed exited 0"; fi
last=$((ranks - 1))
grep -q "layerlab: error: rank $last of $ranks: .*r04_c02.exr" "$work/log" || fail "no error naming rank $last and its file"
[ "$(grep -c 'layerlab: error' "$work/log")" = 1 ] || fail "more than one rank reported the error"
after=$(cd "$work/out" && find . -type f | sort | xargs md5sum)
[ "$before" = "$after" ] || fail "the failed solve changed $work/out"
[ "$(ls -A "$work/out" | grep -c staging)" = 0 ] || fail "a staging folder was left in $work/out"
# A fresh output folder is not created.
if mpi "$ranks" "$layerlab" solve "$small" --target "$work/lf" --iterations 2 --threads 1 --out "$work/fresh" \
  >"$work/log" 2>&1; then fail "a solve with a rank that failed exited 0"; fi
[ ! -e "$work/fresh" ] || fail "the failed solve left $work/fresh: $(ls -A "$work/fresh")"
echo "PASS"
