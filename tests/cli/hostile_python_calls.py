"""The Python family of tests/cli/hostile_inputs.sh: hostile arguments to the layerlab module, one call a run.

    hostile_python_calls.py --list                 the calls' names
    hostile_python_calls.py SOURCE_DIR NAME [ARG]  runs one; ARG: a path for the calls that take one

Exit 1 when the call is refused with a clear error (ValueError or TypeError naming the argument, or a
layerlab.Error for a path), as the command exits on a clear error; otherwise (the call returns, raises
something else, or pybind11's cast message) exit 3 with a line "... as bad as an internal error", as the
command exits on an internal error, which hostile_inputs.sh's `try` counts as a failure. The exact messages are held by
python/tests/test_hostile_arguments.py; this runs every such call in a process of its own, under the
script's 30 s limit, so that a crash or a hang is seen too."""

import math
import pathlib
import sys

RAW = ("Unable to cast", "internal error", "_M_default_append", "bad_alloc", "incompatible function arguments")


def calls(source):
    import numpy as np

    import layerlab

    scene = pathlib.Path(source) / "examples" / "small" / "hybrid_small.json"
    system = layerlab.load_scene(scene).compile()
    patterns = [np.full((l.rows, l.cols, 3), 0.5, np.float32) for l in system.layers]
    target = layerlab.synthesize(system, patterns)

    def with_value(value):
        rgb = np.array(target.rgb)
        rgb[1, 2, 3, 1] = value
        return rgb

    def bad_patterns(value):
        bad = [p.copy() for p in patterns]
        bad[0][0, 0, 0] = value
        return bad

    def edited_geometry(field, value):
        g = layerlab.LightFieldGeometry(cols=4, rows=4)
        setattr(g, field, value)
        return g

    def scene_with(value):
        document = layerlab.load_scene(scene).document
        document["elements"][3]["max_transmittance"] = value
        return document

    solution = lambda: layerlab.solve(system, target, iterations=1, threads=1)  # noqa: E731
    return {
        # name: (call, words the message must hold)
        "target_inf": (lambda: layerlab.solve(system, with_value(math.inf), iterations=1), "target: view 1"),
        "target_negative": (lambda: layerlab.solve(system, with_value(-1.0), iterations=1), "target: view 1"),
        "target_nan": (lambda: layerlab.solve(system, with_value(math.nan), iterations=1), "target: view 1"),
        "compare_target_nan": (lambda: layerlab.compare(scene, layerlab.LightField(with_value(math.nan),
                                                                                   target.geometry)),
                               "compare: target: view 1"),
        "patterns_nan": (lambda: layerlab.synthesize(system, bad_patterns(math.nan)), "pattern 0"),
        "patterns_above_1": (lambda: layerlab.synthesize(system, bad_patterns(2.0)), "pattern 0"),
        "geometry_zero_cols": (lambda: layerlab.LightFieldGeometry(cols=0), "cols"),
        "geometry_negative_views": (lambda: layerlab.LightFieldGeometry(views_x=-3), "views_x"),
        "geometry_huge_rows": (lambda: layerlab.LightFieldGeometry(rows=2**40), "rows"),
        "geometry_too_many_rays": (lambda: layerlab.LightFieldGeometry(cols=16384, rows=16384, views_x=256,
                                                                       views_y=256), "rays"),
        "geometry_nan_window": (lambda: layerlab.LightFieldGeometry(window_width=math.nan), "window_width"),
        "geometry_edited_zero_cols": (lambda: layerlab.solve(system, layerlab.LightField(
            edited_geometry("cols", 0)), iterations=1), "cols"),
        "geometry_edited_negative_views": (lambda: layerlab.LightField(edited_geometry("views_y", -3)), "views_y"),
        "synthesize_bad_geometry": (lambda: layerlab.synthesize(system, patterns, geometry=edited_geometry(
            "rows", -1)), "rows"),
        "operator_bad_geometry": (lambda: layerlab.DisplayOperator(system, geometry=edited_geometry("rows", -1)),
                                  "rows"),
        "operator_patterns_nan": (lambda: layerlab.DisplayOperator(system).forward(bad_patterns(math.nan)),
                                  "pattern 0"),
        "operator_gradient_inf": (lambda: layerlab.DisplayOperator(system).adjoint(
            patterns, np.full(layerlab.DisplayOperator(system).light_field_shape, math.inf, np.float32)),
            "light_field_gradient"),
        "retina_operator_tiny_resolution": (lambda: layerlab.RetinaOperator(system, [1.0], resolution_deg=1e-9),
                                            "resolution_deg"),
        "retina_operator_nan_state": (lambda: layerlab.RetinaOperator(system, [math.nan]), "accommodation[0]"),
        "retina_huge_field": (lambda: solution().retina([1.0], field_deg=(1e9, 1e9)), "field"),
        "retina_nan_state": (lambda: solution().retina([math.nan]), "accommodation[0]"),
        "retina_tiny_resolution": (lambda: solution().retina([1.0], resolution_deg=1e-9), "resolution"),
        "scene_dict_nan": (lambda: layerlab.load_scene(scene_with(math.nan)), "/elements/3/max_transmittance"),
        "scene_dict_numpy_value": (lambda: layerlab.load_scene(scene_with(np.float32(0.3))),
                                   "/elements/3/max_transmittance"),
        "contrast_section_inf": (lambda: layerlab.contrast(scene, {"frequencies": [math.inf]}), "/frequencies/0"),
        "iterations_2_40": (lambda: layerlab.solve(system, target, iterations=2**40), "iterations"),
        "iterations_str": (lambda: layerlab.solve(system, target, iterations="10"), "iterations"),
        "seed_negative": (lambda: layerlab.solve(system, target, seed=-1), "seed"),
        "tolerance_str": (lambda: layerlab.solve(system, target, tolerance="0.1"), "tolerance"),
        "display_str": (lambda: layerlab.solve("scene.json", target), "display"),
        "compare_iterations_2_40": (lambda: layerlab.compare(scene, target, iterations=2**40), "iterations"),
        "run_iterations_2_40": (lambda: layerlab.run(scene, "never_written", iterations=2**40), "iterations"),
    }


