"""ssim and ms_ssim against independent code: SSIM against scikit-image's structural_similarity, MS-SSIM against
the same definition written here over SciPy's Gaussian filter, on random and natural images, to 1e-4."""

import math

import numpy as np
import pytest

from conftest import SKIP_REASON

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)
ndimage = pytest.importorskip("scipy.ndimage", reason="SciPy is not installed")


def skimage_metrics():
    """scikit-image's metrics, for the SSIM tests alone (the others need NumPy and SciPy only)."""
    return pytest.importorskip("skimage.metrics", reason="scikit-image (python3-skimage) is not installed")

WEIGHTS = (0.0448, 0.2856, 0.3001, 0.2363, 0.1333)


def reference_ssim(x, y, data_range=1.0):
    return skimage_metrics().structural_similarity(x, y, gaussian_weights=True, sigma=1.5, use_sample_covariance=False,
                                                 data_range=data_range)


def terms(x, y, data_range):
    """The mean luminance and contrast-structure factors of SSIM, with SciPy's filter (skimage's settings)."""
    blur = lambda a: ndimage.gaussian_filter(a, 1.5, mode="reflect", truncate=3.5)
    ux, uy = blur(x), blur(y)
    vx, vy, vxy = blur(x * x) - ux * ux, blur(y * y) - uy * uy, blur(x * y) - ux * uy
    c1, c2 = (0.01 * data_range) ** 2, (0.03 * data_range) ** 2
    inner = (slice(5, -5), slice(5, -5))
    lum = ((2 * ux * uy + c1) / (ux * ux + uy * uy + c1))[inner].mean()
    cs = ((2 * vxy + c2) / (vx + vy + c2))[inner].mean()
    return lum, cs


def reference_ms_ssim(x, y, data_range=1.0):
    value = 1.0
    for j, w in enumerate(WEIGHTS):
        lum, cs = terms(x, y, data_range)
        value *= max(cs, 0) ** w
        if j == len(WEIGHTS) - 1:
            value *= max(lum, 0) ** w
        else:
            h, v = x.shape[0] // 2 * 2, x.shape[1] // 2 * 2
            half = lambda a: 0.25 * (a[0:h:2, 0:v:2] + a[1:h:2, 0:v:2] + a[0:h:2, 1:v:2] + a[1:h:2, 1:v:2])
            x, y = half(x), half(y)
    return value


def natural_pair():
    """A natural photograph (scikit-image's camera man) and a blurred, noisy copy of it."""
    data = pytest.importorskip("skimage.data", reason="scikit-image (python3-skimage) is not installed")
    x = data.camera().astype(np.float64) / 255
    rng = np.random.default_rng(3)
    y = np.clip(ndimage.gaussian_filter(x, 1.2) + rng.normal(0, 0.03, x.shape), 0, 1)
    return x, y


def random_pair(shape, seed):
    rng = np.random.default_rng(seed)
    x = ndimage.gaussian_filter(rng.random(shape), 2.0)
    return x, np.clip(x + rng.normal(0, 0.05, shape), 0, 1)


@pytest.mark.parametrize("pair", ["natural", "random", "random-odd"])
def test_ssim_is_scikit_images(pair):
    x, y = natural_pair() if pair == "natural" else random_pair((181, 203) if pair == "random-odd" else (64, 96), 7)
    assert layerlab.ssim(x, y) == pytest.approx(reference_ssim(x, y), abs=1e-4)
    assert layerlab.ssim(x, x) == pytest.approx(1.0, abs=1e-12)
    assert layerlab.ssim(x, y, data_range=2.0) == pytest.approx(reference_ssim(x, y, 2.0), abs=1e-4)


