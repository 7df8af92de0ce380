"""layerlab.torch (python/layerlab/torch.py): the autograd Functions over DisplayOperator and RetinaOperator,
checked by torch.autograd.gradcheck on small systems of every display kind, by the chain of adjoints by hand,
and for zero-copy reads."""

import numpy as np
import pytest

from conftest import EXAMPLES, SKIP_REASON, layerlab
from test_operators import KINDS, random_patterns, shrunk

pytestmark = pytest.mark.skipif(layerlab is None, reason=SKIP_REASON)
torch = pytest.importorskip("torch", reason="PyTorch (Debian's python3-torch) is not installed")
import layerlab.torch as ltorch  # noqa: E402


@pytest.fixture(scope="module", params=sorted(KINDS))
def display(request):
    path, extra, options = KINDS[request.param]
    return layerlab.DisplayOperator(shrunk(path, **extra), **options)


def test_gradcheck_synthesize(display):
    """torch.autograd.gradcheck in double: the analytic Jacobian (the adjoint, column by column) against
    central differences. The kernels compute in float32, so the step is 1e-2, not 1e-6: the map is affine in
    each single value, so the central difference is exact for any step and only float32 rounding remains."""
    rng = np.random.default_rng(5)
    patterns = [torch.tensor(p, dtype=torch.float64, requires_grad=True) for p in random_patterns(display, rng)]
    assert torch.autograd.gradcheck(lambda *t: ltorch.synthesize(display, t), patterns, eps=1e-2, atol=2e-5,
                                    rtol=1e-4)


def test_gradcheck_retina():
    system = shrunk(EXAMPLES / "small" / "hybrid_small.json", cols=8, rows=5, views=3, pupil=3)
    eye = layerlab.RetinaOperator(system, [0.4, 1.9])
    x = torch.tensor(np.random.default_rng(2).uniform(0, 1, eye.geometry.shape), requires_grad=True)
    assert torch.autograd.gradcheck(lambda lf: ltorch.retina(eye, lf), (x,), eps=1e-2, atol=2e-5, rtol=1e-4)


def test_gradient_through_both_matches_numpy_chain():
    """loss = sum(w * A L(t)): the patterns' gradient from backward() is J^T A^T w, chained by hand."""
    system = layerlab.load_scene(EXAMPLES / "small" / "hybrid_small.json").compile()
    display, eye = layerlab.DisplayOperator(system), layerlab.RetinaOperator(system, [0.5, 1.5])
    rng = np.random.default_rng(9)
    t = random_patterns(display, rng)
    w = rng.standard_normal(eye.images_shape).astype(np.float32)
    patterns = [torch.from_numpy(p.copy()).requires_grad_() for p in t]
    (ltorch.retina(eye, ltorch.synthesize(display, patterns)) * torch.from_numpy(w)).sum().backward()
    expected = display.adjoint(t, eye.adjoint(w))
    for p, e in zip(patterns, expected):
        np.testing.assert_allclose(p.grad.numpy(), e, rtol=1e-5, atol=1e-6)


def test_float32_tensors_are_read_without_a_copy_and_results_returned_without_one():
    system = shrunk(EXAMPLES / "multiplicative_2layer.json")
    display = layerlab.DisplayOperator(system)
    p = torch.rand(display.pattern_shapes[0])
    assert ltorch._array(p, "p").__array_interface__["data"][0] == p.data_ptr()
    lf = ltorch.synthesize(display, [p, torch.rand(display.pattern_shapes[1])])
    assert lf.dtype == torch.float32 and tuple(lf.shape) == display.light_field_shape


def test_torch_arguments_are_named():
    system = shrunk(EXAMPLES / "multiplicative_2layer.json")
    with pytest.raises(TypeError, match="display: expected a layerlab.DisplayOperator or layerlab.System, got str"):
        ltorch.synthesize("scene.json", [])
    with pytest.raises(TypeError, match="patterns: expected a list of tensors"):
        ltorch.synthesize(system, torch.zeros(3))
    with pytest.raises(TypeError, match="light_field: expected a torch.Tensor, got list"):
        ltorch.retina(layerlab.RetinaOperator(system, [1.0]), [0.5])
    with pytest.raises(TypeError, match=r"patterns\[0\]: expected a torch.Tensor, got ndarray"):
        ltorch.synthesize(system, [np.zeros((4, 6, 3)), np.zeros((4, 6, 3))])
    with pytest.raises(TypeError, match="eye: expected a layerlab.RetinaOperator"):
        ltorch.retina(system, torch.zeros(1))


def test_gradients_only_where_asked_and_in_each_inputs_dtype():
    """A pattern that needs no gradient gets none; the light field comes in the inputs' promoted dtype and
    each gradient in its pattern's; a float64 or non-contiguous pattern is read as the same values."""
    system = shrunk(EXAMPLES / "multiplicative_2layer.json")
    display = layerlab.DisplayOperator(system)
    rng = np.random.default_rng(6)
    t = random_patterns(display, rng)
    front = torch.from_numpy(t[0].astype(np.float64)).requires_grad_()
    rear = torch.from_numpy(t[1].copy())  # no gradient asked
    lf = ltorch.synthesize(display, [front, rear])
    assert lf.dtype == torch.float64
    w = torch.from_numpy(rng.standard_normal(display.light_field_shape))
    (lf * w).sum().backward()
    assert rear.grad is None and front.grad.dtype == torch.float64
    expected = display.adjoint(t, w.numpy().astype(np.float32))[0]
    np.testing.assert_allclose(front.grad.numpy(), expected, rtol=1e-5, atol=1e-6)
    # A non-contiguous view (a transposed array's transpose) holds the same values: the same light field.
    strided = torch.from_numpy(np.ascontiguousarray(t[1].transpose(1, 0, 2))).transpose(0, 1)
    assert not strided.is_contiguous()
    np.testing.assert_array_equal(ltorch.synthesize(display, [torch.from_numpy(t[0]), strided]).numpy(),
                                  display.forward(t))


def test_a_broadcast_gradient_reaches_the_patterns():
    """lf.sum() hands backward a gradient of stride 0 (one value broadcast): read as the ones it stands for."""
    system = shrunk(EXAMPLES / "additive_2layer.json")
    display = layerlab.DisplayOperator(system)
    t = random_patterns(display, np.random.default_rng(8))
    patterns = [torch.from_numpy(p.copy()).requires_grad_() for p in t]
    ltorch.synthesize(display, patterns).sum().backward()
    ones = np.ones(display.light_field_shape, np.float32)
    for p, e in zip(patterns, display.adjoint(t, ones)):
        np.testing.assert_allclose(p.grad.numpy(), e, rtol=1e-6)
