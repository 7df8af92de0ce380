#!/bin/sh
# layerlab sweep --slurm never runs text of the user's as a command: names
# and paths holding newlines, $(...), backticks, quotes, ;, #, % and spaces
# are either refused, naming the field, before anything is written, or
# carried as data. The generated submit.sh runs with a stub sbatch
# (tests/cli/sbatch_stub.py: parses the #SBATCH lines as sbatch does, runs
# the array's first and last task and the gather step) and a stub srun on
# PATH; array.sbatch and gather.sbatch run by hand too. No marker file of an
# injected command may appear, and the directives must be exactly those asked.
. "$(dirname "$0")/sweep_common.sh"
stubs=$work/bin && mkdir -p "$stubs" "$work/run"
ln -s "$(cd "$(dirname "$0")" && pwd)/sbatch_stub.py" "$stubs/sbatch"
printf '#!/bin/sh\ntouch "%s/srun-was-called"\n' "$work" >"$stubs/srun" && chmod +x "$stubs/srun"
export SBATCH_STUB_LOG=$work/sbatch.log
nl='
'
# sweep FILE NAME_JSON [EXTRA_JSON]: two jobs of the reduced example; NAME_JSON "" leaves "name" out.
sweep() {
  name=${2:+\"name\": $2,}
  cat >"$1" <<JSON
{ "format": "layerlab-sweep/1", $name "scene": "$examples/small/hybrid_small.json",
  "iterations": 2, "work": ["solve"], "parameters": [$PUPILS] ${3:+, $3} }
JSON
}
no_markers() {
  found=$(find "$work" -name 'MARK*' -o -name srun-was-called)
  [ -z "$found" ] || fail "$1: an injected command ran: $found"
}
# refused LABEL FIELD OUT COMMAND...: non-zero, names FIELD, writes nothing into OUT, runs nothing.
refused() {
  label=$1 field=$2 out=$3
  shift 3
  if (cd "$work/run" && "$@") >"$work/log" 2>&1; then fail "$label: accepted"; fi
  grep -q "internal error" "$work/log" && fail "$label: internal error"
  grep -qF -- "$field" "$work/log" || fail "$label: the error does not name $field: $(cat "$work/log")"
  [ -e "$out/manifest.json" ] || [ -e "$out/slurm" ] && fail "$label: wrote into $out"
  no_markers "$label"
}

# 1. Hostile but carried as data: the folders, the sweep file and the executable's path.
dir="$work/a dir;\$(touch MARK1)\`touch MARK2\`'q'\"dq\"#h %a&|<>*?"
mkdir -p "$dir/bin \$(touch MARK3)"
ln "$layerlab" "$dir/bin \$(touch MARK3)/layerlab" 2>/dev/null || cp "$layerlab" "$dir/bin \$(touch MARK3)/layerlab"
exe="$dir/bin \$(touch MARK3)/layerlab"
file="$dir/s \$(touch MARK4); \`touch MARK5\` #.json"
out="$dir/out \$(touch MARK6) 'x' \"y\" ;z #w %j"
sweep "$file" '"ok name-1.0+x"' '"slurm": { "time": "10", "mem": "2G", "partition": "gpu,cpu", "account": "proj_1" }'
(cd "$work/run" && "$exe" sweep "$file" --out "$out" --slurm --slurm-time 1:00:00 --slurm-cpus-per-task 3) \
  >"$work/log" 2>&1 || fail "the hostile but valid paths were refused"
no_markers "writing the scripts"
(cd "$work/run" && PATH="$stubs:$PATH" sh "$out/slurm/submit.sh") >"$work/log" 2>&1 || fail "submit.sh failed"
no_markers "submit.sh"
/usr/bin/python3 - "$SBATCH_STUB_LOG" "$out" "$examples" >"$work/check" 2>&1 <<'PY' || fail "the submissions: $(cat "$work/check")"
import json, sys
log, out = sys.argv[1], sys.argv[2]
subs = [json.loads(l) for l in open(log)]
assert len(subs) == 2, subs
logs = out.replace("%", "%%") + "/slurm/logs"
want = ["--job-name=ok name-1.0+x", "--array=0-1", "--ntasks=1", "--cpus-per-task=3", "--time=1:00:00",
        "--mem=2G", "--partition=gpu,cpu", "--account=proj_1", "--output=" + logs + "/job-%a.out"]
assert subs[0]["argv"] == ["--parsable", out + "/slurm/array.sbatch"], subs[0]["argv"]
assert subs[0]["directives"] == want, (subs[0]["directives"], want)
assert subs[0]["runs"] == [{"task": "0", "exit": 0}, {"task": "1", "exit": 0}], subs[0]["runs"]
assert subs[1]["argv"] == ["--dependency=afterany:4242", out + "/slurm/gather.sbatch"], subs[1]["argv"]
assert subs[1]["directives"] == ["--job-name=ok name-1.0+x-gather", "--ntasks=1", "--time=1:00:00", "--mem=2G",
                                 "--partition=gpu,cpu", "--account=proj_1", "--output=" + logs + "/gather.out"], subs[1]
assert subs[1]["runs"] == [{"task": None, "exit": 0}], subs[1]["runs"]
PY
[ "$(state "$out" 000)" = complete ] && [ "$(state "$out" 001)" = complete ] || fail "the stub's tasks did not run the jobs"
grep -q "^001,5,complete,slurm task 1," "$out/table.csv" || fail "the gather step's table: $(cat "$out/table.csv")"
(cd "$work/run" && SLURM_ARRAY_TASK_ID=1 "$out/slurm/array.sbatch") >"$work/log" 2>&1 || fail "array.sbatch by hand"
grep -q "already complete" "$work/log" || fail "array.sbatch by hand did not find job 001 complete"
(cd "$work/run" && "$out/slurm/gather.sbatch") >"$work/log" 2>&1 || fail "gather.sbatch by hand"
no_markers "the scripts by hand"
grep -q "MARK" "$out/slurm/array.sbatch" || fail "the paths are not in the script at all"
cat "$out/slurm/array.sbatch" "$out/slurm/gather.sbatch" "$out/slurm/submit.sh" | grep "^#" | grep -v "^#SBATCH" |
  grep -q "MARK" && fail "a comment carries a path: $(grep -n '^#' "$out/slurm/array.sbatch")"

# 2. Refused, naming the field, before anything is written.
good="$work/good.json"
sweep "$good" '"fine"'
o="$work/refused"
for bad in '"x\n#SBATCH --wrap=\"touch MARK10\"\ntouch MARK11"' '"$(touch MARK12)"' '"`touch MARK13`"' \
           '"a; touch MARK14"' "\"it's\"" '"a # b"' '"a\"b"' '"hetjob"' '""'; do
  sweep "$work/bad.json" "$bad"
  refused "name $bad" "bad.json: /name:" "$o" "$layerlab" sweep "$work/bad.json" --out "$o" --slurm
done
stem="$work/\$(touch MARK15) x.json"
sweep "$stem" ""
refused "a hostile file stem as the name" "/name:" "$o" "$layerlab" sweep "$stem" --out "$o" --slurm
grep -q "stem" "$work/log" || fail "the refusal of a stem does not say the name is the stem"
nlfile="$work/new${nl}line \$(touch MARK16).json"
sweep "$nlfile" '"fine"'
refused "a newline in the sweep file's path" "SWEEP (the sweep file's path)" "$o" "$layerlab" sweep "$nlfile" --out "$o" --slurm
refused "a newline in --out" "--out:" "$work/o${nl}#SBATCH --x" "$layerlab" sweep "$good" --out "$work/o${nl}#SBATCH --x" --slurm
refused "a carriage return in --out" "--out:" "$work/o$(printf '\r')" "$layerlab" sweep "$good" --out "$work/o$(printf '\r')" --slurm
refused "a backslash in --out" "--out:" "$work/o\\a" "$layerlab" sweep "$good" --out "$work/o\\a" --slurm
refused "hetjob in --out" "--out:" "$work/HetJob" "$layerlab" sweep "$good" --out "$work/HetJob" --slurm
for t in "1:00:00${nl}#SBATCH --wrap=touch" '1h' '$(touch MARK17)' '1:00:00 #x' '-1' ''; do
  refused "--slurm-time $t" "--slurm-time" "$o" "$layerlab" sweep "$good" --out "$o" --slurm --slurm-time "$t"
done
refused "--slurm-mem" "--slurm-mem" "$o" "$layerlab" sweep "$good" --out "$o" --slurm --slurm-mem '4 GB'
refused "--slurm-partition" "--slurm-partition" "$o" "$layerlab" sweep "$good" --out "$o" --slurm --slurm-partition 'gpu;touch MARK18'
refused "--slurm-account" "--slurm-account" "$o" "$layerlab" sweep "$good" --out "$o" --slurm --slurm-account 'a"b'
refused "--slurm-cpus-per-task 0" "--slurm-cpus-per-task" "$o" "$layerlab" sweep "$good" --out "$o" --slurm --slurm-cpus-per-task 0
refused "--slurm-time without --slurm" "--slurm" "$o" "$layerlab" sweep "$good" --out "$o" --slurm-time 10
for kv in '"time": "10 min"' '"mem": "4G; touch MARK19"' '"partition": "a b"' '"account": "$(touch MARK20)"' \
          '"cpus-per-task": 0' '"cpus-per-task": "4"' '"nodes": 2' '"time": 10'; do
  key=$(echo "$kv" | sed 's/^"\([^"]*\)".*/\1/')
  sweep "$work/bad.json" '"fine"' "\"slurm\": { $kv }"
  refused "slurm $kv" "bad.json: /slurm/$key:" "$o" "$layerlab" sweep "$work/bad.json" --out "$o" --slurm
done
sweep "$work/bad.json" '"fine"' '"slurm": "gpu"'
refused "slurm not an object" "bad.json: /slurm:" "$o" "$layerlab" sweep "$work/bad.json" --out "$o" --slurm
[ ! -e "$o" ] || [ -z "$(ls -A "$o")" ] || fail "a refused sweep wrote into $o: $(ls -A "$o")"

# 3. The command line overrides the file; cpus-per-task defaults to the sweep's threads.
sweep "$work/res.json" '"fine"' '"threads": 2, "slurm": { "time": "10", "partition": "a" }'
"$layerlab" sweep "$work/res.json" --out "$work/res" --slurm --slurm-partition b >"$work/log" 2>&1 || fail "the resources"
grep -q '^#SBATCH --time=10$' "$work/res/slurm/array.sbatch" || fail "the file's time is not asked"
grep -q '^#SBATCH --partition=b$' "$work/res/slurm/array.sbatch" || fail "--slurm-partition does not override the file"
grep -q '^#SBATCH --cpus-per-task=2$' "$work/res/slurm/array.sbatch" || fail "cpus-per-task is not the threads"
no_markers "the end"
echo "PASS"