def main(argv):
    if argv[1:] == ["--list"]:
        print(" ".join(NAMES))
        return 0
    source, name = argv[1], argv[2]
    import layerlab

    if name == "read_lightfield":  # a hostile folder: any clear layerlab error
        try:
            layerlab.read_lightfield(argv[3])
        except layerlab.Error as e:
            return refused(str(e), "")
        return unclear(f"{name}: {argv[3]} was read")
    call, words = calls(source)[name]
    try:
        call()
    except (ValueError, TypeError) as e:
        return refused(str(e), words)
    except Exception as e:  # noqa: BLE001: anything else is the finding
        return unclear(f"{name}: {type(e).__name__}: {e}")
    return unclear(f"{name}: accepted")


def unclear(what):
    print(f"{what}: as bad as an internal error", file=sys.stderr)
    return 3


def refused(message, words):
    print(message, file=sys.stderr)
    if any(raw in message for raw in RAW) or words not in message:
        return unclear(f"not a clear refusal (expected the words {words!r})")
    return 1


NAMES = ["target_inf", "target_negative", "target_nan", "compare_target_nan", "patterns_nan", "patterns_above_1",
         "geometry_zero_cols", "geometry_negative_views", "geometry_huge_rows", "geometry_too_many_rays",
         "geometry_nan_window", "geometry_edited_zero_cols", "geometry_edited_negative_views",
         "synthesize_bad_geometry", "retina_huge_field", "retina_nan_state", "retina_tiny_resolution",
         "scene_dict_nan", "scene_dict_numpy_value", "contrast_section_inf", "iterations_2_40", "iterations_str",
         "seed_negative", "tolerance_str", "display_str", "compare_iterations_2_40", "run_iterations_2_40"]

if __name__ == "__main__":
    sys.exit(main(sys.argv))
