#!/usr/bin/python3
"""A command's flags against its option table.

usage: option_table_flags.py LAYERLAB SOURCE_DIR COMMAND SECTION [--scene FILE] [OWN_FLAG...]

The table is read from docs/scene-reference.md's SECTION ("solve",
"run.contrast"), which docs.scene_reference_current holds to the option
table in the source. Every flag the table names is one of `layerlab COMMAND
--help`'s, and every flag of the command is the table's or one of the
OWN_FLAGs (output, checkpoints, memory: not options of the table). With
--scene, a value just beyond the upper end of each flag's range is refused
naming the flag and the table's range (IsValid's message), before the sweep.
"""
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ALWAYS_OWN = {"--help", "--quiet", "--verbose", "--json"}


def option_table(reference, section):
    """(key, range, flag) of every row of the section's option tables."""
    text = Path(reference).read_text()
    start = text.index(f"## `{section}`")
    end = text.find("\n## ", start + 1)
    rows = []
    for line in text[start:end if end >= 0 else len(text)].splitlines():
        cells = [c.strip().strip("`") for c in line.strip().strip("|").split("|")]
        if len(cells) == 8 and cells[0] not in ("key", "---"):
            rows.append((cells[0], cells[3], cells[6]))
    if not rows:
        sys.exit(f"FAIL: no {section} option table in {reference}")
    return rows


def beyond_the_top(cell):
    """A value just beyond the range's upper end: the end when open, else past it."""
    m = re.match(r"^[\[(]\s*(-?[\d.e+]+),\s*(-?[\d.e+]+)\s*([\])])", cell)
    if not m:
        return None
    top = float(m.group(2))
    if m.group(3) == ")":
        return m.group(2)
    return str(int(top) + 1) if top.is_integer() else repr(top * 1.5)


def refusals(layerlab, command, scene, rows):
    failures = []
    with tempfile.TemporaryDirectory() as out:
        for key, cell, flag in rows:
            value = beyond_the_top(cell) if flag else None
            if value is None:
                continue
            run = subprocess.run([layerlab, command, scene, "--out", out + "/o", flag, value], capture_output=True,
                                 text=True)
            said = run.stderr.strip().splitlines()[-1:] or [""]
            if run.returncode == 0 or flag not in said[0] or "must be in " + cell not in said[0]:
                failures.append(f"{flag} {value}: expected a refusal naming {flag} and \"must be in {cell}\" "
                                f"(the table's range of {key}), got exit {run.returncode}: {said[0]}")
    return failures


def main():
    layerlab, source, command, section = sys.argv[1:5]
    rest = sys.argv[5:]
    scene = None
    if rest[:1] == ["--scene"]:
        scene, rest = rest[1], rest[2:]
    own = ALWAYS_OWN | set(rest)
    rows = option_table(Path(source) / "docs" / "scene-reference.md", section)
    table = {flag: key for key, _, flag in rows if flag}
    help_text = subprocess.run([layerlab, command, "--help"], capture_output=True, text=True, check=True).stdout
    given = set(re.findall(r"(?<![\w-])(--[a-z][a-z-]*)", help_text))
    with_embree = "--target-scene" in help_text or command != "solve"
    failures = []
    for flag, key in table.items():
        if flag == "--target-scene" and not with_embree:
            continue  # a build without Embree renders no target scene
        if flag not in given:
            failures.append(f"the option table gives {key} the flag {flag}, which `layerlab {command}` lacks")
    for flag in sorted(given - set(table) - own):
        failures.append(f"`layerlab {command}` has {flag}, which the {section} option table lacks")
    if scene:
        failures += refusals(layerlab, command, scene, rows)
    for f in failures:
        print("FAIL:", f)
    if failures:
        return 1
    print(f"{command}'s {len(table)} option flags are the {section} table's")
    return 0


if __name__ == "__main__":
    sys.exit(main())
