#!/usr/bin/python3
"""One command's `--json` result: stdout holds exactly one JSON object, for
that command, with the expected fields.

usage: json_result.py FILE COMMAND [KEY | KEY=VALUE ...]

KEY: the field is present (a dotted path: "report.final_psnr_db").
KEY=VALUE: and equals VALUE, read as JSON when it parses so (numbers, true,
null, lists), else as text.
"""
import json
import sys


def field(result, path):
    value = result
    for part in path.split("."):
        if isinstance(value, list):
            value = value[int(part)]
        elif part in value:
            value = value[part]
        else:
            sys.exit(f"FAIL: {sys.argv[1]}: no field {path!r} in {sorted(result)}")
    return value


def main():
    path, command, checks = sys.argv[1], sys.argv[2], sys.argv[3:]
    text = open(path).read()
    try:
        result = json.loads(text)  # one object and nothing else: a second would not parse
    except json.JSONDecodeError as e:
        sys.exit(f"FAIL: {path}: stdout is not one JSON object ({e}):\n{text[:600]}")
    if not isinstance(result, dict):
        sys.exit(f"FAIL: {path}: not a JSON object")
    for key in ("command", "layerlab_version", "git_commit"):
        if key not in result:
            sys.exit(f"FAIL: {path}: no {key!r}")
    if result["command"] != command:
        sys.exit(f"FAIL: {path}: command {result['command']!r}, expected {command!r}")
    for check in checks:
        key, _, expected = check.partition("=")
        value = field(result, key)
        if "=" in check:
            try:
                want = json.loads(expected)
            except json.JSONDecodeError:
                want = expected
            if value != want:
                sys.exit(f"FAIL: {path}: {key} is {value!r}, expected {want!r}")
    print(f"{command}: one JSON object, {len(result)} fields")


if __name__ == "__main__":
    main()
