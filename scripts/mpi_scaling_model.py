#!/usr/bin/env python3
"""The on-paper scaling of a view-partitioned solve (docs/mpi.md).

Each rank holds its views' share of the target and the per-ray buffers and
every layer; a layer update needs the layer-sized numerator and denominator
summed over all views, so over all ranks: one allreduce of
2 x pixels x 3 channels doubles per layer update. Compute per rank is the
measured single-rank time per iteration times the largest share of views a
rank holds (ceil(views / ranks) / views). The allreduce is Rabenseifner's
(reduce-scatter then allgather, what OpenMPI uses for large messages):
2 log2(p) alpha + 2 (p - 1) / p * n / beta.

Usage: mpi_scaling_model.py T1_SECONDS [--updates 12] [--layers-per-update 1]
"""
import argparse
import math

PIXELS = 400 * 200  # each of the paper prototype's 4 layers (layerlab info examples/paper_prototype.json)
VIEWS = 13 * 13
NETWORKS = {  # name: (alpha in s, beta in bytes/s), assumed, not measured
    "InfiniBand HDR100 (2 us, 12 GB/s)": (2e-6, 12e9),
    "10 Gb Ethernet (25 us, 1.1 GB/s)": (25e-6, 1.1e9),
}


def allreduce_seconds(n_bytes, p, alpha, beta):
    if p == 1:
        return 0.0
    return 2 * math.ceil(math.log2(p)) * alpha + 2 * (p - 1) / p * n_bytes / beta


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("t1", type=float, help="measured time per iteration of one rank, s")
    ap.add_argument("--updates", type=int, default=12, help="allreduces per iteration (hybrid: 2 sets x 3 x 2 layers)")
    ap.add_argument("--layers-per-update", type=int, default=1, help="layers in one allreduce (joint: 4)")
    a = ap.parse_args()
    n = 2 * PIXELS * 3 * 8 * a.layers_per_update  # numerator and denominator, RGB, double
    print(f"bytes per allreduce: {n} ({n / 1e6:.2f} MB); per iteration {a.updates} allreduces, {a.updates * n / 1e6:.1f} MB")
    for name, (alpha, beta) in NETWORKS.items():
        print(f"\n{name}")
        print("| ranks | views per rank (max) | compute (ms) | communication (ms) | time per iteration (ms) | speed-up | efficiency |")
        print("| --- | --- | --- | --- | --- | --- | --- |")
        for p in (1, 2, 4, 8, 16, 32, 64):
            share = math.ceil(VIEWS / p)
            compute = a.t1 * share / VIEWS
            comm = a.updates * allreduce_seconds(n, p, alpha, beta)
            t = compute + comm
            print(f"| {p} | {share} | {compute * 1e3:.1f} | {comm * 1e3:.1f} | {t * 1e3:.1f} | {a.t1 / t:.1f} | {a.t1 / t / p * 100:.0f} % |")


if __name__ == "__main__":
    main()
