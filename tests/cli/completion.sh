#!/usr/bin/env bash
# Issue 50: the bash completion, the zsh completion and the man page the build
# writes from the parser's own tree (app/cli_catalogue.h): the completion
# offers commands, a command's options and an option's choices; the zsh
# script parses; the man page names every command and the exit statuses.
# Usage: completion.sh LAYERLAB BUILD_DIR WORK_DIR
source "$(dirname "$0")/common.sh"
build=$2
rm -rf "$work" && mkdir -p "$work"
for f in layerlab.bash _layerlab layerlab.1; do
  [ -s "$build/share/$f" ] || fail "the build did not write share/$f"
done
"$layerlab" help --completion bash | cmp -s - "$build/share/layerlab.bash" || fail "share/layerlab.bash is stale"
# complete WORDS... : what the completion offers for the last word
complete_words() {
  bash -c 'source "$1"; shift; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _layerlab; printf "%s\n" "${COMPREPLY[@]}"' \
    complete "$build/share/layerlab.bash" "$@"
}
offers() {
  local want=$1
  shift
  complete_words "$@" | grep -q -x -- "$want" || fail "completing \"$*\" does not offer $want: $(complete_words "$@" | head -5)"
}
offers solve layerlab so
offers render-target layerlab ren
offers solve layerlab -q so
offers --solver layerlab solve scene.json --sol
offers --json layerlab solve scene.json --js
offers wave layerlab contrast scene.json --diffraction w
offers retina layerlab help ret
complete_words layerlab solve scene.json --solv | grep -q -x -- "--out" && fail "--solv offers --out"
bash -n "$build/share/layerlab.bash" || fail "layerlab.bash does not parse"
if command -v zsh >/dev/null; then
  zsh -n "$build/share/_layerlab" || fail "_layerlab does not parse"
else
  echo "zsh not installed: the zsh script's syntax is not checked"
fi
man_page="$build/share/layerlab.1"
grep -q '^\.TH LAYERLAB 1' "$man_page" || fail "no .TH"
for command in $("$layerlab" help --json | /usr/bin/python3 -c 'import json,sys; print(" ".join(c["name"] for c in json.load(sys.stdin)["commands"][1:]))'); do
  grep -q -F ".SS \"${command//-/\\-}\"" "$man_page" || fail "the man page lacks $command"
done
for status in 0 1 2 3 130; do
  grep -q -x "\.B $status" "$man_page" || fail "the man page does not explain exit status $status"
done
if command -v groff >/dev/null; then
  groff -man -Tutf8 -ww "$man_page" 2>"$work/groff.err" >/dev/null
  [ ! -s "$work/groff.err" ] || fail "groff warns: $(head -3 "$work/groff.err")"
fi
echo "PASS"
