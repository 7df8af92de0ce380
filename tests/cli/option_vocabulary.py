#!/usr/bin/python3
"""docs/cli.md's vocabulary against every command's options.

usage: option_vocabulary.py LAYERLAB CLI_MD

The command line's options come from `layerlab help --json` (the parser's own
tree). The vocabulary is the table under "## Vocabulary" in docs/cli.md, one
row per option name:

    | `--out` | DIR | the output folder ... | compare, contrast, ... |

Every option name of every command has exactly one row; a row's commands are
exactly those that have the option ("every command" for the global ones); no
row names an option no command has; an option takes a value in every command
that has it or in none (the value column is empty for a flag).
"""
import json
import re
import subprocess
import sys
from pathlib import Path


def catalogue(layerlab):
    out = subprocess.run([layerlab, "help", "--json"], check=True, capture_output=True, text=True).stdout
    uses = {}  # long name -> {command: takes_value}
    commands = []
    for command in json.loads(out)["commands"]:
        commands.append(command["name"])
        for option in command["options"]:
            if option["positional"]:
                continue
            long_names = [n for n in option["names"] if n.startswith("--")]
            name = long_names[0] if long_names else option["names"][0]
            uses.setdefault(name, {})[command["name"]] = option["takes_value"]
    return commands, uses


def vocabulary(cli_md):
    text = Path(cli_md).read_text()
    start = text.index("\n## Vocabulary")
    end = text.find("\n## ", start + 1)
    rows = {}
    for line in text[start:end if end >= 0 else len(text)].splitlines():
        cells = [c.strip() for c in re.split(r"(?<!\\)\|", line.strip().strip("|"))]  # "\|" is a pipe in a cell
        if len(cells) != 4 or cells[0] in ("option", "") or set(cells[0]) <= set("-: "):
            continue
        names = re.findall(r"`(-[^`]+)`", cells[0])
        if not names:
            sys.exit(f"FAIL: {cli_md}: a vocabulary row without an option name: {line}")
        long_names = [n for n in names if n.startswith("--")]
        name = long_names[0] if long_names else names[0]
        if name in rows:
            sys.exit(f"FAIL: {cli_md}: two rows for {name}")
        used_by = {c.strip().strip("`") for c in cells[3].split(",") if c.strip()}
        rows[name] = (cells[1].strip("`"), cells[2], used_by)
    if not rows:
        sys.exit(f"FAIL: {cli_md}: no vocabulary table")
    return rows


def main():
    layerlab, cli_md = sys.argv[1], sys.argv[2]
    commands, uses = catalogue(layerlab)
    rows = vocabulary(cli_md)
    failures = []
    for name, by in sorted(uses.items()):
        if name == "--help":
            continue
        if name not in rows:
            failures.append(f"{name} (of {', '.join(sorted(by))}) has no row in the vocabulary")
            continue
        value, meaning, used_by = rows[name]
        expected = set(by)
        if used_by == {"every command"}:
            used_by = set(commands)
        if used_by != expected:
            failures.append(f"{name}: the row says {sorted(used_by)}, the commands that have it are {sorted(expected)}")
        if len(set(by.values())) > 1:
            failures.append(f"{name}: takes a value in {sorted(c for c, v in by.items() if v)} but not in "
                            f"{sorted(c for c, v in by.items() if not v)}")
        elif bool(value) != next(iter(by.values())):
            failures.append(f"{name}: the row's value column ({value!r}) disagrees with the parser")
        if not meaning:
            failures.append(f"{name}: no meaning")
    for name in sorted(set(rows) - set(uses)):
        failures.append(f"{name}: a row for an option no command has")
    if failures:
        sys.exit("FAIL:\n  " + "\n  ".join(failures))
    print(f"PASS: {len(rows)} option names, each with one meaning, across {len(commands)} commands")


if __name__ == "__main__":
    main()
