"""layerlab.plot: each figure drawn from the data it is given (the lines' points, the pictures' codes)."""

import os

import numpy as np
import pytest

from conftest import SKIP_REASON, has_embree

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)
matplotlib = pytest.importorskip("matplotlib", reason="python3-matplotlib is not installed")
matplotlib.use("Agg")
import layerlab.plot  # noqa: E402

OUT = os.path.join(os.getcwd(), "plots")


@pytest.fixture(scope="module")
def solution(small_scene_path):
    if not has_embree():
        pytest.skip("the small scene's target is rendered with Embree")
    layerlab.set_verbosity("quiet")
    try:
        return layerlab.solve(layerlab.load_scene(small_scene_path), iterations=3, threads=1)
    finally:
        layerlab.set_verbosity("normal")


def saved(figure, name):
    os.makedirs(OUT, exist_ok=True)
    figure.savefig(os.path.join(OUT, name))
    return figure


def test_patterns_are_the_eyes_orientation_in_srgb(solution):
    figure = saved(layerlab.plot.patterns(solution), "patterns.png")
    shown = [ax.images[0].get_array() for ax in figure.axes if ax.images]
    assert len(shown) == len(solution.system.layers)
    for k, layer in enumerate(solution.system.layers):
        # The eye's orientation by hand: the panel's pixel order with the layer's mirror reversals undone.
        eye = solution.patterns[k]
        if layer.flip_x:
            eye = eye[:, ::-1]
        if layer.flip_y:
            eye = eye[::-1, :]
        np.testing.assert_array_equal(shown[k], layerlab.srgb(eye))
        assert f"{layer.name} ({layer.diopters:.2f} D)" in [ax.get_title() for ax in figure.axes]
    assert any(layer.flip_x or layer.flip_y for layer in solution.system.layers), "a mirrored layer is checked"


def test_psnr_against_time_draws_the_trace_from_iteration_0(solution):
    figure = saved(layerlab.plot.psnr_against_time(solution.report), "psnr.png")
    line = figure.axes[0].lines[0]
    np.testing.assert_array_equal(line.get_xdata(), solution.report["trace"]["seconds"])
    np.testing.assert_array_equal(line.get_ydata(), solution.report["trace"]["psnr_db"])
    assert figure.axes[0].get_ylabel() == "PSNR (dB)"


def test_retina_and_contrast(solution, small_scene_path):
    diopters, images = layerlab.focal_stack(solution, 0.4, 1.6, 0.6, resolution_deg=0.2)
    figure = saved(layerlab.plot.retina(images, diopters), "retina.png")
    shown = [ax.images[0].get_array() for ax in figure.axes if ax.images]
    assert len(shown) == 3
    np.testing.assert_array_equal(shown[1], layerlab.srgb(images[1]))
    with pytest.raises(ValueError, match="3 images but 2 accommodation states"):
        layerlab.plot.retina(images, diopters[:2])
    curves = layerlab.contrast(small_scene_path, peak_uncertainty=False, depths=["0.7 D"], frequencies=["0.5 cpd"])
    figure = saved(layerlab.plot.contrast(curves), "contrast.png")
    lines = figure.axes[0].lines
    assert len(lines) == len(curves)
    for line, curve in zip(lines, curves):
        np.testing.assert_array_equal(line.get_ydata(), curve["contrast"])
        assert (line.get_linestyle() == "--") == (curve["display"] == "natural")
