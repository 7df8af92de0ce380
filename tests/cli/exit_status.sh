#!/usr/bin/env bash
# Issue 50: the exit status says what kind of failure (docs/cli.md): 0 done,
# 1 an input refused, 2 the command line itself, 130 interrupted
# (cli.solve_interrupted); usage errors carry the "layerlab: error:" prefix
# and name the command; the global options go before or after the command;
# a value that needs no data is refused before any data is read.
# Usage: exit_status.sh LAYERLAB EXAMPLES_DIR WORK_DIR
source "$(dirname "$0")/common.sh"
rm -rf "$work" && mkdir -p "$work"
small="$examples/small/hybrid_small.json"
# status EXPECTED STDERR_PATTERN COMMAND...
status() {
  local expected=$1 pattern=$2
  shift 2
  "$layerlab" "$@" >"$work/out" 2>"$work/log"
  local got=$?
  [ "$got" -eq "$expected" ] || fail "layerlab $* exited $got, expected $expected: $(head -c 400 "$work/log")"
  [ -z "$pattern" ] || grep -q -E -- "$pattern" "$work/log" || fail "layerlab $*: no \"$pattern\" in: $(cat "$work/log")"
  echo "exit $got: layerlab $*"
}
status 0 "" help
status 0 "" help solve
status 0 "" --version
status 0 "" solve --help
status 0 "" --quiet info "$small"
status 0 "" info "$small" --quiet
status 0 "" -v info "$small"
grep -q "^Usage: layerlab \[OPTIONS\] SUBCOMMAND" <("$layerlab" help) || fail "layerlab help does not give the usage of layerlab (named so, not by its path)"

status 2 '^layerlab: error: unknown command "frobnicate"' frobnicate
status 2 '^layerlab: error: unknown command "sovle"; did you mean "solve"' -q --json sovle
status 2 '^layerlab: error: help: unknown command "retna"; did you mean "retina"' help retna
status 2 '^layerlab: error: solve: The following argument was not expected: --no-such-option' \
  solve "$small" --no-such-option --out "$work/o"
status 2 '^layerlab: error: solve: --out is required \(layerlab help solve\)' solve "$small"
status 2 '^layerlab: error: A subcommand is required \(layerlab help\)' --quiet
status 2 '^layerlab: error: .*--quiet and --verbose exclude each other' -q info "$small" -v
status 2 '^layerlab: error: contrast: --retina-field is now --field' contrast "$small" --retina-field 5 --out "$work/o"
status 2 '^layerlab: error: solve: --initial is now --initial-value' solve "$small" --initial 0.3 --out "$work/o"
status 2 '^layerlab: error: render-target: the output folder is given as --out' \
  render-target "$examples/small/small_dice_target.json" "$work/lf"

status 1 '^layerlab: error: .*no_such_scene.json' info "$examples/no_such_scene.json"
# A value the parser's own check refuses is a refused input too.
status 1 '^layerlab: error: sweep: --jobs: Value -1 not in range' sweep "$work/none.json" --jobs -1 --out "$work/o"
status 1 '^layerlab: error: solve: Could not convert: --iterations = many' solve "$small" --iterations many --out "$work/o"
# Checked before the target is read: a target that does not exist is never reached.
status 1 '^layerlab: error: --iterations: 0: must be in \[1, 1000000\]' \
  solve "$small" --iterations 0 --target "$work/no_such_target" --out "$work/o"
[ ! -e "$work/o" ] || fail "a refused solve left $work/o"
# One wording for the same range in every command that takes it.
for command in compare tolerance; do
  status 1 '^layerlab: error: --iterations: 0: must be in \[1, 1000000\]' \
    $command "$small" --iterations 0 --target "$work/no_such_target" --out "$work/o"
done
status 1 '^layerlab: error: --iterations: 0: must be in \[1, 1000000\]' run "$small" --iterations 0 --out "$work/o"
status 1 '^layerlab: error: --accommodation: "0,2.6,0.1": the sweep takes a range FROM:TO:STEP' \
  contrast "$small" --accommodation 0,2.6,0.1 --out "$work/o"
status 1 '^layerlab: error: --focal-stack: "0,2.6,0.1": give a range FROM:TO:STEP' \
  retina "$small" --patterns "$work/none" --focal-stack 0,2.6,0.1 --out "$work/o"
echo "PASS"
