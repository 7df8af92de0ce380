#!/bin/sh
# layerlab optimize with a multistart: the starts run one after another, in a
# process pool (--local -j 2), as MPI ranks (--mpi, when $4 names mpirun) and
# as the tasks of a Slurm array run by hand in another order (--slurm, then
# its gather step); every runner gives the same designs in the same order,
# the same best design and the same metrics (to 1e-6). A runner flag on a design without a
# multistart is refused naming /optimizer/global.
# Expects: $1 LAYERLAB, $2 EXAMPLES_DIR, $3 WORK_DIR, [$4 MPIEXEC].
. "$(dirname "$0")/common.sh"
mpiexec=${4:-}
rm -rf "$work" && mkdir -p "$work"
design=$work/design.json
python3 - "$examples/optimize/one_layer_depth.json" "$design" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d["scene"] = sys.argv[1].rsplit("/", 1)[0] + "/" + d["scene"]
d["optimizer"] = {"global": "multistart", "starts": 3, "evaluations": 30}  # --evaluations 12 below
json.dump(d, open(sys.argv[2], "w"))
PY
"$layerlab" optimize "$design" --out "$work/seq" --evaluations 12 --json >"$work/seq.json" 2>"$work/log" || fail "the starts one after another"
grep -q "each of its 3 starts ended (one after another)" "$work/seq.json" || fail "the sequential run's summary"
grep -q '"ran": 12,' "$work/seq.json" && grep -q '"replayed": 0,' "$work/seq.json" || fail "the sequential run's counts"
[ -f "$work/seq/starts/s02/evaluations.jsonl" ] || fail "no log of start s02"
"$layerlab" optimize "$design" --out "$work/local" --local -j 2 --evaluations 12 --json >"$work/local.json" 2>"$work/log" ||
  fail "the process pool"
grep -q "each of its 3 starts ended (2 at a time)" "$work/local.json" || fail "the pool's summary"
runs="seq local"
if [ -n "$mpiexec" ]; then
  "$mpiexec" --oversubscribe --allow-run-as-root -np 2 "$layerlab" optimize "$design" --out "$work/mpi" --mpi \
    --evaluations 12 >"$work/log" 2>&1 || fail "the MPI run"
  grep -q "rank 1: start s01" "$work/log" || fail "start s01 did not run on rank 1"
  "$mpiexec" --oversubscribe --allow-run-as-root -np 2 "$layerlab" optimize "$design" --out "$work/mpi" --mpi \
    --evaluations 12 --json >"$work/mpi.json" 2>"$work/log" || fail "the MPI run again"
  grep -q '"ran": 0,' "$work/mpi.json" && grep -q '"replayed": 12,' "$work/mpi.json" || fail "the MPI run again ran evaluations"
  runs="$runs mpi"
fi
"$layerlab" optimize "$design" --out "$work/slurm" --slurm --evaluations 12 >"$work/log" 2>&1 || fail "--slurm"
array=$work/slurm/slurm/array.sbatch
grep -q "^#SBATCH --array=0-2$" "$array" || fail "the array does not cover starts 0 to 2"
grep -q -- "'--evaluations' '12' --start \"\$SLURM_ARRAY_TASK_ID\"" "$array" || fail "the task does not select its start"
for task in 2 0; do
  SLURM_ARRAY_TASK_ID=$task "$array" >"$work/log" 2>&1 || fail "task $task"
done
"$work/slurm/slurm/gather.sbatch" >"$work/log" 2>&1 || fail "the gather step with a start not run"
grep -q "the starts s01 have no evaluations yet" "$work/log" || fail "the gather step did not name the start not run"
SLURM_ARRAY_TASK_ID=1 "$array" >"$work/log" 2>&1 || fail "task 1"
"$work/slurm/slurm/gather.sbatch" >"$work/log" 2>&1 || fail "the gather step"
runs="$runs slurm"
python3 - "$work" $runs <<'PY' || fail "the runners' results differ"
import csv, json, sys
work, runs = sys.argv[1], sys.argv[2:]
def history(run):
    rows = list(csv.reader(open("%s/%s/history.csv" % (work, run))))
    return rows[0], rows[1:]
head, base = history("seq")
assert head[:4] == ["evaluation", "job", "start", "depth (D)"], head
assert {r[2] for r in base} == {"s00", "s01", "s02"}, base
assert len(base) == 12, len(base)
# The same designs in the same order, from the same warm starts; the same metrics to 1e-6: a solve's
# threads follow the machine's load (framework/thread_budget.h), so its float sums may differ in the last bits.
exact = [head.index(c) for c in ["evaluation", "job", "start", "depth (D)", "state", "warm start from"]]
metric = head.index("psnr (dB)")
for run in runs[1:]:
    h, rows = history(run)
    assert h == head and len(rows) == len(base), (run, h, len(rows))
    for a, b in zip(rows, base):
        assert [a[i] for i in exact] == [b[i] for i in exact], (run, a, b)
        assert abs(float(a[metric]) - float(b[metric])) <= 1e-6 * abs(float(b[metric])), (run, a, b)
    best = json.load(open("%s/%s/best_scene.json" % (work, run)))
    assert best == json.load(open(work + "/seq/best_scene.json")), run
best = json.load(open(work + "/seq.json"))["best"]["depth (D)"]
assert abs(best - 1.3) < 0.05, best
PY
# A runner flag needs a multistart.
"$layerlab" optimize "$examples/optimize/one_layer_depth.json" --out "$work/single" --local >"$work/log" 2>&1 &&
  fail "--local without a multistart ran"
grep -q 'one_layer_depth.json: /optimizer/global: --local runs the starts of a multistart' "$work/log" ||
  fail "--local without a multistart: the message"
[ ! -e "$work/single" ] || fail "a refused run wrote its folder"
echo PASS
