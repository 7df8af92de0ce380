"""Hostile arguments (issue 40): the module refuses what the command line refuses, through the same checks,
with ValueError (layerlab.ArgumentError, layerlab.SceneError) or TypeError naming the argument and the
offending index; never a solve of non-light, a NaN light field, `internal error` or pybind11's cast message."""

import math

import numpy as np
import pytest

from conftest import SKIP_REASON

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)


def patterns_of(system, value=0.5):
    return [np.full((layer.rows, layer.cols, 3), value, np.float32) for layer in system.layers]


@pytest.fixture(scope="module")
def target(small_system):
    return layerlab.synthesize(small_system, patterns_of(small_system))


@pytest.fixture(scope="module")
def solution(small_system, target):
    return layerlab.solve(small_system, target, iterations=1, threads=1)


def no_raw_message(e):
    text = str(e.value)
    assert "Unable to cast" not in text and "internal error" not in text and "_M_default_append" not in text, text


def test_an_argument_error_is_a_value_error_and_a_layerlab_error():
    assert issubclass(layerlab.ArgumentError, ValueError)
    assert issubclass(layerlab.ArgumentError, layerlab.Error)


# Targets: the check a light-field folder's views go through (ReadExr: finite, non-negative light).


@pytest.mark.parametrize("value, said", [(np.inf, "+inf"), (-0.25, "negative (-0.250000)"), (np.nan, "NaN")])
def test_a_target_pixel_that_is_not_light_is_named(small_system, target, value, said):
    rgb = np.array(target.rgb)
    rgb[7, 2, 3, 1] = value
    views_x = target.geometry.views_x
    where = f"target: view 7 (row {7 // views_x}, col {7 % views_x}): pixel (row 2, col 3) channel G is {said}"
    for given in (layerlab.LightField(rgb, target.geometry), rgb):  # a light field, and a bare array
        with pytest.raises(layerlab.ArgumentError) as e:
            layerlab.solve(small_system, given, iterations=1)
        assert where in str(e.value)
        assert "light must be finite and non-negative" in str(e.value)


def test_compare_refuses_a_target_that_is_not_light(small_scene_path, target):
    rgb = np.array(target.rgb)
    rgb[0, 0, 1, 2] = np.inf
    with pytest.raises(ValueError, match=r"compare: target: view 0 .*pixel \(row 0, col 1\) channel B is \+inf"):
        layerlab.compare(small_scene_path, layerlab.LightField(rgb, target.geometry), iterations=1)


# Patterns: the check `layerlab retina --patterns` makes of a pattern file (ReadPatterns: transmittance in [0, 1]).


@pytest.mark.parametrize("value, said", [(np.nan, "is NaN"), (-1.0, "is negative"), (1.5, "is 1.500000"),
                                         (np.inf, "is +inf")])
def test_a_pattern_value_outside_0_1_is_named_with_its_layer(small_system, value, said):
    patterns = patterns_of(small_system)
    patterns[1][3, 4, 0] = value
    with pytest.raises(layerlab.ArgumentError) as e:
        layerlab.synthesize(small_system, patterns)
    layer = small_system.layers[1].name
    assert f"pattern 1 ({layer}): pixel (row 3, col 4) channel R {said}" in str(e.value)


# Geometries: the limits a light-field manifest is held to (CheckLightFieldGeometry), counted in checked arithmetic.


@pytest.mark.parametrize("field, value, said", [
    ("cols", 0, "cols: 0: must be in [1, 16384]"),
    ("rows", -1, "rows: -1: must be in [1, 16384]"),
    ("views_x", -3, "views_x: -3: must be in [1, 256]"),
    ("views_y", 2**40, "views_y: 1099511627776: must be in [1, 256]"),
    ("window_width", math.nan, "window_width: must be in (0, 1e+06] m, got nan"),
    ("origin_z", 0.0, "origin_z: must be in (0, 1e+06] m, got 0"),
    ("eyebox_width", math.inf, "eyebox_width: must be in [0, 1] m, got inf"),
    ("window_left", -math.inf, "window_left: must be finite, got -inf"),
])
def test_a_geometry_beyond_a_manifests_limits_is_refused_naming_the_field(field, value, said):
    with pytest.raises(layerlab.ArgumentError) as e:
        layerlab.LightFieldGeometry(**{field: value})
    assert f"LightFieldGeometry: {said}" in str(e.value)
    no_raw_message(e)


