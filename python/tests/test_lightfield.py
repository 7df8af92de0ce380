"""Light fields: NumPy views of layerlab's buffers, wrapping arrays, the folder format, rendering."""

import gc

import numpy as np
import pytest

from conftest import EXAMPLES, SKIP_REASON, has_embree

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)


def geometry(views_x=3, views_y=2, cols=5, rows=4):
    return layerlab.LightFieldGeometry(origin_z=1.0, window_left=-0.2, window_top=0.1, window_width=0.4,
                                       window_height=0.2, cols=cols, rows=rows, views_x=views_x, views_y=views_y)


def ramp(g):
    return np.arange(np.prod(g.shape), dtype=np.float32).reshape(g.shape) / 100


def test_a_new_light_field_is_black_and_its_rgb_a_view():
    g = geometry()
    lf = layerlab.LightField(g)
    assert g.shape == (6, 4, 5, 3)
    rgb = lf.rgb
    assert rgb.shape == g.shape and rgb.dtype == np.float32 and not rgb.any()
    assert rgb.flags.c_contiguous and rgb.flags.writeable
    # The same buffer every time, and the view of one view lies inside it.
    assert lf.rgb.ctypes.data == rgb.ctypes.data
    rgb[1 * 3 + 2, 3, 4, 1] = 7.5  # view row 1, column 2
    assert lf.view(1, 2)[3, 4, 1] == 7.5
    assert np.shares_memory(lf.view(1, 2), lf.rgb)
    assert lf.depth is None
    with pytest.raises(IndexError):
        lf.view(2, 0)


def test_a_view_keeps_its_light_field_alive():
    rgb = layerlab.LightField(geometry()).rgb
    gc.collect()
    rgb[:] = 0.25  # writes into the buffer the light field still owns
    assert rgb.base is not None and float(rgb.sum()) == pytest.approx(0.25 * rgb.size)


def test_wrapping_an_array_copies_it_once():
    g = geometry()
    a = ramp(g)
    lf = layerlab.LightField(a, g)
    np.testing.assert_array_equal(lf.rgb, a)
    assert not np.shares_memory(lf.rgb, a)
    a[0, 0, 0, 0] = 99  # the light field holds its own copy
    assert lf.rgb[0, 0, 0, 0] == 0
    # float64 and non-contiguous arrays are converted
    np.testing.assert_allclose(layerlab.LightField(np.asfortranarray(a.astype(np.float64)), g).rgb, a)


def test_a_wrong_shape_names_the_expected_one():
    g = geometry()
    with pytest.raises(ValueError, match=r"expected shape \(6, 4, 5, 3\) \(views, rows, cols, RGB.*got \(6, 5, 4, 3\)"):
        layerlab.LightField(np.zeros((6, 5, 4, 3), np.float32), g)
    with pytest.raises(ValueError, match=r"got \(6, 4, 5\)"):
        layerlab.LightField(np.zeros((6, 4, 5), np.float32), g)


def test_save_and_read_back(tmp_path):
    g = geometry()
    lf = layerlab.LightField(ramp(g), g)
    lf.scene = "a ramp"
    written = lf.save(tmp_path / "lf")
    assert "lightfield.json" in written
    back = layerlab.read_lightfield(tmp_path / "lf")
    assert back.geometry.shape == g.shape and back.geometry.origin_z == g.origin_z
    assert back.geometry.window_width == pytest.approx(g.window_width)
    np.testing.assert_array_equal(back.rgb, lf.rgb)
    assert back.scene == "a ramp"


def test_a_bad_folder_is_an_error(tmp_path):
    with pytest.raises(layerlab.Error, match="lightfield.json"):
        layerlab.read_lightfield(tmp_path)


@pytest.mark.skipif(not has_embree(), reason="this build has no Embree")
def test_render_a_target_scene():
    lf = layerlab.render_target(EXAMPLES / "small" / "small_dice_target.json")
    g = lf.geometry
    assert lf.rgb.shape == (g.views_x * g.views_y, g.rows, g.cols, 3)
    assert np.isfinite(lf.rgb).all() and (lf.rgb >= 0).all() and lf.rgb.max() > 0
    assert lf.depth is not None and lf.depth.shape == lf.rgb.shape[:3]
