#!/usr/bin/env bash
# Every docs/*.md that the sources, tests and documents cite exists (issue 18:
# docs/lightfield-format.md was cited and absent).
# Usage: doc_citations.sh SOURCE_DIR
set -u
cd "$1" || exit 1
missing=0 cited=0
while read -r doc; do
  cited=$((cited + 1))
  [ -f "$doc" ] || { echo "FAIL: $doc is cited but absent:"; grep -rln --exclude-dir=build --exclude-dir=out --exclude-dir=.git "$doc" . | head -3; missing=1; }
done < <(grep -rhoE --exclude-dir=build --exclude-dir=out --exclude-dir=.git 'docs/[A-Za-z0-9_.-]+\.md' . | sort -u)
# Bare names beside other docs ("(lightfield-format.md)" inside docs/) count too.
while read -r doc; do
  cited=$((cited + 1))
  [ -f "docs/$doc" ] || { echo "FAIL: docs/$doc is cited (as $doc) in docs/ but absent"; missing=1; }
done < <(grep -hoE '\(`?[A-Za-z0-9_-]+\.md`?\)' docs/*.md | tr -d '()`' | sort -u)
[ "$cited" -ge 5 ] || { echo "FAIL: only $cited citations found; the search is broken"; exit 1; }
[ "$missing" -eq 0 ] && echo "PASS: $cited cited documents, all present"
exit $missing