def test_a_geometry_of_too_many_rays_is_refused_before_anything_is_allocated():
    with pytest.raises(layerlab.ArgumentError, match=r"LightFieldGeometry: rays: .* is beyond the 2\^31"):
        layerlab.LightFieldGeometry(cols=16384, rows=16384, views_x=256, views_y=256)


def test_a_geometry_edited_out_of_its_limits_is_refused_where_it_is_used(small_system, target):
    zero_cols = layerlab.LightFieldGeometry(cols=4, rows=4, views_x=2, views_y=2)
    zero_cols.cols = 0
    with pytest.raises(layerlab.ArgumentError, match=r"LightField: geometry: cols: must be in \[1, 16384\], got 0"):
        layerlab.solve(small_system, layerlab.LightField(zero_cols), iterations=1)
    negative_views = layerlab.LightFieldGeometry(cols=4, rows=4)
    negative_views.views_x = -3
    with pytest.raises(layerlab.ArgumentError, match=r"LightField: geometry: views_x: must be in \[1, 256\], got -3"):
        layerlab.LightField(negative_views)
    with pytest.raises(layerlab.ArgumentError, match=r"LightField: geometry: views_x"):
        layerlab.LightField(np.zeros((1, 4, 4, 3), np.float32), negative_views)
    with pytest.raises(layerlab.ArgumentError, match=r"synthesize: geometry: views_x: must be in \[1, 256\]"):
        layerlab.synthesize(small_system, patterns_of(small_system), geometry=negative_views)


def test_a_geometry_number_of_the_wrong_type_is_a_type_error_naming_it():
    with pytest.raises(TypeError, match=r"LightFieldGeometry: cols: expected an int, got float 2.5"):
        layerlab.LightFieldGeometry(cols=2.5)
    with pytest.raises(TypeError, match=r"LightFieldGeometry: origin_z: expected a number, got str"):
        layerlab.LightFieldGeometry(origin_z="1 m")


# Retinal images: the checks `layerlab retina` makes of --accommodation, --resolution and --field.


@pytest.mark.parametrize("kwargs, said", [
    ({"accommodation": [1.0, math.nan]}, r"retina: accommodation\[1\]: nan is not a finite number of diopters"),
    ({"accommodation": [-0.5]}, r"retina: accommodation\[0\]: -0.5 is not a finite number of diopters >= 0"),
    ({"accommodation": [1.0], "field_deg": (1e9, 1e9)}, r"retina: field_deg: 1e\+09 deg is not a retinal field side"),
    ({"accommodation": [1.0], "field_deg": (0, 5)}, r"retina: field_deg: 0 deg is not a retinal field side in \(0, 170\]"),
    ({"accommodation": [1.0], "resolution_deg": 20}, r"retina: resolution_deg: 20 deg is not a retinal sample size"),
    ({"accommodation": [1.0], "resolution_deg": 1e-9}, r"retina: resolution_deg: 1e-09 deg over a field of .* beyond the 1e8"),
    ({"accommodation": []}, r"retina: accommodation: no accommodation state given"),
])
def test_retina_options_are_checked_as_the_command_checks_them(solution, kwargs, said):
    with pytest.raises(layerlab.ArgumentError, match=said):
        solution.retina(**kwargs)


# Dicts: a value JSON cannot hold is named by its key path.


def test_a_nan_in_a_scene_dict_is_named_by_its_pointer(small_scene_path):
    document = layerlab.load_scene(small_scene_path).document
    document["elements"][3]["max_transmittance"] = math.nan
    with pytest.raises(layerlab.SceneError) as e:
        layerlab.load_scene(document)
    assert e.value.file == "<dict>" and e.value.pointer == "/elements/3/max_transmittance"
    assert "NaN is not a number JSON holds" in str(e.value)
    document["elements"][3]["max_transmittance"] = np.float32(0.3)
    with pytest.raises(TypeError, match=r"<dict>: /elements/3/max_transmittance: a float32 is not a JSON value"):
        layerlab.load_scene(document)


def test_an_infinity_in_a_contrast_section_is_named_by_its_pointer(small_scene_path):
    with pytest.raises(layerlab.SceneError) as e:
        layerlab.contrast(small_scene_path, {"frequencies": [1.0, math.inf]})
    assert e.value.file == "contrast()" and e.value.pointer == "/run/contrast/frequencies/1"


