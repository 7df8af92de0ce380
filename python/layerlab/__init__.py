"""layerlab: layered light-field displays from Python (docs/python.md).

    import layerlab
    scene = layerlab.load_scene("examples/small/hybrid_small.json")
    system = scene.compile()
    solution = layerlab.solve(scene, iterations=10)   # the scene's "solve" section
    print(solution.report["final_psnr_db"])

Arrays are float32 NumPy arrays: a light field's .rgb is (views, rows, cols, 3),
a pattern (rows, cols, 3); those a layerlab object owns are views of its
buffers that keep it alive. Lengths in meters, angles in degrees; a value's unit
ends its name (fov_x_deg, depth_m, frame_rate_hz).
"""

from typing import Any as _Any, Callable as _Callable, Dict as _Dict, List as _List, Optional as _Optional
from typing import Sequence as _Sequence, Tuple as _Tuple, Union as _Union

import numpy as _numpy

from .errors import ArgumentError, Error, Interrupted, SceneError
from ._layerlab import (
    Branch,
    DisplayOperator,
    Layer,
    LightField,
    LightFieldGeometry,
    PathStep,
    RetinaOperator,
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
    patterns_as_seen,
    read_lightfield,
    render_target,
    run,
    set_verbosity,
    solve,
    solvers,
    srgb,
    ssim,
    synthesize,
    verbosity,
)
from . import _layerlab


def _spell_out_keywords(function, leading, keywords, returns):
    """`function` (a C++ function that takes its options as **kwargs) wrapped in one whose signature names
    every option: the parameters `leading` (inspect.Parameter objects), then each of `keywords` ([(name,
    annotation, default text)], from the option table) keyword-only with default None: not given, the
    table's default, which the docstring states; `returns` the return annotation. An option given as None is
    left out of the call."""
    import functools
    import inspect

    types = {"int": int, "float": float, "list": list, "bool": bool, "str": str, "object": object}
    options = {name for name, _, _ in keywords}

    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        return function(*args, **{k: v for k, v in kwargs.items() if not (k in options and v is None)})

    wrapper.__signature__ = inspect.Signature(leading + [
        inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY, default=None, annotation=types[annotation])
        for name, annotation, _ in keywords], return_annotation=returns)
    # pybind11's first docstring line is its own signature, with **kwargs: the one above replaces it.
    doc = function.__doc__ or ""
    wrapper.__doc__ = doc.split("\n", 1)[1].lstrip("\n") if doc.startswith(function.__name__ + "(") else doc
    return wrapper


def _parameters(*specs):
    """inspect.Parameter objects from (name, default or ..., keyword_only, annotation): ... for a required one."""
    import inspect

    return [inspect.Parameter(name, inspect.Parameter.KEYWORD_ONLY if keyword_only
                              else inspect.Parameter.POSITIONAL_OR_KEYWORD,
                              default=inspect.Parameter.empty if default is ... else default, annotation=annotation)
            for name, default, keyword_only, annotation in specs]


solve = _spell_out_keywords(
    _layerlab.solve,
    _parameters(("display", ..., False, _Union[Scene, System]),
                ("target", None, False, _Optional[_Union[LightField, _numpy.ndarray]]),
                ("solver", None, True, _Optional[str]), ("sampling", None, True, _Optional[str]),
                ("callback", None, True, _Optional[_Callable[[_Dict[str, _Any]], _Any]])),
    _layerlab._solve_keywords, Solution)
contrast = _spell_out_keywords(
    _layerlab.contrast, _parameters(("scenes", ..., False, _Union[str, _Sequence[str]]),
                                    ("section", None, False, _Optional[_Dict[str, _Any]])),
    _layerlab._contrast_keywords, _List[_Dict[str, _Any]])


def _require_solution(solution, function):
    if not isinstance(solution, Solution):
        raise TypeError(f"{function}: solution: expected a layerlab.Solution, got {type(solution).__name__}")


def retina(solution: Solution, accommodation: _Sequence[float], *, resolution_deg: float = 0.05,
           field_deg: _Optional[_Tuple[float, float]] = None,
           natural: bool = False) -> _Union[_numpy.ndarray, _Tuple[_numpy.ndarray, _numpy.ndarray]]:
    """What the eye sees of a solution focused at each of `accommodation` (D): (states, rows, cols, 3) float32,
    display-relative linear RGB; resolution_deg: deg per sample; field_deg: (x, y) deg (default: the display's
    field of view); natural=True: (display, natural). The same as Solution.retina."""
    _require_solution(solution, "retina")
    return solution.retina(accommodation, resolution_deg=resolution_deg, field_deg=field_deg, natural=natural)


def focal_stack(solution: Solution, start: float, stop: float, step: float, *, resolution_deg: float = 0.05,
                field_deg: _Optional[_Tuple[float, float]] = None, natural: bool = False) -> _Tuple[_numpy.ndarray, ...]:
    """Retinal images from `start` to `stop` D (inclusive) by `step` D: (diopters, images), images
    (states, rows, cols, 3) as Solution.retina gives them; natural=True: (diopters, images, natural),
    the last what the eye sees of the target itself."""
    _require_solution(solution, "focal_stack")
    if not step > 0 or stop < start:
        raise ValueError(f"focal_stack: needs step > 0 and stop >= start, got {start}, {stop}, {step}")

    diopters = start + step * _numpy.arange(int(_numpy.floor((stop - start) / step + 1e-9)) + 1)
    seen = solution.retina(list(diopters), resolution_deg=resolution_deg, field_deg=field_deg, natural=natural)
    return (diopters, *seen) if natural else (diopters, seen)


__all__ = [
    "__version__", "ArgumentError", "Branch", "compare", "compile", "contrast", "csf_jnd", "display_geometry",
    "DisplayOperator", "Error", "fit", "focal_stack", "Interrupted", "Layer", "LightField", "LightFieldGeometry",
    "load_scene", "ms_ssim", "PathStep", "patterns_as_seen", "read_lightfield", "render_target", "retina",
    "RetinaOperator", "run", "Scene", "SceneError", "set_verbosity", "Solution", "solve", "solvers", "srgb", "ssim",
    "synthesize", "System", "verbosity",
]
