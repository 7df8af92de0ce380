"""set_verbosity(): the C++ core's notes on stderr silenced and restored; a wrong level named."""

import pytest

from conftest import SKIP_REASON, has_embree

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)


@pytest.fixture(autouse=True)
def normal_afterwards():
    yield
    layerlab.set_verbosity("normal")


@pytest.mark.skipif(not has_embree(), reason="the small scene's target is rendered with Embree")
def test_quiet_silences_the_notes_and_normal_brings_them_back(small_scene_path, capfd):
    scene = layerlab.load_scene(small_scene_path)
    assert layerlab.verbosity() == "normal"
    layerlab.solve(scene, iterations=1, threads=1)
    assert "target:" in capfd.readouterr().err, "a solve says what it does on stderr by default"
    layerlab.set_verbosity("quiet")
    assert layerlab.verbosity() == "quiet"
    layerlab.solve(scene, iterations=1, threads=1)
    assert capfd.readouterr().err == ""
    layerlab.set_verbosity("normal")
    layerlab.solve(scene, iterations=1, threads=1)
    assert "target:" in capfd.readouterr().err


def test_a_wrong_level_is_named():
    with pytest.raises(ValueError, match='level "silent" is not one of "quiet", "normal", "verbose"'):
        layerlab.set_verbosity("silent")
    with pytest.raises(TypeError, match="level must be a str"):
        layerlab.set_verbosity(0)
    assert layerlab.verbosity() == "normal"