# Solver options: the type at the boundary, the range SolverOptions::IsValid states.


@pytest.mark.parametrize("option, value, error, said", [
    ("iterations", 2**40, ValueError, r"iterations: 1099511627776: must be in \[1, 1000000\]"),
    ("threads", -2**70, ValueError, r"threads: -1180591620717411303424: must be in \[0, 1024\]"),
    ("seed", -1, ValueError, r"seed: -1: must be in \[0, 2\^64 - 1\]"),
    ("seed", 2**64, ValueError, r"seed: 18446744073709551616: must be in \[0, 2\^64 - 1\]"),
    ("iterations", "10", TypeError, r"iterations: expected an int, got str '10'"),
    ("iterations", 2.0, TypeError, r"iterations: expected an int, got float 2.0"),
    ("tolerance", "0.1", TypeError, r"tolerance: expected a number, got str '0.1'"),
    ("target_range", 1, TypeError, r"target_range: expected a str"),
])
def test_a_solver_option_of_the_wrong_type_or_range_is_named(small_system, target, option, value, error, said):
    with pytest.raises(error, match=said) as e:
        layerlab.solve(small_system, target, **{option: value})
    no_raw_message(e)


def test_a_display_of_the_wrong_type_is_a_type_error_naming_it(target):
    with pytest.raises(TypeError, match=r"solve: display: expected a layerlab.Scene or layerlab.System, got str"):
        layerlab.solve("scene.json", target)


def test_compare_and_run_name_an_iteration_count_out_of_range(small_scene_path, target, tmp_path):
    with pytest.raises(ValueError, match=r"compare: iterations: 1099511627776: must be in \[1, 1000000\]"):
        layerlab.compare(small_scene_path, target, iterations=2**40)
    with pytest.raises(ValueError, match=r"run: iterations: 1099511627776: must be in \[1, 1000000\]"):
        layerlab.run(small_scene_path, tmp_path / "out", iterations=2**40)
    assert not (tmp_path / "out").exists()


def test_names_of_the_wrong_type_or_unknown_are_named(small_scene_path, small_system, target):
    with pytest.raises(TypeError, match=r"compare: solvers\[1\]: expected a str, got int 3"):
        layerlab.compare(small_scene_path, target, solvers=["hybrid", 3], iterations=1)
    with pytest.raises(TypeError, match=r"compare: objectives: expected None, a str or a list of str, got float"):
        layerlab.compare(small_scene_path, target, objectives=1.0, iterations=1)
    with pytest.raises(ValueError, match=r"unknown sampling \"cubic\"; expected nearest or bilinear"):
        layerlab.solve(small_system, target, sampling="cubic", iterations=1)
    with pytest.raises(ValueError, match=r"unknown sampling \"cubic\""):
        layerlab.synthesize(small_system, patterns_of(small_system), sampling="cubic")


def test_a_light_field_that_is_not_light_is_not_saved(target, tmp_path):
    lf = layerlab.LightField(np.array(target.rgb), target.geometry)
    lf.rgb[3, 0, 5, 2] = np.nan
    with pytest.raises(layerlab.ArgumentError, match=r"LightField.save: rgb: view 3 .*pixel \(row 0, col 5\) channel B"):
        lf.save(tmp_path / "lf")
    assert not (tmp_path / "lf").exists()  # nothing written that read_lightfield would refuse


def test_display_geometry_names_an_origin_that_makes_no_light_field(small_system):
    with pytest.raises(layerlab.ArgumentError, match=r"origin plane must be at a finite depth"):
        layerlab.display_geometry(small_system, math.nan)
    with pytest.raises(layerlab.ArgumentError,
                       match=r"display_geometry: origin_diopters 1e-300 gives a geometry: origin_z: must be in"):
        layerlab.display_geometry(small_system, 1e-300)
    with pytest.raises(TypeError, match=r"display_geometry: origin_diopters: expected a number, got str"):
        layerlab.display_geometry(small_system, "1 D")


def test_contrast_names_a_scene_argument_of_the_wrong_type(small_scene_path):
    with pytest.raises(TypeError, match=r"^contrast: scenes: expected a scene file's path or a list of them, got int"):
        layerlab.contrast(5)
    with pytest.raises(TypeError, match=r"^contrast: scenes\[1\]: expected a scene file's path, got float"):
        layerlab.contrast([small_scene_path, 1.5])
