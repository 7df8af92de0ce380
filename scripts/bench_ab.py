#!/usr/bin/env python3
"""Interleaved A/B of benchmark rows: several builds of layerlab_bench, run in rotation.

    bench_ab.py --filter REGEX --rounds N NAME=PATH [NAME=PATH ...]

Round r runs every build once, starting from the r-th (A B C, B C A, C A B, ...), so that
a busy minute of the shared machine falls on every build alike. Prints, per row, each
build's median real time over the rounds (ms) and each median against the first
build's; --json FILE also keeps every sample.
"""
import argparse
import json
import statistics
import subprocess
import sys
import time

UNIT_MS = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--filter", required=True, help="--benchmark_filter of every run")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--json", help="write every sample here")
    parser.add_argument("builds", nargs="+", help="NAME=PATH of a layerlab_bench")
    args = parser.parse_args()
    builds = dict(b.split("=", 1) for b in args.builds)
    names = list(builds)
    samples = {n: {} for n in names}
    for r in range(args.rounds):
        for name in names[r % len(names):] + names[:r % len(names)]:
            out = subprocess.run([builds[name], "--benchmark_filter=" + args.filter, "--benchmark_format=json"],
                                 capture_output=True, text=True, check=True).stdout
            for row in json.loads(out)["benchmarks"]:
                samples[name].setdefault(row["name"], []).append(float(row["real_time"]) * UNIT_MS[row["time_unit"]])
            print(time.strftime("%H:%M:%S"), "round", r, name, file=sys.stderr, flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(samples, f)
    first = names[0]
    print("row," + ",".join(f"{n}_median_ms" for n in names) + "," + ",".join(f"{n}/{first}" for n in names[1:]))
    for row in samples[first]:
        if not all(row in samples[n] for n in names):
            continue
        median = {n: statistics.median(samples[n][row]) for n in names}
        print(row + "," + ",".join(f"{median[n]:.3f}" for n in names) + "," +
              ",".join(f"{median[n] / median[first]:.3f}" for n in names[1:]))


if __name__ == "__main__":
    main()
