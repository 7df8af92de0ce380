"""layerlab's forward model in PyTorch: autograd Functions over its C++ kernels (docs/python.md).

    import layerlab, layerlab.torch
    display = layerlab.DisplayOperator(system)              # patterns -> light field
    eye = layerlab.RetinaOperator(system, [0.4, 1.0, 1.6])  # light field -> retinal images
    patterns = [torch.full(s, 0.5, requires_grad=True) for s in display.pattern_shapes]
    lf = layerlab.torch.synthesize(display, patterns)       # (views, rows, cols, 3)
    images = layerlab.torch.retina(eye, lf)                 # (states, rows, cols, 3)
    loss = (images - target_images).abs().mean()
    loss.backward()                                         # patterns[k].grad: J^T A^T dloss

The forward passes call DisplayOperator.forward and RetinaOperator.forward,
the backward passes their adjoints (the display's Jacobian transpose at the
patterns, the retinal operator's transpose). The kernels compute in float32:
float32 CPU tensors that are contiguous are read without a copy (other
dtypes and layouts are converted once), results are returned without a copy
and in the dtype of the inputs. Tensors on another device are refused.
"""

import torch

from . import _layerlab


def _array(tensor, what):
    """A float32 NumPy array of `tensor`'s values: its own memory when it is a contiguous float32 CPU tensor."""
    if not isinstance(tensor, torch.Tensor):
        raise TypeError(f"{what}: expected a torch.Tensor, got {type(tensor).__name__}")
    if tensor.device.type != "cpu":
        raise ValueError(f"{what}: layerlab's kernels run on the CPU; got a tensor on {tensor.device}")
    return tensor.detach().to(torch.float32).contiguous().numpy()


def _display(display):
    if isinstance(display, _layerlab.DisplayOperator):
        return display
    if isinstance(display, _layerlab.System):
        return _layerlab.DisplayOperator(display)
    raise TypeError(f"synthesize: display: expected a layerlab.DisplayOperator or layerlab.System, "
                    f"got {type(display).__name__}")


class Synthesize(torch.autograd.Function):
    """L(t): the light field of patterns t (DisplayOperator.forward); backward: J(t)^T dL (its adjoint)."""

    @staticmethod
    def forward(ctx, display, *patterns):
        ctx.display = display
        ctx.dtype = patterns[0].dtype if patterns else torch.float32
        ctx.save_for_backward(*patterns)
        arrays = [_array(p, f"synthesize: patterns[{k}]") for k, p in enumerate(patterns)]
        return torch.from_numpy(display.forward(arrays)).to(ctx.dtype)

    @staticmethod
    @torch.autograd.function.once_differentiable
    def backward(ctx, grad_light_field):
        patterns = ctx.saved_tensors
        if not any(ctx.needs_input_grad[1:]):
            return (None,) + (None,) * len(patterns)
        arrays = [_array(p, f"synthesize: patterns[{k}]") for k, p in enumerate(patterns)]
        grads = ctx.display.adjoint(arrays, _array(grad_light_field, "synthesize: gradient"))
        return (None,) + tuple(torch.from_numpy(g).to(ctx.dtype) if need else None
                               for g, need in zip(grads, ctx.needs_input_grad[1:]))


class Retina(torch.autograd.Function):
    """A L: the retinal images of a light field per accommodation state (RetinaOperator.forward); backward:
    A^T dimages (its adjoint)."""

    @staticmethod
    def forward(ctx, eye, light_field):
        ctx.eye = eye
        ctx.dtype = light_field.dtype
        return torch.from_numpy(eye.forward(_array(light_field, "retina: light_field"))).to(ctx.dtype)

    @staticmethod
    @torch.autograd.function.once_differentiable
    def backward(ctx, grad_images):
        if not ctx.needs_input_grad[1]:
            return None, None
        return None, torch.from_numpy(ctx.eye.adjoint(_array(grad_images, "retina: gradient"))).to(ctx.dtype)


def synthesize(display, patterns):
    """The light field (views, rows, cols, 3) the display shows with `patterns` (one (rows, cols, 3) tensor
    per layer, System.layers order), differentiable in the patterns. `display`: a layerlab.DisplayOperator
    (made once, reused), or a layerlab.System (an operator made for this call, with its defaults)."""
    display = _display(display)
    patterns = list(patterns)
    return Synthesize.apply(display, *patterns)


def retina(eye, light_field):
    """The retinal images (states, rows, cols, 3) of a light field, one per accommodation state of `eye`
    (a layerlab.RetinaOperator), differentiable in the light field."""
    if not isinstance(eye, _layerlab.RetinaOperator):
        raise TypeError(f"retina: eye: expected a layerlab.RetinaOperator, got {type(eye).__name__}")
    return Retina.apply(eye, light_field)


def total_variation(pattern):
    """The anisotropic total variation of a (rows, cols, channels) tensor: the sum of the absolute
    differences of neighbouring pixels along rows and columns."""
    return (pattern[1:] - pattern[:-1]).abs().sum() + (pattern[:, 1:] - pattern[:, :-1]).abs().sum()
