#!/bin/sh
# --max-memory applies per rank, and each rank's estimate counts its own
# block of view rows: a limit below every rank's estimate is refused by rank 0
# with its estimate (its share of the target, less than the whole target),
# before any view is read, exit non-zero, nothing written; a limit above each
# rank's estimate (far below the ranks' sum) runs. At this size the program's
# resident memory (with MPI's libraries) outweighs the rays, so the shares are
# compared on the estimate's ray-sized part, the target, not on the totals.
. "$(dirname "$0")/mpi_solve_common.sh"
# target_mb: the target's share in the refusal on stderr ("(target 1.0 MB + ...").
target_mb() { sed -n 's/.*needs about [0-9.]* MB (target \([0-9.]*\) MB.*/\1/p' "$work/log" | head -n 1; }
need() { sed -n 's/.*needs about \([0-9.]*\) MB.*/\1/p' "$work/log" | head -n 1; }
if "$layerlab" solve "$small" --target "$work/lf" --iterations 1 --threads 1 --out "$work/one" --max-memory "1 MB" \
  >"$work/log" 2>&1; then fail "one process under --max-memory 1 MB was not refused"; fi
whole=$(target_mb)
[ -n "$whole" ] || fail "no breakdown in the one-process refusal: $(cat "$work/log")"
if mpi "$ranks" "$layerlab" solve "$small" --target "$work/lf" --iterations 1 --threads 1 --out "$work/over" \
  --max-memory "1 MB" >"$work/log" 2>&1; then fail "$ranks ranks under --max-memory 1 MB were not refused"; fi
grep -q "layerlab: error: rank 0 of $ranks: the solve needs about .*, more than --max-memory 1.0 MB per rank; nothing was read or written" \
  "$work/log" || fail "no per-rank refusal from rank 0: $(cat "$work/log")"
[ ! -e "$work/over" ] || fail "the refused solve left $work/over"
rank0=$(target_mb)
python3 -c 'import sys; sys.exit(not float(sys.argv[2]) < float(sys.argv[1]))' "$whole" "$rank0" ||
  fail "rank 0 of $ranks holds $rank0 MB of the target, not less than the whole $whole MB"
rank0_need=$(need)
# Above each rank's estimate, below what the ranks hold together.
limit=$(python3 -c 'import sys; print("%.1f MB" % (float(sys.argv[1]) + 8))' "$rank0_need")
mpi "$ranks" "$layerlab" solve "$small" --target "$work/lf" --iterations 1 --threads 1 --out "$work/fits" \
  --max-memory "$limit" >"$work/log" 2>&1 || fail "$ranks ranks under --max-memory $limit per rank failed: $(cat "$work/log")"
grep -q "rank 0 of $ranks needs about" "$work/log" || fail "rank 0 does not say what each rank needs"
echo "PASS"
