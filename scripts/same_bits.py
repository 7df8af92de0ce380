#!/usr/bin/env python3
"""Same bits: the outputs of two layerlab binaries, file by file.

    same_bits.py --old OLD/layerlab --new NEW/layerlab --out DIR [--dice PATH] [--quick]

Runs the same jobs with both binaries, in alternation, and compares what they
wrote byte for byte: the main job of the README on the shipped example (its
`run` section), the Fig. 5 contrast table, and with the dice target (beside
development checkouts only) a solve of every built-in solver on a display it
suits, at a fixed iteration count. A restructuring that claims the same bits
must leave every file equal, apart from what records wall time: the lines of
report.json, trace.csv and the HTML pages that carry seconds, and the
`compare` section, whose solves stop on a time budget. Those are listed
apart. Exit status 1 when a file differs otherwise or is missing on one side.
"""
import argparse
import csv
import io
import json
import os
import re
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DEFAULT_DICE = os.path.join(ROOT, "..", "shared", "data", "dice")
# What records the run and not its results: wall time, the build, and the fewest threads an iteration ran on
# (threads_min: the machine's load at the time; framework/thread_budget.h).
TIMED_JSON_KEY = re.compile(r"seconds|time|date|elapsed|version|^layerlab$|^command$|^host$|^threads_min$",
                            re.IGNORECASE)


def jobs(dice, quick):
    example = os.path.join(ROOT, "examples", "paper_prototype.json")
    found = [("main-job", ["run", example]),
             ("fig5-contrast", ["contrast"] + [os.path.join(ROOT, "examples", s) for s in
                                               ("additive_2layer.json", "multiplicative_2layer.json",
                                                "paper_prototype.json")])]
    if quick or not os.path.isdir(dice):
        return found
    solves = [("hybrid", "paper_prototype.json"), ("joint", "paper_prototype.json"),
              ("quasi-newton", "paper_prototype.json"), ("multiplicative", "multiplicative_2layer.json"),
              ("additive-trust-region", "additive_2layer.json")]
    for solver, scene in solves:
        found.append((f"dice-{solver}", ["solve", os.path.join(ROOT, "examples", scene), "--target", dice,
                                          "--solver", solver, "--iterations", "10", "--write-lightfield"]))
    return found


VERSION = re.compile(rb"git [0-9a-f]{7,40}(-dirty)?")
SECONDS = re.compile(rb"\b\d+(\.\d+)? s\b")
TRACE_ROW = re.compile(rb"^(\s+\d+)\s+[0-9.]+(\s)", re.MULTILINE)  # the seconds column, however wide


def masked_text(name, data):
    data = SECONDS.sub(b"T s", VERSION.sub(b"git X", data))
    if name.endswith("report.txt"):  # the trace table: iteration, seconds, objective, PSNR
        data = TRACE_ROW.sub(rb"\1 T\2", data)
    if name.endswith("peaks.txt"):  # the last two columns: solve (s), sweep (s)
        lines = data.split(b"\n")
        data = b"\n".join(b" ".join(l.split()[:-2]) if l and not l.startswith(b"#") else l for l in lines)
    return data


def without_timing(path, data):
    """The file's bytes with what records wall time (and the build's version) masked."""
    name = os.path.basename(path)
    if name.endswith(".json"):
        def strip(value):
            if isinstance(value, dict):
                return {k: strip(v) for k, v in value.items() if not TIMED_JSON_KEY.search(k)}
            if isinstance(value, list):
                return [strip(v) for v in value]
            if isinstance(value, str):
                return masked_text(name, value.encode()).decode(errors="replace")
            return value
        try:
            return json.dumps(strip(json.loads(data)), sort_keys=True).encode()
        except ValueError:
            return data
    if name.endswith(".csv"):
        rows = list(csv.reader(io.StringIO(data.decode(errors="replace"))))
        if rows and any(TIMED_JSON_KEY.search(h) for h in rows[0]):
            keep = [i for i, h in enumerate(rows[0]) if not TIMED_JSON_KEY.search(h)]
            data = "\n".join(",".join(r[i] for i in keep if i < len(r)) for r in rows).encode()
        return masked_text(name, data)
    if name.endswith((".txt", ".md")):
        return masked_text(name, data)
    return data


def compare(old_dir, new_dir):
    same, timed, differ, missing = [], [], [], []
    names = set()
    for base in (old_dir, new_dir):
        for parent, _, files in os.walk(base):
            for f in files:
                names.add(os.path.relpath(os.path.join(parent, f), base))
    for name in sorted(names):
        a, b = os.path.join(old_dir, name), os.path.join(new_dir, name)
        if not (os.path.isfile(a) and os.path.isfile(b)):
            missing.append(name)
            continue
        x, y = open(a, "rb").read(), open(b, "rb").read()
        if x == y:
            same.append(name)
        elif name.startswith("compare/") or name.endswith((".html", ".svg")) or \
                without_timing(name, x) == without_timing(name, y):
            timed.append(name)
        else:
            differ.append(name)
    return same, timed, differ, missing


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--old", required=True)
    parser.add_argument("--new", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--dice", default=DEFAULT_DICE)
    parser.add_argument("--quick", action="store_true", help="the main job and Fig. 5 only")
    args = parser.parse_args()
    if os.path.exists(args.out):
        shutil.rmtree(args.out)
    failed = False
    for name, argv in jobs(args.dice, args.quick):
        for side, binary in (("old", args.old), ("new", args.new)):
            out = os.path.join(args.out, side, name)
            run = subprocess.run([binary] + argv + ["--out", out], stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
            if run.returncode != 0:
                print(f"{name} ({side}) failed:\n{run.stdout.decode(errors='replace')[-2000:]}")
                failed = True
        same, timed, differ, missing = compare(*(os.path.join(args.out, s, name) for s in ("old", "new")))
        print(f"{name}: {len(same)} files the same bits, {len(timed)} differing only in what records wall time, "
              f"{len(differ)} differing, {len(missing)} on one side only")
        for f in differ:
            print(f"  DIFFERS: {f}")
        for f in missing:
            print(f"  ONE SIDE ONLY: {f}")
        failed = failed or bool(differ or missing)
    print("same bits" if not failed else "NOT the same bits")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
