#!/bin/sh
# layerlab sweep: a bad sweep file is refused with the file and the JSON
# pointer before anything is written; a good one expands into job folders
# (here with --slurm, which runs nothing) whose scenes the other commands
# read; the inputs are never modified.
. "$(dirname "$0")/sweep_common.sh"
sweep=$work/sweep.json
before=$(cat "$examples/small/hybrid_small.json" | cksum)

refused() {  # refused MESSAGE: the sweep is refused with MESSAGE and writes nothing
  if "$layerlab" sweep "$sweep" --out "$work/out" --slurm >"$work/log" 2>&1; then fail "accepted: $1"; fi
  grep -qF "$1" "$work/log" || fail "expected: $1"
  [ ! -e "$work/out" ] || fail "a refused sweep wrote $work/out"
}
write_sweep "$sweep" '["solve"]' '[{ "name": "pupil", "pointer": "/elements/0/pupil_size", "values": ["3 mm"] }]'
refused "$sweep: /parameters/0/pointer: \"/elements/0/pupil_size\" is not in the scene"
write_sweep "$sweep" '["solve"]' '[{ "name": "pupil", "pointer": "/elements/0/pupil_diameter", "values": [] }]'
refused "$sweep: /parameters/0/values: is empty"
write_sweep "$sweep" '["solve", "focus"]' "[$PUPILS]"
refused "$sweep: /work/1: unknown work \"focus\""

write_sweep "$sweep" '["solve"]' "[$PUPILS, $COMBINERS]"
cp "$sweep" "$work/sweep.copy"
"$layerlab" sweep "$sweep" --out "$work/out" --slurm >"$work/log" 2>&1 || fail "the sweep did not expand"
grep -q "sweep: 4 jobs in $work/out/jobs (4 scenes written)" "$work/log" || fail "no expansion line"
for id in 000 001 002 003; do
  [ -f "$work/out/jobs/$id/scene.json" ] || fail "no scene for job $id"
  "$layerlab" info "$work/out/jobs/$id/scene.json" >/dev/null 2>&1 || fail "job $id's scene does not load"
  [ "$(state "$work/out" $id)" = none ] || fail "--slurm ran job $id"
done
python3 - "$work/out" <<'PY' || fail "the job scenes do not hold the grid's values"
import json, sys
out = sys.argv[1]
m = json.load(open(out + "/manifest.json"))
assert [j["values"] for j in m["jobs"]] == [{"pupil": p, "combiner": c} for p in ("3 mm", "5 mm") for c in ("50/50", "30/70")], m
for j, (p, r) in zip(m["jobs"], [(p, r) for p in ("3 mm", "5 mm") for r in (0.5, 0.3)]):
    s = json.load(open(out + "/" + j["folder"] + "/scene.json"))
    assert s["elements"][0]["pupil_diameter"] == p and s["elements"][2]["reflectance"] == r, (j, s["elements"][2])
    assert abs(s["elements"][2]["transmittance"] - (1 - r)) < 1e-12
PY
[ "$(cat "$examples/small/hybrid_small.json" | cksum)" = "$before" ] || fail "the base scene changed"
cmp -s "$sweep" "$work/sweep.copy" || fail "the sweep file changed"
# Again: nothing changed, nothing written.
"$layerlab" sweep "$sweep" --out "$work/out" --slurm >"$work/log" 2>&1 || fail "the second expansion failed"
grep -q "(0 scenes written)" "$work/log" || fail "an unchanged sweep wrote its scenes again"
echo "PASS"
