"""The paper's 30 x 3 hybrid solve of the dice, from Python and from the command,
interleaved A/B in one run; prints each solve's seconds (the report's, the same
clock in both) and the ratio of the medians (Python / command).

    PYTHONPATH=build/python /usr/bin/python3 python/examples/solve_ratio.py [ROUNDS]

Needs ../shared/data/dice (given to both; the scene's own "solve" section renders examples/targets/dice.json).
"""

import json
import pathlib
import statistics
import subprocess
import sys
import tempfile

import layerlab

root = pathlib.Path(__file__).resolve().parents[2]
scene_path = root / "examples" / "paper_prototype.json"
command = pathlib.Path(sys.argv[2]) if len(sys.argv) > 2 else root / "build" / "layerlab"
rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 5

scene = layerlab.load_scene(scene_path)
system = scene.compile()
dice = root.parent / "shared" / "data" / "dice"
target = layerlab.read_lightfield(dice)
python_s, command_s = [], []
with tempfile.TemporaryDirectory() as out:
    for r in range(rounds):
        report = layerlab.solve(system, target, solver="hybrid", iterations=30, sub_iterations=3).report
        python_s.append(report["seconds"])
        subprocess.run([str(command), "solve", str(scene_path), "--target", str(dice), "--solver", "hybrid",
                        "--iterations", "30", "--sub-iterations", "3", "--out", out], check=True, capture_output=True)
        command_report = json.loads((pathlib.Path(out) / "report.json").read_text())
        command_s.append(command_report["seconds"])
        assert command_report["final_psnr_db"] == report["final_psnr_db"], "not the same solve"
        print(f"round {r}: python {python_s[-1]:.3f} s, command {command_s[-1]:.3f} s, "
              f"PSNR {report['final_psnr_db']:.3f} dB")
ratio = statistics.median(python_s) / statistics.median(command_s)
print(f"median python {statistics.median(python_s):.3f} s, command {statistics.median(command_s):.3f} s, "
      f"ratio {ratio:.3f}")
