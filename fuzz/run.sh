#!/usr/bin/env bash
# Replays every fuzz target's seed corpus, then fuzzes each target from a fresh
# copy of that corpus, for a time or for a number of executions. Exits non-zero
# on any finding (crash, sanitizer report, uncaught exception, leak, timeout,
# out of memory); the input that caused it is kept in BUILD_DIR/fuzz-findings/<target>/.
# Usage: fuzz/run.sh BUILD_DIR [SECONDS | --runs N] [--seed K]
#   (BUILD_DIR configured with -DLAYERLAB_FUZZ=ON; SECONDS defaults to 20.)
# With --runs and --seed the run is reproducible: the same inputs in the same
# order on every machine (CI runs this way, so a red CI is never a lucky draw).
set -uo pipefail
usage() { echo "usage: $0 BUILD_DIR [SECONDS | --runs N] [--seed K]" >&2; exit 2; }
[ $# -ge 1 ] || usage
build=$(cd "$1" && pwd) || exit 2
shift
seconds=20 runs="" seed=""
while [ $# -gt 0 ]; do
  case "$1" in
    --runs) [ $# -ge 2 ] && [[ "$2" =~ ^[1-9][0-9]*$ ]] || usage; runs=$2; shift 2 ;;
    --seed) [ $# -ge 2 ] && [[ "$2" =~ ^[1-9][0-9]*$ ]] || usage; seed=$2; shift 2 ;;
    *) [[ "$1" =~ ^[1-9][0-9]*$ ]] || usage; seconds=$1; shift ;;
  esac
done
budget=(-max_total_time="$seconds")
[ -n "$runs" ] && budget=(-runs="$runs")
[ -n "$seed" ] && budget+=(-seed="$seed")
corpora=$(cd "$(dirname "$0")/corpus" && pwd)
findings="$build/fuzz-findings"
scratch=$(mktemp -d "${TMPDIR:-/tmp}/layerlab-fuzz-run.XXXXXX")
trap 'rm -rf "$scratch"' EXIT

export ASAN_OPTIONS="${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"

targets=()
for exe in "$build"/fuzz/*_fuzz; do
  [ -x "$exe" ] && targets+=("$exe")
done
if [ ${#targets[@]} -eq 0 ]; then
  echo "run.sh: no fuzz targets in $build/fuzz (build them: cmake --build $1 --target fuzzers)" >&2
  exit 2
fi

failed=()
summary=()
for exe in "${targets[@]}"; do
  target=$(basename "$exe")
  name=${target%_fuzz}
  seeds="$corpora/$name"
  log="$scratch/$target.log"
  mkdir -p "$findings/$target"
  if [ ! -d "$seeds" ]; then
    echo "run.sh: $target has no seed corpus ($seeds)" >&2
    failed+=("$target"); continue
  fi
  # 1. Replay: every seed once.
  if ! "$exe" "$seeds" -runs=0 -timeout=25 -artifact_prefix="$findings/$target/" >"$log" 2>&1; then
    cat "$log" >&2
    echo "run.sh: $target: FINDING while replaying $seeds" >&2
    failed+=("$target"); continue
  fi
  replayed=$(find "$seeds" -type f | wc -l)
  # 2. Fuzz: new inputs go to a fresh temporary corpus seeded from the repository's.
  work="$scratch/$name"
  mkdir -p "$work"
  cp -r "$seeds/." "$work/"
  start=$(date +%s)
  "$exe" "$work" "${budget[@]}" -timeout=25 -rss_limit_mb=2048 -print_final_stats=1 \
         -artifact_prefix="$findings/$target/" >"$log" 2>&1
  status=$?
  elapsed=$(( $(date +%s) - start ))
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  corpus_size=$(find "$work" -type f | wc -l)
  if [ $status -ne 0 ]; then
    tail -n 60 "$log" >&2
    echo "run.sh: $target: FINDING after ${elapsed}s (inputs in $findings/$target/)" >&2
    failed+=("$target")
    summary+=("$(printf '%-28s FINDING  replayed %3d seeds, %10s executions in %4ds' "$target" "$replayed" "${execs:-?}" "$elapsed")")
  else
    summary+=("$(printf '%-28s ok       replayed %3d seeds, %10s executions in %4ds (%.0f/s), corpus %d -> %d' \
                 "$target" "$replayed" "${execs:-?}" "$elapsed" "$(( ${execs:-0} / (elapsed > 0 ? elapsed : 1) ))" \
                 "$replayed" "$corpus_size")")
  fi
done

printf '%s\n' "${summary[@]}"
if [ ${#failed[@]} -gt 0 ]; then
  echo "run.sh: findings in: ${failed[*]}" >&2
  exit 1
fi