@pytest.mark.parametrize("pair", ["natural", "random-odd"])
def test_ms_ssim_is_the_papers(pair):
    x, y = natural_pair() if pair == "natural" else random_pair((181, 203), 11)
    expected = reference_ms_ssim(x, y)
    assert 0 < expected < 1
    assert layerlab.ms_ssim(x, y) == pytest.approx(expected, abs=1e-4)
    assert layerlab.ms_ssim(x, x) == pytest.approx(1.0, abs=1e-12)
    # More blur, less similar.
    z = ndimage.gaussian_filter(x, 3.0)
    assert layerlab.ms_ssim(x, z) < layerlab.ms_ssim(x, ndimage.gaussian_filter(x, 1.0))


def test_bad_inputs_are_refused_naming_what():
    x = np.zeros((200, 200))
    with pytest.raises(layerlab.ArgumentError, match="differ in size"):
        layerlab.ssim(x, np.zeros((200, 199)))
    with pytest.raises(layerlab.ArgumentError, match="at least 176"):
        layerlab.ms_ssim(np.zeros((100, 300)), np.zeros((100, 300)))
    with pytest.raises(layerlab.ArgumentError, match="data range"):
        layerlab.ssim(x, x, data_range=0)
    with pytest.raises(layerlab.ArgumentError, match="not finite"):
        y = x.copy()
        y[3, 4] = np.nan
        layerlab.ssim(x, y)
    with pytest.raises(layerlab.ArgumentError, match="2-D"):
        layerlab.ssim(np.zeros((20, 20, 3)), np.zeros((20, 20, 3)))


def barten(u, luminance, field_x, field_y):
    """Barten's CSF (1999, eq. 3.26) with the standard observer's constants and his pupil, written here apart."""
    d = 5 - 3 * np.tanh(0.4 * np.log(luminance * field_x * field_y / 40 ** 2))
    sigma = np.sqrt((0.5 / 60) ** 2 + (0.08 / 60 * d) ** 2)
    e = np.pi * d ** 2 / 4 * luminance * (1 - (d / 9.7) ** 2 + (d / 12.4) ** 4)
    size = lambda x0: (1 / x0 ** 2 + 1 / 12 ** 2 + u ** 2 / 15 ** 2) ** -0.5
    with np.errstate(divide="ignore"):
        s = (np.exp(-2 * np.pi ** 2 * sigma ** 2 * u ** 2) / 3) / np.sqrt(
            2 / 0.1 / (size(field_x) * size(field_y)) * (1 / (0.03 * 1.2274e6 * e) + 3e-8 / (1 - np.exp(-(u / 7) ** 2))))
    return np.where(u > 0, s, 0.0)


def test_csf_jnd_is_the_definition_over_numpys_fft():
    rng = np.random.default_rng(5)
    rows, cols, pixel_deg, beta = 72, 90, 0.02, 4.0
    reference = 40 * (1 + 0.3 * ndimage.gaussian_filter(rng.random((rows, cols)), 3))
    test = reference * (1 + 0.01 * rng.standard_normal((rows, cols)))
    fy = np.fft.fftfreq(rows, pixel_deg)[:, None]
    fx = np.fft.fftfreq(cols, pixel_deg)[None, :]
    mean = reference.mean()
    weight = barten(np.hypot(fx, fy), mean, cols * pixel_deg, rows * pixel_deg)
    j = np.fft.ifft2(weight * np.fft.fft2((test - reference) / mean)).real
    scale = (math.gamma((beta + 1) / 2) / (np.sqrt(np.pi) * math.gamma(beta / 2 + 1))) ** (1 / beta)
    expected = (np.abs(j) ** beta).mean() ** (1 / beta) / scale
    assert expected > 1
    assert layerlab.csf_jnd(reference, test, pixel_deg) == pytest.approx(expected, rel=1e-9)
    assert layerlab.csf_jnd(reference, reference, pixel_deg) == 0
    with pytest.raises(layerlab.ArgumentError, match="minkowski_exponent"):
        layerlab.csf_jnd(reference, test, pixel_deg, minkowski_exponent=0.5)
