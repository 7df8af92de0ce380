#!/bin/sh
# layerlab optimize: a run killed (kill -9) part way leaves its finished
# evaluations logged; the same command again answers them from the log, runs
# none of them twice, and ends where an uninterrupted run ends. A design
# whose constraints exclude every design is refused before anything runs.
. "$(dirname "$0")/common.sh"
rm -rf "$work" && mkdir -p "$work"
design=$examples/optimize/one_layer_depth.json out=$work/out
setsid "$layerlab" optimize "$design" --out "$out" >"$work/log" 2>&1 &
pid=$!
i=0
until [ -f "$out/evaluations.jsonl" ] && [ "$(wc -l <"$out/evaluations.jsonl")" -ge 3 ]; do
  i=$((i + 1)); [ $i -lt 3000 ] || { kill -KILL -$pid; fail "three evaluations did not finish in 60 s"; }
  sleep 0.02
done
kill -KILL -$pid 2>/dev/null; wait $pid 2>/dev/null
logged=$(wc -l <"$out/evaluations.jsonl")
[ ! -e "$out/history.csv" ] || fail "a killed optimization wrote its history"
"$layerlab" optimize "$design" --out "$out" --json >"$work/resumed.json" 2>"$work/log" || fail "the resumed optimization failed"
grep -q "optimize: [0-9]* evaluations in .*evaluations.jsonl from an earlier run; they are not repeated" "$work/log" ||
  fail "the resumed run did not read the log"
"$layerlab" optimize "$design" --out "$work/whole" --json >"$work/whole.json" 2>/dev/null || fail "the uninterrupted optimization failed"
python3 - "$work" "$logged" <<'PY' || fail "the resumed run differs from an uninterrupted one"
import json, sys
work, logged = sys.argv[1], int(sys.argv[2])
resumed, whole = json.load(open(work + "/resumed.json")), json.load(open(work + "/whole.json"))
xs = [json.loads(l)["x"] for l in open(work + "/out/evaluations.jsonl")]
assert len(xs) == len({tuple(x) for x in xs}), "a design was evaluated twice: %s" % xs
assert resumed["replayed"] >= logged - 1, (resumed["replayed"], logged)  # the line being written at the kill may be lost
assert resumed["ran"] + resumed["replayed"] == whole["ran"], (resumed, whole)
assert resumed["best"] == whole["best"], (resumed["best"], whole["best"])
hist = lambda d: [l.split(",")[2] for l in open(work + d + "/history.csv")][1:]
assert hist("/out") == hist("/whole"), "the histories' designs differ"
PY
# A constraint no design within the bounds meets: refused, named, nothing written.
python3 - "$design" "$work/infeasible.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d["scene"] = sys.argv[1].rsplit("/", 1)[0] + "/" + d["scene"]
d["constraints"] = [{"name": "near enough", "terms": {"depth": 1}, "min": "3 D"}]
json.dump(d, open(sys.argv[2], "w"))
PY
"$layerlab" optimize "$work/infeasible.json" --out "$work/infeasible" >"$work/log" 2>&1 && fail "an infeasible design was accepted"
grep -q 'infeasible.json: /constraints/0: no design meets "near enough": depth (D) must be at least 3 D, but within the variables. bounds it is at most 2.4 D' "$work/log" ||
  fail "the infeasible design's message"
[ ! -e "$work/infeasible" ] || fail "an infeasible design wrote its folder"
echo PASS
