#!/usr/bin/env bash
# Checks that the C++ files git tracks (or those given) are laid out as
# .clang-format says; lists those that are not and exits 1. Changes nothing:
# `clang-format-14 -i FILE` applies the layout.
# Usage: scripts/check_format.sh [FILE...]
set -euo pipefail
cd "$(dirname "$0")/.."
format=$(command -v clang-format-14 || command -v clang-format || true)
if [ -z "$format" ]; then
  echo "check_format: clang-format (14) is not installed" >&2
  exit 2
fi
if [ $# -gt 0 ]; then files=("$@"); else mapfile -t files < <(git ls-files '*.cpp' '*.h'); fi
unformatted=()
for f in "${files[@]}"; do
  "$format" --dry-run -Werror "$f" >/dev/null 2>&1 || unformatted+=("$f")
done
if [ ${#unformatted[@]} -gt 0 ]; then
  printf 'check_format: %d of %d files differ from .clang-format:\n' "${#unformatted[@]}" "${#files[@]}" >&2
  printf '  %s\n' "${unformatted[@]}" >&2
  exit 1
fi
echo "check_format: ${#files[@]} files as .clang-format says"
