# Sourced by the sweep tests (tests/cli/sweep_*.sh): a sweep of the reduced
# example (examples/small/hybrid_small.json), two iterations per solve, so
# that each job takes about a second. Expects: $1 LAYERLAB, $2 EXAMPLES_DIR, $3 WORK_DIR.
. "$(dirname "$0")/common.sh"
rm -rf "$work" && mkdir -p "$work"
# write_sweep FILE WORK PARAMETERS [ITERATIONS]: WORK and PARAMETERS as JSON.
write_sweep() {
  cat >"$1" <<JSON
{ "format": "layerlab-sweep/1", "name": "test sweep", "scene": "$examples/small/hybrid_small.json",
  "iterations": ${4:-2}, "work": $2, "parameters": $3 }
JSON
}
PUPILS='{ "name": "pupil", "pointer": "/elements/0/pupil_diameter", "values": ["3 mm", "5 mm"] }'
COMBINERS='{ "name": "combiner", "pointers": ["/elements/2/reflectance", "/elements/2/transmittance"],
             "values": [[0.5, 0.5], [0.3, 0.7]], "labels": ["50/50", "30/70"] }'
# state DIR ID: the job's recorded state, or "none".
state() {
  python3 -c 'import json,sys
try: print(json.load(open(sys.argv[1]))["state"])
except FileNotFoundError: print("none")' "$1/jobs/$2/job.json"
}
# field DIR ID KEY
field() { python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])' "$1/jobs/$2/job.json" "$3"; }
