#!/bin/sh
# mpirun -np N layerlab solve: every solver that sums over rays (and the
# multiplicative rank-2 display, its subframes), its rays partitioned in
# tiles across N ranks, against the same solve in one process: the
# same PSNR to 1e-9 relative and patterns to 1e-6 of their largest value
# (the ranks' float sums differ in rounding from one process's); N = 1 under
# mpirun gives the same bits as one process; N fixed, the same bits run to run.
. "$(dirname "$0")/mpi_solve_common.sh"
# solve SCENE SOLVER OUT [mpirun -np N]
solve() {
  s_scene=$1 s_solver=$2 s_out=$3
  shift 3
  "$@" "$layerlab" solve "$s_scene" --target "$work/lf" --solver "$s_solver" --iterations 4 --threads 1 --out "$s_out" \
    -q >"$work/log" 2>&1 || fail "$s_solver: the solve failed ($*)"
}
psnr() { python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["final_psnr_db"])' "$1/report.json"; }
for case in "$small hybrid" "$small joint" "$small quasi-newton" "$examples/multiplicative_2layer.json multiplicative" \
  "$examples/tensor_display_rank2.json multiplicative" "$examples/additive_2layer.json additive-trust-region"; do
  set -- $case
  scene=$1 solver=$2
  solver=$2$(basename "$scene" .json | sed -n 's/.*_rank\([0-9]\)$/_rank\1/p')  # the output folders' names
  solve "$scene" "${solver%_rank*}" "$work/one_$solver"
  solve "$scene" "${solver%_rank*}" "$work/n_$solver" mpi "$ranks"
  solve "$scene" "${solver%_rank*}" "$work/again_$solver" mpi "$ranks"
  a=$(psnr "$work/one_$solver") b=$(psnr "$work/n_$solver")
  python3 -c 'import sys; a, b = float(sys.argv[1]), float(sys.argv[2]); print("%s on %s ranks: PSNR %.17g dB, relative difference %.2g" % (sys.argv[3], sys.argv[4], b, abs(a - b) / abs(a)))' "$a" "$b" "$solver" "$ranks"
  python3 -c 'import sys; a, b = float(sys.argv[1]), float(sys.argv[2]); sys.exit(abs(a - b) > 1e-9 * abs(a))' "$a" "$b" ||
    fail "$solver: PSNR $b dB on $ranks ranks, $a dB in one process"
  grep -q "\"rays\": $(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["rays"])' "$work/one_$solver/report.json")" \
    "$work/n_$solver/report.json" || fail "$solver: the report does not count every rank's rays"
  for f in "$work/one_$solver"/patterns/*.exr; do
    name=$(basename "$f")
    d=$("$exr_difference" "$f" "$work/n_$solver/patterns/$name") || fail "$solver: cannot compare $name"
    echo "$solver on $ranks ranks: $name differs by $d of its largest value"
    python3 -c 'import sys; sys.exit(float(sys.argv[1]) > 1e-6)' "$d" ||
      fail "$solver: $name differs by $d (relative) on $ranks ranks"
    cmp -s "$work/n_$solver/patterns/$name" "$work/again_$solver/patterns/$name" ||
      fail "$solver: $name is not the same bits in two runs on $ranks ranks"
  done
done
solve "$small" hybrid "$work/mpi1" mpi 1
for f in "$work/one_hybrid"/patterns/*.exr; do
  cmp -s "$f" "$work/mpi1/patterns/$(basename "$f")" || fail "one rank under mpirun differs from one process: $(basename "$f")"
done
echo "PASS"
