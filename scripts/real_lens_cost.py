#!/usr/bin/env python3
"""What ignoring a real lens costs: a target factorized for the ideal display
and shown through the real lens, against the factorization that knows the lens.

    PYTHONPATH=build/python /usr/bin/python3 scripts/real_lens_cost.py \
        --ideal examples/paper_prototype.json --real examples/paper_prototype_la1608.json \
        --target OUT/target [--iterations 30] [--resolution 0.1]

Both solves run on the same target light field (a folder, e.g. the `target/`
a `layerlab run` of the real scene wrote). Printed per factorization: the
light field's PSNR through the real lens, and the focal stack's (0 to 2.6 D
by 0.2 D, what the eye sees through the real lens against what it sees of the
target itself), both over display-relative values with peak 1.
"""
import argparse
import math

import numpy

import layerlab


def psnr(a, b):
    mse = float(numpy.mean((numpy.asarray(a, dtype=numpy.float64) - numpy.asarray(b, dtype=numpy.float64)) ** 2))
    return math.inf if mse == 0 else 10 * math.log10(1.0 / mse)


def measure(solution, target, resolution):
    shown = layerlab.synthesize(solution.system, solution.patterns, target.geometry)
    _, display, natural = layerlab.focal_stack(solution, 0.0, 2.6, 0.2, resolution=resolution, natural=True)
    return psnr(shown.rgb, target.rgb), psnr(display, natural)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ideal", required=True, help="the display with its ideal lens (scene JSON)")
    parser.add_argument("--real", required=True, help="the same display with the real lens (scene JSON)")
    parser.add_argument("--target", required=True, help="target light-field folder")
    parser.add_argument("--iterations", type=int, default=30)
    parser.add_argument("--resolution", type=float, default=0.1, help="retinal sample size, degrees")
    args = parser.parse_args()
    target = layerlab.read_lightfield(args.target, load_depth=False)
    real = layerlab.solve(layerlab.load_scene(args.real), target, iterations=args.iterations)
    knows = measure(real, target, args.resolution)
    ideal = layerlab.solve(layerlab.load_scene(args.ideal), target, iterations=args.iterations)
    for mine, theirs in zip(real.patterns, ideal.patterns):
        mine[...] = theirs  # the ideal factorization, shown through the real lens
    ignores = measure(real, target, args.resolution)
    print(f"{'factorization':40s} {'PSNR (dB)':>10s} {'focal stack PSNR (dB)':>22s}")
    print(f"{'knows the real lens':40s} {knows[0]:10.2f} {knows[1]:22.2f}")
    print(f"{'computed for the ideal lens':40s} {ignores[0]:10.2f} {ignores[1]:22.2f}")


if __name__ == "__main__":
    main()
