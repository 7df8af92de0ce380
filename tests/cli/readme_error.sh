#!/usr/bin/env bash
# Issue 18: the README's example error message is the one the program prints.
# Takes from README.md the reduced scene (the ```json block), the misspelling
# ("misspelled `X`") and the printed line ("layerlab: error: ..."), makes the
# misspelled scene, runs the README's command and compares.
# Usage: readme_error.sh LAYERLAB README.md WORK_DIR
set -u
layerlab=$1 readme=$2 work=$3
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work"
scene=$(awk '/^```json$/{on=1; next} /^```$/{if (on) exit} on' "$readme")
[ -n "$scene" ] || fail "no \`\`\`json block in $readme"
expected=$(grep -m1 '^    layerlab: error: ' "$readme" | sed 's/^    //')
[ -n "$expected" ] || fail "no indented 'layerlab: error:' line in $readme"
# "its lens's `focal_length` misspelled `focal_lenght`" (the sentence may wrap).
words=$(tr '\n' ' ' <"$readme" | grep -o '`[a-z_]*` misspelled `[a-z_]*`' | head -1)
right=$(echo "$words" | sed 's/^`\([a-z_]*\)`.*/\1/') wrong=$(echo "$words" | sed 's/.*`\([a-z_]*\)`$/\1/')
[ -n "$right" ] && [ -n "$wrong" ] || fail "the README does not say which key is misspelled"
command=$(tr '\n' ' ' <"$readme" | grep -o '`layerlab info scene.json` prints' | head -1)
[ -n "$command" ] || fail "the README does not say which command prints the message"
printf '%s\n' "$scene" | sed "s/\"$right\"/\"$wrong\"/" >"$work/scene.json"
grep -q "\"$wrong\"" "$work/scene.json" || fail "the misspelling \"$wrong\" did not make it into the scene"
# The scene as written compiles (so the message is about the typo alone).
printf '%s\n' "$scene" >"$work/good.json"
(cd "$work" && "$layerlab" info good.json >/dev/null 2>&1) || fail "the README's scene does not compile as written"
(cd "$work" && "$layerlab" info scene.json >"$work/out" 2>"$work/err")
code=$?
[ "$code" -eq 1 ] || fail "exit status $code, the README says 1"
actual=$(cat "$work/err")
[ "$actual" = "$expected" ] || fail "the program prints
  $actual
the README shows
  $expected"
echo "PASS: $actual"
