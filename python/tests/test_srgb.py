"""srgb(): the PNGs' 8-bit codes, against IEC 61966-2-1's formula written here in NumPy."""

import numpy as np
import pytest

from conftest import SKIP_REASON

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)


def iec_61966(linear):
    v = np.clip(np.nan_to_num(np.asarray(linear, dtype=np.float64), nan=0.0), 0.0, 1.0)
    encoded = np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)
    return np.round(255 * encoded).astype(np.uint8)  # halves: none among these values


def test_codes_are_the_formulas_and_keep_the_shape():
    rng = np.random.default_rng(7)
    image = rng.uniform(-0.2, 1.3, size=(5, 7, 3)).astype(np.float32)
    codes = layerlab.srgb(image)
    assert codes.dtype == np.uint8 and codes.shape == image.shape
    np.testing.assert_array_equal(codes, iec_61966(image.astype(np.float64)))
    # The edges: black, the linear segment's end (12.92 x 0.0031308 x 255 = 10.3), 0.2158 (255 x 0.5019 = 127.98),
    # white, beyond white, NaN, below black.
    edges = np.array([0.0, 0.0031308, 0.2158, 1.0, 2.0, np.nan, -1.0], dtype=np.float32)
    np.testing.assert_array_equal(layerlab.srgb(edges), [0, 10, 128, 255, 255, 0, 0])


def test_white_scales_and_a_bad_white_is_refused():
    image = np.full((2, 2, 3), 4.0, dtype=np.float32)
    np.testing.assert_array_equal(layerlab.srgb(image, white=8.0), iec_61966(np.full((2, 2, 3), 0.5)))
    with pytest.raises(layerlab.ArgumentError, match="srgb: white"):
        layerlab.srgb(image, white=0.0)
