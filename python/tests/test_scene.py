"""load_scene, compile, the display system as Python objects, SceneError."""

import gc
import json
import math

import pytest

from conftest import EXAMPLES, SKIP_REASON

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)


def scene_dict(path):
    with open(path) as f:
        return json.load(f)


def test_small_prototype_layers_and_branches(small_scene_path):
    scene = layerlab.load_scene(small_scene_path)
    assert scene.file == str(small_scene_path)
    assert scene.elements[0] == "eye"
    system = scene.compile()
    assert len(system.layers) == 4 and len(system.branches) == 2
    # The scene asks for images at 0.4, 1.0, 1.6 and 2.2 D (farthest first).
    assert system.diopters == pytest.approx([0.4, 1.0, 1.6, 2.2], abs=1e-9)
    assert system.depths_m == pytest.approx([1 / 0.4, 1 / 1.0, 1 / 1.6, 1 / 2.2], rel=1e-9)
    # A thin lens of focal length f images a panel at distance d < f with M = f / (f - d).
    f = system.focal_length_m
    assert f == pytest.approx(0.075)
    for layer, m in zip(system.layers, system.magnifications):
        assert layer.magnification == m
        assert m == pytest.approx(f / (f - layer.panel_distance_m), rel=1e-9)
    # Each branch: the half mirror's 0.5 times its two panels' maximum transmittance (from the scene).
    doc = scene_dict(small_scene_path)
    max_t = {e["name"]: e["max_transmittance"] for e in doc["elements"] if e["type"] == "lc_panel"}
    for b, (branch, efficiency) in enumerate(zip(system.branches, system.efficiencies)):
        expected = 0.5 * math.prod(max_t[system.layers[k].element] for k in branch.layers)
        assert efficiency == pytest.approx([expected] * 3, rel=1e-9)
        assert all(system.layers[k].branch == b for k in branch.layers)
    assert [s.type for s in system.layers[0].path] == ["thin_lens", "half_mirror", "lc_panel"]


def test_a_dict_is_the_same_scene_as_its_file(small_scene_path):
    from_file = layerlab.load_scene(small_scene_path).compile()
    from_dict = layerlab.compile(layerlab.load_scene(scene_dict(small_scene_path)))
    assert from_dict.file == "<dict>"
    assert from_dict.depths_m == from_file.depths_m
    assert from_dict.magnifications == from_file.magnifications
    assert from_dict.efficiencies == from_file.efficiencies


def test_layers_keep_their_system_alive(small_scene_path):
    layers = layerlab.load_scene(small_scene_path).compile().layers
    gc.collect()
    assert [layer.name for layer in layers] == ["rear_a", "rear_b", "front_a", "front_b"]
    assert layers[3].diopters == pytest.approx(2.2)


def test_a_bad_scene_dict_raises_scene_error_with_its_pointer(small_scene_path):
    doc = scene_dict(small_scene_path)
    panel = next(i for i, e in enumerate(doc["elements"]) if e["type"] == "lc_panel")
    doc["elements"][panel]["pixel_pitch"] = "-585 um"
    with pytest.raises(layerlab.SceneError) as info:
        layerlab.load_scene(doc, file="mine.json")
    e = info.value
    assert e.file == "mine.json"
    assert e.pointer == f"/elements/{panel}/pixel_pitch"
    assert str(e).startswith(f"mine.json: /elements/{panel}/pixel_pitch: ")
    assert e.message and e.message in str(e)
    assert isinstance(e, layerlab.Error) and isinstance(e, ValueError)


def test_a_compile_error_names_the_element(small_scene_path):
    doc = scene_dict(small_scene_path)
    doc["elements"][0]["next"] = "nowhere"
    scene = layerlab.load_scene(doc)
    with pytest.raises(layerlab.SceneError) as info:
        scene.compile()
    assert info.value.file == "<dict>"
    assert info.value.pointer.startswith("/elements/0")
    assert "nowhere" in str(info.value)


def test_a_missing_file_names_it():
    path = EXAMPLES / "no_such_scene.json"
    with pytest.raises(layerlab.Error) as info:
        layerlab.load_scene(path)
    assert str(path) in str(info.value)


def test_not_a_scene():
    with pytest.raises(TypeError, match="expected a path .* or a dict, got int"):
        layerlab.load_scene(3)
    with pytest.raises(ValueError):
        layerlab.load_scene({"format": "layerlab-scene/1", "elements": [], "x": float("nan")})
