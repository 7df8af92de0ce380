"""One 30 x 3 hybrid solve of the dice from Python, for timing the whole process against `layerlab solve`
(docs/python.md, Speed). Prints the report's solve seconds and PSNR.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/solve_once.py [DICE_DIR]
"""

import pathlib
import sys

import layerlab

root = pathlib.Path(__file__).resolve().parents[2]
dice = sys.argv[1] if len(sys.argv) > 1 else root.parent / "shared" / "data" / "dice"
system = layerlab.load_scene(root / "examples" / "paper_prototype.json").compile()
target = layerlab.read_lightfield(dice)
report = layerlab.solve(system, target, solver="hybrid", iterations=30, sub_iterations=3).report
print(f"python solve {report['seconds']:.3f} s PSNR {report['final_psnr_db']:.4f}")
