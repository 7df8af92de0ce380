"""fit(): `layerlab fit` as columns and a calibrated scene dict, against the example's true values and the command."""

import json
import os
import subprocess

import numpy as np
import pytest

from conftest import EXAMPLES, SKIP_REASON

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)

SCENE = EXAMPLES / "paper_prototype.json"
MEASUREMENTS = EXAMPLES / "paper_prototype_measurements.json"


def has_ceres():
    try:
        layerlab.fit(EXAMPLES / "no_such_scene.json", EXAMPLES / "no_such_measurements.json")
    except layerlab.Error as e:
        return "needs Ceres" not in str(e)
    return True


pytestmark = pytest.mark.skipif(not has_ceres(), reason="this build has no Ceres (LAYERLAB_WITH_CERES=OFF)")

# The placements the example's measurements were made with (docs/measurements-format.md): m, rad.
TRUTH = {
    "rear_a": (73.1570e-3, 0.30e-3, -0.20e-3, 0.25), "rear_b": (69.4683e-3, -0.45e-3, 0.15e-3, -0.40),
    "front_a": (67.0478e-3, 0.10e-3, 0.35e-3, 0.15), "front_b": (64.0232e-3, -0.25e-3, -0.30e-3, -0.20),
}


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    os.chdir(tmp_path_factory.mktemp("fit"))  # the calibrated scene's paths are relative to it
    return layerlab.fit(SCENE, MEASUREMENTS)


def test_the_fit_recovers_the_true_placements(fitted):
    p = fitted["parameters"]
    value = {(e, q): (v, s) for e, q, v, s in zip(p["element"], p["quantity"], p["value"], p["std_dev"])}
    for panel, (distance, ox, oy, rotation_deg) in TRUTH.items():
        for quantity, truth in (("distance", distance), ("offset_x", ox), ("offset_y", oy),
                                ("rotation", rotation_deg)):
            v, s = value[(panel, quantity)]
            assert s > 0 and abs(v - truth) < 4 * s, (panel, quantity, v, truth, s)
    units = dict(zip(p["quantity"], p["unit"]))
    assert units["rotation"] == "deg" and units["distance"] == "m" and units["virtual_depth"] == "D"
    fitted_rows = [k for k, st in enumerate(p["status"]) if st == "fitted"]
    assert fitted_rows and all(np.isfinite(p["std_dev"][k]) for k in fitted_rows if not p["derived"][k])
    assert fitted["report"]["usable"] and "fitted 420 markers and 68 luminance samples" in fitted["brief"]


def test_the_same_as_the_command(fitted, tmp_path):
    out, report = tmp_path / "calibrated.json", tmp_path / "report.json"
    os.chdir(tmp_path)
    subprocess.run([os.environ["LAYERLAB_COMMAND"], "fit", str(SCENE), str(MEASUREMENTS), "--out", str(out),
                    "--report", str(report)], check=True, capture_output=True)
    written = json.loads(report.read_text())
    p = fitted["parameters"]
    assert [(q["element"], q["quantity"]) for q in written["parameters"]] == list(zip(p["element"], p["quantity"]))
    # The command's report is SI (rad); Python gives angles in degrees, the API's one angle unit.
    for q, unit, value in zip(written["parameters"], p["unit"], p["value"]):
        assert value == pytest.approx(q["value"] * (180 / np.pi if unit == "deg" else 1), rel=1e-12, abs=1e-15)
    # report: report.json's content with its angles in degrees (keys ending _rad or _arcmin renamed _deg).
    def in_degrees(j):
        if isinstance(j, list):
            return [in_degrees(v) for v in j]
        if not isinstance(j, dict):
            return j
        out = {}
        for key, value in j.items():
            scale = 180 / np.pi if key.endswith("_rad") else 1 / 60 if key.endswith("_arcmin") else None
            if scale and isinstance(value, (int, float)):
                out[key.rsplit("_", 1)[0] + "_deg"] = value * scale
            elif scale and isinstance(value, list) and all(isinstance(v, (int, float)) for v in value):
                out[key.rsplit("_", 1)[0] + "_deg"] = [v * scale for v in value]
            else:
                out[key] = in_degrees(value)
        if out.get("unit") == "rad":
            out.update({k: out[k] * 180 / np.pi for k in ("value", "scene_value", "std_dev")
                        if isinstance(out.get(k), (int, float))}, unit="deg")
        return out
    assert fitted["report"]["geometry"] == pytest.approx(in_degrees(written["geometry"]))
    assert any(k.endswith("_deg") for k in json.dumps(fitted["report"]).replace('"', ' ').split())
    # The calibrated scene, as the command writes it in this folder, key order included.
    assert json.dumps(fitted["scene"]) == json.dumps(json.loads(out.read_text()))
    system = layerlab.load_scene(fitted["scene"]).compile()
    assert [l.name for l in system.layers] == ["rear_a", "rear_b", "front_a", "front_b"]


def test_bad_measurements_name_the_place():
    measurements = json.loads(MEASUREMENTS.read_text())
    measurements["captures"][0]["markers"]["rear_x"] = measurements["captures"][0]["markers"].pop("rear_a")
    with pytest.raises(layerlab.SceneError) as info:
        layerlab.fit(SCENE, measurements)
    assert info.value.file == "<dict>" and info.value.pointer == "/captures/0/markers/rear_x"
    assert "rear_a" in info.value.message  # did you mean
    measurements = json.loads(MEASUREMENTS.read_text())
    measurements["camera"]["fz"] = 1
    with pytest.raises(layerlab.SceneError) as info:
        layerlab.fit(SCENE, measurements)
    assert info.value.pointer.startswith("/camera")
    with pytest.raises(ValueError, match="loss"):
        layerlab.fit(SCENE, MEASUREMENTS, loss="square")
    with pytest.raises(layerlab.Error):
        layerlab.fit(SCENE, EXAMPLES / "no_such_measurements.json")
