#!/usr/bin/python3
"""`layerlab solve`'s flags against the solver option table.

usage: solver_option_flags.py LAYERLAB SOURCE_DIR

The table is read from docs/scene-reference.md's "solve" section, which
docs.scene_reference_current holds to solvers/solver_option_table.cpp. Every
flag the table names is one of `layerlab solve --help`'s, and every flag of
the solve command is the table's or one of the command's own (output,
checkpoints, memory), not a solver option.
"""
import re
import subprocess
import sys
from pathlib import Path

# The solve command's flags that set no solver option.
COMMAND_OWN = {"--help", "--out", "--write-lightfield", "--checkpoint-every", "--resume", "--max-memory", "--quiet",
               "--verbose"}


def option_table(reference):
    """(key, flag, python) of every row of the solve section's tables."""
    text = Path(reference).read_text()
    section = text[text.index("## `solve`"):text.index("\n## ", text.index("## `solve`") + 1)]
    rows = []
    for line in section.splitlines():
        cells = [c.strip().strip("`") for c in line.strip().strip("|").split("|")]
        if len(cells) == 8 and cells[0] not in ("key", "---"):
            rows.append((cells[0], cells[6], cells[7]))
    if not rows:
        sys.exit(f"FAIL: no solve option table in {reference}")
    return rows


def main():
    layerlab, source = sys.argv[1], sys.argv[2]
    rows = option_table(Path(source) / "docs" / "scene-reference.md")
    table = {flag: key for key, flag, _ in rows if flag}
    help_text = subprocess.run([layerlab, "solve", "--help"], capture_output=True, text=True, check=True).stdout
    given = set(re.findall(r"(?<![\w-])(--[a-z][a-z-]*)", help_text))
    with_embree = "--target-scene" in help_text
    failures = []
    for flag, key in table.items():
        if flag == "--target-scene" and not with_embree:
            continue  # a build without Embree renders no target scene
        if flag not in given:
            failures.append(f"the option table gives {key} the flag {flag}, which `layerlab solve` lacks")
    for flag in sorted(given - set(table) - COMMAND_OWN):
        failures.append(f"`layerlab solve` has {flag}, which the option table (solvers/solver_option_table.cpp) "
                        "lacks")
    for f in failures:
        print("FAIL:", f)
    if failures:
        return 1
    print(f"solve's {len(table)} option flags are the table's")
    return 0


if __name__ == "__main__":
    sys.exit(main())
