"""layerlab: layered light-field displays from Python (docs/python.md).

    import layerlab
    scene = layerlab.load_scene("examples/small/hybrid_small.json")
    system = scene.compile()
    solution = layerlab.solve(scene, iterations=10)   # the scene's "solve" section
    print(solution.report["final_psnr_db"])

Arrays are float32 NumPy arrays: a light field's .rgb is (views, rows, cols, 3),
a pattern (rows, cols, 3); those a layerlab object owns are views of its
buffers that keep it alive. Lengths in meters, angles in radians.
"""

from .errors import Error, Interrupted, SceneError
from ._layerlab import (
    Branch,
    Layer,
    LightField,
    LightFieldGeometry,
    PathStep,
    Scene,
    Solution,
    System,
    __version__,
    compile,
    contrast,
    display_geometry,
    load_scene,
    read_lightfield,
    render_target,
    run,
    solve,
    solvers,
    synthesize,
)

__all__ = [
    "Branch", "Error", "Interrupted", "Layer", "LightField", "LightFieldGeometry", "PathStep", "Scene",
    "SceneError", "Solution", "System", "__version__", "compile", "contrast", "display_geometry", "load_scene",
    "read_lightfield", "render_target", "run", "solve", "solvers",
    "synthesize",
]
