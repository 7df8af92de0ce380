"""run(): the main job of `layerlab run`, the same library call."""

import json

import pytest

from conftest import SKIP_REASON, has_embree

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)


@pytest.mark.skipif(not has_embree(), reason="this build has no Embree (the reduced example renders its target)")
def test_run_the_reduced_example(small_scene_path, tmp_path):
    out = tmp_path / "small"
    outcome = layerlab.run(small_scene_path, out, iterations=3)
    assert outcome["solved"] and outcome["solver"] == "hybrid" and outcome["iterations"] == 3
    assert "index.html" in outcome["written"]
    assert outcome["index_html"].endswith("index.html")
    on_disk = {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()}
    assert set(outcome["written"]) <= on_disk  # beside them the run's own manifest
    report = json.loads((out / "solve" / "report.json").read_text())
    assert report["final_psnr_db"] == pytest.approx(outcome["psnr_db"], abs=1e-9)


def test_run_a_bad_scene_is_an_error(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "layerlab-scene/1", "elements": [{"type": "eye", "name": "eye"}]}')
    with pytest.raises(layerlab.SceneError) as info:
        layerlab.run(bad, tmp_path / "out")
    assert info.value.file == str(bad) and info.value.pointer.startswith("/elements/0")
    assert not (tmp_path / "out").exists()
