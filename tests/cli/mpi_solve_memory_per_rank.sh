#!/bin/sh
# --max-memory applies per rank: a limit the whole solve is over but each
# rank's block is under runs on N ranks; a limit each rank is over is
# refused before any view is read, with the rank's estimate, exit non-zero.
. "$(dirname "$0")/mpi_solve_common.sh"
need() {  # the estimate in MB that the solve prints on stderr ("needs about 70.1 MB")
  sed -n 's/.*needs about \([0-9.]*\) MB.*/\1/p' "$work/log" | head -n 1
}
"$layerlab" solve "$small" --target "$work/lf" --iterations 1 --threads 1 --out "$work/one" >"$work/log" 2>&1 ||
  fail "the one-process solve failed"
whole=$(need)
mpi "$ranks" "$layerlab" solve "$small" --target "$work/lf" --iterations 1 --threads 1 --out "$work/n" >"$work/log" 2>&1 ||
  fail "the $ranks-rank solve failed"
rank0=$(need)
python3 -c 'import sys; sys.exit(not float(sys.argv[2]) < float(sys.argv[1]))' "$whole" "$rank0" ||
  fail "rank 0 of $ranks needs $rank0 MB, not less than the whole solve's $whole MB"
# Between: the last rank (the largest block) and the whole solve.
limit=$(python3 -c 'import sys; print("%.3f MB" % ((float(sys.argv[1]) - 0.05)))' "$whole")
"$layerlab" solve "$small" --target "$work/lf" --iterations 1 --threads 1 --out "$work/refused" --max-memory "$limit" \
  >"$work/log" 2>&1 && fail "one process under --max-memory $limit was not refused"
mpi "$ranks" "$layerlab" solve "$small" --target "$work/lf" --iterations 1 --threads 1 --out "$work/fits" \
  --max-memory "$limit" >"$work/log" 2>&1 || fail "$ranks ranks under --max-memory $limit per rank failed"
# Below every rank's share.
if mpi "$ranks" "$layerlab" solve "$small" --target "$work/lf" --iterations 1 --threads 1 --out "$work/over" \
  --max-memory "1 MB" >"$work/log" 2>&1; then fail "$ranks ranks under --max-memory 1 MB were not refused"; fi
grep -q "layerlab: error: rank 0 of $ranks: the solve needs about .*, more than --max-memory 1.0 MB per rank; nothing was read or written" \
  "$work/log" || fail "no per-rank refusal from rank 0"
[ ! -e "$work/over" ] || fail "the refused solve left $work/over"
echo "PASS"
