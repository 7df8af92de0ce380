"""contrast(): the Fig. 5 sweep as arrays, against the command's CSV and natural viewing's focus."""

import csv
import os
import subprocess

import numpy as np
import pytest

from conftest import SKIP_REASON

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)

SECTION = {"depths": ["0.7 D", "1.9 D"], "frequencies": ["1 cpd"],
           "accommodation": {"from": "0 D", "to": "2.6 D", "step": "0.1 D"}, "retina_field": "4 deg"}


def test_contrast_curves(small_scene_path, tmp_path):
    curves = layerlab.contrast(small_scene_path, SECTION)
    assert [(c["display"], c["target_diopters"]) for c in curves] == [
        ("natural", 0.7), ("hybrid_small", 0.7), ("natural", 1.9), ("hybrid_small", 1.9)]
    for c in curves:
        np.testing.assert_allclose(c["accommodation"], np.arange(27) * 0.1, atol=1e-9)
        assert c["contrast"].shape == (27,) and c["contrast_shifted"].shape == (27,)
        assert c["frequency"] == 1.0
        if c["display"] == "natural":  # the eye sees the grating sharpest where it lies
            assert c["peak"] == pytest.approx(c["target_diopters"], abs=0.15)
    command = os.environ.get("LAYERLAB_COMMAND")
    if not command:
        pytest.skip("LAYERLAB_COMMAND not set (ctest sets it): no comparison with the command")
    subprocess.run([command, "contrast", str(small_scene_path), "--depths", "0.7,1.9", "--frequencies", "1",
                    "--accommodation", "0:2.6:0.1", "--field", "4", "--out", str(tmp_path)],
                   check=True, capture_output=True)
    with open(tmp_path / "contrast.csv") as f:
        rows = list(csv.DictReader(f))
    for c in curves:
        mine = [r for r in rows if r["display"] == c["display"] and float(r["target_D"]) == c["target_diopters"]]
        np.testing.assert_allclose([float(r["normalized_contrast"]) for r in mine], c["contrast"], atol=1e-6)


def test_contrast_options_are_checked_with_their_pointer(small_scene_path):
    with pytest.raises(layerlab.SceneError) as info:
        layerlab.contrast(small_scene_path, {"frequencies": ["-2 cpd"]})
    assert info.value.file == "contrast()" and info.value.pointer == "/run/contrast/frequencies/0"
    with pytest.raises(layerlab.SceneError, match="frequncies"):
        layerlab.contrast(small_scene_path, {"frequncies": ["2 cpd"]})


def test_factorized_for_and_field_center(small_scene_path):
    """Factorized for itself, off the axis, a display's second curve is its own; other layers are refused."""
    section = dict(SECTION, depths=["1.3 D"], retina_field="2 deg", field_center="3 deg")
    curves = layerlab.contrast(small_scene_path, section, factorized_for=small_scene_path)
    names = [c["display"] for c in curves]
    assert names == ["natural", "hybrid_small", "hybrid_small (factorized for hybrid_small)"]
    own, seen = curves[1], curves[2]
    assert own["factorized_for"] is None and seen["factorized_for"] == "hybrid_small"
    np.testing.assert_array_equal(seen["contrast"], own["contrast"])
    other = small_scene_path.parent.parent / "multiplicative_2layer.json"
    with pytest.raises(layerlab.Error, match="factorized_for: multiplicative_2layer: its patterns cannot be shown"):
        layerlab.contrast(small_scene_path, section, factorized_for=str(other))
    with pytest.raises(layerlab.Error, match="field_center: 80: the retinal window"):
        layerlab.contrast(small_scene_path, dict(section, field_center="80 deg"))
