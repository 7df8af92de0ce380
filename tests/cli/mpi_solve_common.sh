# Sourced by the MPI solve tests (tests/cli/mpi_solve_*.sh): the reduced
# example's target (5 x 5 views of 80 x 40) rendered once, and `mpirun`
# with the flags CI needs (root, two cores).
# Expects: $1 LAYERLAB, $2 EXAMPLES_DIR, $3 WORK_DIR, $4 MPIEXEC, $5 RANKS, $6 EXR_DIFFERENCE.
. "$(dirname "$0")/common.sh"
mpiexec=$4 ranks=$5 exr_difference=$6
rm -rf "$work" && mkdir -p "$work"
small=$examples/small/hybrid_small.json
"$layerlab" render-target "$examples/small/small_dice_target.json" --out "$work/lf" -q >"$work/log" 2>&1 ||
  fail "rendering the target failed"
mpi() { "$mpiexec" --oversubscribe --allow-run-as-root -np "$@"; }
