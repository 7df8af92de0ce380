#!/usr/bin/python3
"""A solve on a busy machine: the default threads against one thread (issue 49).

Runs `layerlab solve SCENE --iterations N` with the default thread count and
with `--threads 1`, interleaved (their order alternating from round to round),
on an idle machine and under a background load of one busy process per core
(`--load`), and prints each configuration's median solve time (the solver's
own, from report.json), the ratio default / one thread and the PSNR, which
must be the same in both.

Usage: bench/busy_machine.py LAYERLAB [--scene S] [--iterations N] [--rounds R] [--loads 0,2]
A measurement, not a test: nothing here fails on a slow figure.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))


def solve(layerlab, scene, iterations, threads, out, env):
    command = [layerlab, "solve", scene, "--iterations", str(iterations), "--out", out, "-q"]
    if threads:
        command += ["--threads", str(threads)]
    subprocess.run(command, check=True, env=env, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "report.json")) as f:
        report = json.load(f)
    return report["seconds"], report["final_psnr_db"], report["threads"]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("layerlab")
    parser.add_argument("--scene", default=os.path.join(HERE, "..", "examples", "small", "hybrid_small.json"))
    parser.add_argument("--iterations", type=int, default=100)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--loads", default="0,%d" % os.cpu_count(), help="busy processes, comma-separated")
    parser.add_argument("--env", action="append", default=[], help="NAME=VALUE for the default-thread runs")
    args = parser.parse_args()
    with open("/proc/loadavg") as f:
        print("load average before: " + " ".join(f.read().split()[:3]))
    default_env = dict(os.environ)
    for assignment in args.env:
        name, _, value = assignment.partition("=")
        default_env[name] = value
    print("| busy processes | default threads: median s | one thread: median s | default / one | "
          "pair by pair: median of default / one | PSNR (dB) |")
    print("| --- | --- | --- | --- | --- | --- |")
    with tempfile.TemporaryDirectory() as work:
        # One untimed run first: the page cache and the target scene read warm for every timed run.
        solve(args.layerlab, args.scene, 1, 1, os.path.join(work, "warm"), os.environ)
        for load in [int(x) for x in args.loads.split(",")]:
            busy = [subprocess.Popen(["sh", "-c", "while :; do :; done"]) for _ in range(load)]
            try:
                times = {"default": [], "one": []}
                psnr, threads_used = {}, {}
                for r in range(args.rounds):
                    order = ["default", "one"] if r % 2 == 0 else ["one", "default"]
                    for config in order:
                        out = os.path.join(work, "%s-%d-%d" % (config, load, r))
                        env = default_env if config == "default" else os.environ
                        seconds, db, used = solve(args.layerlab, args.scene, args.iterations,
                                                  0 if config == "default" else 1, out, env)
                        times[config].append(seconds)
                        psnr.setdefault(config, db)
                        threads_used[config] = used
            finally:
                for p in busy:
                    p.kill()
                    p.wait()
            d, o = statistics.median(times["default"]), statistics.median(times["one"])
            same = "%.2f" % psnr["default"] if psnr["default"] == psnr["one"] else "%.4f / %.4f" % (
                psnr["default"], psnr["one"])
            pairs = statistics.median(a / b for a, b in zip(times["default"], times["one"]))
            print("| %d | %.3f (%d threads; %s) | %.3f (%s) | %.2f | %.2f | %s |" % (
                load, d, threads_used["default"], ", ".join("%.2f" % t for t in times["default"]), o,
                ", ".join("%.2f" % t for t in times["one"]), d / o, pairs, same))
            sys.stdout.flush()


if __name__ == "__main__":
    main()
