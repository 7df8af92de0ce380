#!/usr/bin/env bash
# Runs docs/tutorial.md: writes each ```json file=NAME block into a fresh
# folder WORK/my-display (beside a link WORK/examples to the repository's),
# runs each "$ " line of the ```console blocks there with layerlab on PATH,
# fails on a non-zero exit, and checks that every output line the tutorial
# shows appears in what the command printed (stdout and stderr): "..." in a
# line stands for anything, a run of spaces for any run of spaces, and a line
# of "..." alone for output left out.
# Usage: tutorial.sh LAYERLAB_BINARY REPOSITORY TUTORIAL.md WORK
set -euo pipefail
layerlab=$(realpath "$1") repo=$(realpath "$2") tutorial=$(realpath "$3") work=$4
rm -rf "$work"
mkdir -p "$work/my-display"
ln -s "$repo/examples" "$work/examples"
export PATH="$(dirname "$layerlab"):$PATH"
cd "$work/my-display"

files=0 commands=0 checked=0
command="" expected=()

# A shown line as an extended regular expression.
pattern() {
  printf '%s' "$1" | sed -e 's/[][\.*^$+?(){}|/]/\\&/g' -e 's/\\\.\\\.\\\./.*/g' -e 's/  */[[:space:]]+/g'
}

run() {  # the pending command and its shown output
  local shown
  [ -n "$command" ] || return 0
  commands=$((commands + 1))
  local rc=0
  bash -c "$command" </dev/null >output.txt 2>&1 || rc=$?
  if [ "$rc" -ne 0 ]; then
    echo "tutorial: \`$command\` failed (exit $rc); it printed:" >&2
    cat output.txt >&2
    exit 1
  fi
  for shown in "${expected[@]}"; do
    if [ -z "${shown// /}" ] || [ "$shown" = "..." ]; then continue; fi
    if ! grep -Eq -- "$(pattern "$shown")" output.txt; then
      echo "tutorial: \`$command\` did not print the line docs/tutorial.md shows:" >&2
      echo "  $shown" >&2
      echo "it printed:" >&2
      cat output.txt >&2
      exit 1
    fi
    checked=$((checked + 1))
  done
  command="" expected=()
}

state=text file=""
while IFS= read -r line || [ -n "$line" ]; do
  case $state in
    text)
      if [[ $line =~ ^\`\`\`json\ file=([^ ]+)$ ]]; then
        file=${BASH_REMATCH[1]} state=file
        : >"$file"
        files=$((files + 1))
      elif [[ $line == '```console' ]]; then
        state=console
      fi
      ;;
    file)
      if [[ $line == '```' ]]; then state=text; else printf '%s\n' "$line" >>"$file"; fi
      ;;
    console)
      if [[ $line == '```' ]]; then
        run
        state=text
      elif [[ $line == '$ '* ]]; then
        run
        command=${line#\$ }
      else
        expected+=("$line")
      fi
      ;;
  esac
done <"$tutorial"
[ "$state" = text ] || { echo "tutorial: $tutorial ends inside a code block" >&2; exit 1; }
[ "$commands" -gt 0 ] || { echo "tutorial: no commands found in $tutorial" >&2; exit 1; }
rm -f output.txt
echo "tutorial: wrote $files files, ran $commands commands, found $checked shown lines in their output"
