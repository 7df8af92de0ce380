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

from .errors import ArgumentError, Error, Interrupted, SceneError
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
    compare,
    compile,
    contrast,
    csf_jnd,
    display_geometry,
    fit,
    load_scene,
    ms_ssim,
    read_lightfield,
    render_target,
    run,
    set_verbosity,
    solve,
    solvers,
    ssim,
    synthesize,
    verbosity,
)



def retina(solution, accommodation, resolution=0.05, field=None, natural=False):
    """What the eye sees of a solution focused at each of `accommodation` (D): (states, rows, cols, 3) float32,
    display-relative linear RGB; natural=True: (display, natural). The same as Solution.retina."""
    return solution.retina(accommodation, resolution=resolution, field=field, natural=natural)


def focal_stack(solution, start, stop, step, resolution=0.05, field=None, natural=False):
    """Retinal images from `start` to `stop` D (inclusive) by `step`: (diopters, images), images
    (states, rows, cols, 3) as Solution.retina gives them; natural=True: (diopters, images, natural),
    the last what the eye sees of the target itself."""
    if not step > 0 or stop < start:
        raise ValueError(f"focal_stack: needs step > 0 and stop >= start, got {start}, {stop}, {step}")
    import numpy

    diopters = start + step * numpy.arange(int(numpy.floor((stop - start) / step + 1e-9)) + 1)
    seen = solution.retina(list(diopters), resolution=resolution, field=field, natural=natural)
    return (diopters, *seen) if natural else (diopters, seen)


__all__ = [
    "ArgumentError", "Branch", "Error", "Interrupted", "Layer", "LightField", "LightFieldGeometry", "PathStep", "Scene",
    "SceneError", "Solution", "System", "__version__", "compare", "compile", "contrast", "csf_jnd", "display_geometry", "fit", "focal_stack", "load_scene",
    "ms_ssim", "read_lightfield", "render_target", "retina", "run", "solve", "solvers", "ssim",
    "synthesize",
]
