#!/usr/bin/env python3
"""The strong scaling of a partitioned solve of the paper prototype (docs/mpi.md),
from measured per-rank costs and communication volumes.

Input: a CSV of partitioned solves of the paper-scale target, one row per rank
count, with the figures each solve's "MPI:" line gives, per iteration:
  ranks, compute_s, sent_bytes, whole_bytes, sums
compute_s is the largest rank's CPU seconds of compute (the sums' CPU taken
out), sent_bytes what a rank's sums sent on average, whole_bytes what the same
sums would have sent as whole chunks, sums the reductions.

Model, per iteration on p ranks:
- compute(p) = a + b * share(p): share(p) is the largest tile's fraction of
  the rays (the tiles of framework/mpi_ranks.h, RayTileOfRank, on 13 view rows
  of 200 pixel rows); a (the layer-sized work every rank repeats) and b (the
  per-ray work) are fitted to the measured compute_s by least squares.
- communication(p) = sums * ((2 (p - 1) + ceil(log2 p)) alpha + sent(p) / beta):
  the spans' MPI_Alltoall (log2 p steps), the reduce-scatter's MPI_Alltoallv
  and the allgather's MPI_Allgatherv (p - 1 messages each). sent(p) per sum is
  the allgather's n (p - 1) / p, n the layer-sized message, plus the reduce-
  scatter's spans, fitted as n (c0 + c1 / p) to the measured rows and never
  more than whole chunks, n (p - 1) / p.
The networks are assumptions, not measurements.

Usage: mpi_scaling_model.py MEASURED.csv
"""
import argparse
import csv
import math

VIEW_ROWS, PIXEL_ROWS = 13, 200  # the paper prototype's target (layerlab info examples/paper_prototype.json)
NETWORKS = {  # name: (alpha in s, beta in bytes/s), assumed, not measured
    "InfiniBand HDR100 (2 us, 12 GB/s)": (2e-6, 12e9),
    "10 Gb Ethernet (25 us, 1.1 GB/s)": (25e-6, 1.1e9),
}


def largest_share(p):
    """The largest tile's fraction of the rays on p ranks (RayTileOfRank's grid)."""
    best = None
    for a in range(1, p + 1):
        b = p // a
        if p % a or a > VIEW_ROWS or b > PIXEL_ROWS:
            continue
        largest = math.ceil(VIEW_ROWS / a) * math.ceil(PIXEL_ROWS / b)
        if best is None or largest < best[0]:
            best = (largest, a, b)
    if best is None:
        return None
    return best[0] / (VIEW_ROWS * PIXEL_ROWS), best[1], best[2]


def fit_line(xs, ys):
    """Least squares y = c0 + c1 x."""
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    c1 = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else 0.0
    return my - c1 * mx, c1


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("measured", help="CSV: ranks, compute_s, sent_bytes, whole_bytes, sums (per iteration)")
    args = ap.parse_args()
    rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(open(args.measured))]
    a, b = fit_line([largest_share(int(r["ranks"]))[0] for r in rows], [r["compute_s"] for r in rows])
    many = [r for r in rows if r["ranks"] > 1]
    sums = many[0]["sums"]
    # n from the whole chunks: a sum sends n (p - 1) / p in its reduce-scatter and as much in its allgather.
    n = sum(r["whole_bytes"] / r["sums"] * r["ranks"] / (2 * (r["ranks"] - 1)) for r in many) / len(many)
    c0, c1 = fit_line([1 / r["ranks"] for r in many],
                      [(r["sent_bytes"] / r["sums"] - n * (r["ranks"] - 1) / r["ranks"]) / n for r in many])
    print(f"compute per iteration = {a * 1e3:.1f} ms + {b * 1e3:.1f} ms x share of the rays (fitted)")
    print(f"per sum: n = {n / 1e6:.2f} MB; the reduce-scatter sends n x ({c0:.3f} + {c1:.3f} / p) (fitted); {sums:.0f} sums")
    print("\n| ranks | measured compute (ms) | model compute (ms) | measured MB sent | model MB sent |")
    print("| --- | --- | --- | --- | --- |")

    def sent(p):
        return 0.0 if p == 1 else n * (p - 1) / p + n * min(max(c0 + c1 / p, 0.0), (p - 1) / p)

    for r in rows:
        p = int(r["ranks"])
        print(f"| {p} | {r['compute_s'] * 1e3:.1f} | {(a + b * largest_share(p)[0]) * 1e3:.1f} | "
              f"{r['sent_bytes'] / 1e6:.2f} | {sums * sent(p) / 1e6 if p > 1 else 0:.2f} |")
    t1 = a + b
    for name, (alpha, beta) in NETWORKS.items():
        print(f"\n{name}")
        print("| ranks | tiles | compute (ms) | MB sent per rank | communication (ms) | time per iteration (ms) "
              "| speed-up | efficiency |")
        print("| --- | --- | --- | --- | --- | --- | --- | --- |")
        for p in (1, 2, 4, 8, 16, 32, 64, 128):
            share, va, vb = largest_share(p)
            compute = a + b * share
            comm = 0.0 if p == 1 else sums * ((2 * (p - 1) + math.ceil(math.log2(p))) * alpha + sent(p) / beta)
            t = compute + comm
            print(f"| {p} | {va} x {vb} | {compute * 1e3:.1f} | {sums * sent(p) / 1e6:.1f} | {comm * 1e3:.1f} | "
                  f"{t * 1e3:.1f} | {t1 / t:.1f} | {t1 / t / p * 100:.0f} % |")


if __name__ == "__main__":
    main()
