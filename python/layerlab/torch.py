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
patterns, the retinal operator's transpose). The kernels compute in float32.
A contiguous float32 CPU tensor is handed to the operator as a NumPy view of
its memory (other dtypes and layouts are converted once); the operator then
copies its inputs once into layerlab's own buffers (a pattern and a light
field own their memory), and its results become tensors without a copy, in
the inputs' dtype (torch.result_type over them). Tensors on another device
are refused.
"""

from typing import Sequence, Union

import torch

from . import _layerlab


def _array(tensor, what):
    """A float32 NumPy array of `tensor`'s values: its own memory when it is a contiguous float32 CPU tensor."""
    if not isinstance(tensor, torch.Tensor):
        raise TypeError(f"{what}: expected a torch.Tensor, got {type(tensor).__name__}")
    if tensor.device.type != "cpu":
        raise ValueError(f"{what}: layerlab's kernels run on the CPU; got a tensor on {tensor.device}")
    return tensor.detach().to(torch.float32).contiguous().numpy()


def _result_type(tensors):
    """The dtype of a result computed from `tensors`, by torch's promotion; float32 without any."""
    dtype = torch.float32 if not tensors else tensors[0].dtype
    for t in tensors[1:]:
        dtype = torch.promote_types(dtype, t.dtype)
    return dtype


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
        arrays = [_array(p, f"synthesize: patterns[{k}]") for k, p in enumerate(patterns)]
        ctx.display = display
        ctx.dtypes = [p.dtype for p in patterns]
        ctx.save_for_backward(*patterns)
        dtype = _result_type(patterns)
        return torch.from_numpy(display.forward(arrays)).to(dtype)

    @staticmethod
    @torch.autograd.function.once_differentiable
    def backward(ctx, grad_light_field):
        patterns = ctx.saved_tensors
        if not any(ctx.needs_input_grad[1:]):
            return (None,) + (None,) * len(patterns)
        arrays = [_array(p, f"synthesize: patterns[{k}]") for k, p in enumerate(patterns)]
        grads = ctx.display.adjoint(arrays, _array(grad_light_field, "synthesize: gradient"))
        return (None,) + tuple(torch.from_numpy(g).to(dtype) if need else None
                               for g, need, dtype in zip(grads, ctx.needs_input_grad[1:], ctx.dtypes))


class Retina(torch.autograd.Function):
    """A L: the retinal images of a light field per accommodation state (RetinaOperator.forward); backward:
    A^T dimages (its adjoint)."""

    @staticmethod
    def forward(ctx, eye, light_field):
        array = _array(light_field, "retina: light_field")
        ctx.eye = eye
        ctx.dtype = light_field.dtype
        return torch.from_numpy(eye.forward(array)).to(ctx.dtype)

    @staticmethod
    @torch.autograd.function.once_differentiable
    def backward(ctx, grad_images):
        if not ctx.needs_input_grad[1]:
            return None, None
        return None, torch.from_numpy(ctx.eye.adjoint(_array(grad_images, "retina: gradient"))).to(ctx.dtype)


def synthesize(display: Union[_layerlab.DisplayOperator, _layerlab.System],
               patterns: Sequence[torch.Tensor]) -> torch.Tensor:
    """The light field (views, rows, cols, 3) the display shows with `patterns` (one (rows, cols, 3) tensor
    per layer, System.layers order), differentiable in the patterns. `display`: a layerlab.DisplayOperator
    (made once, reused), or a layerlab.System (an operator made for this call, with its defaults)."""
    display = _display(display)
    if isinstance(patterns, torch.Tensor) or not isinstance(patterns, (list, tuple)):
        raise TypeError(f"synthesize: patterns: expected a list of tensors, one per layer, got "
                        f"{type(patterns).__name__}")
    for k, p in enumerate(patterns):
        if not isinstance(p, torch.Tensor):
            raise TypeError(f"synthesize: patterns[{k}]: expected a torch.Tensor, got {type(p).__name__}")
    return Synthesize.apply(display, *patterns)


def retina(eye: _layerlab.RetinaOperator, light_field: torch.Tensor) -> torch.Tensor:
    """The retinal images (states, rows, cols, 3) of a light field, one per accommodation state of `eye`
    (a layerlab.RetinaOperator), differentiable in the light field."""
    if not isinstance(eye, _layerlab.RetinaOperator):
        raise TypeError(f"retina: eye: expected a layerlab.RetinaOperator, got {type(eye).__name__}")
    if not isinstance(light_field, torch.Tensor):
        raise TypeError(f"retina: light_field: expected a torch.Tensor, got {type(light_field).__name__}")
    return Retina.apply(eye, light_field)


def total_variation(pattern: torch.Tensor) -> torch.Tensor:
    """The anisotropic total variation of a (rows, cols, channels) tensor: the sum of the absolute
    differences of neighbouring pixels along rows and columns."""
    return (pattern[1:] - pattern[:-1]).abs().sum() + (pattern[:, 1:] - pattern[:, :-1]).abs().sum()
