"""DisplayOperator and RetinaOperator (python/src/operators.cpp) and their PyTorch Functions
(python/layerlab/torch.py), on small systems of every display kind: the adjoint identity
<J x, y> = <x, J^T y> against the forward map alone, and torch.autograd.gradcheck against
central differences."""

import copy
import json

import numpy as np
import pytest

from conftest import EXAMPLES, SKIP_REASON, layerlab

pytestmark = pytest.mark.skipif(layerlab is None, reason=SKIP_REASON)


def shrunk(path, cols=6, rows=4, views=2, pupil=2, **extra):
    """The example scene at `path` with panels of cols x rows pixels (the same active width), views x views
    views and pupil x pupil pupil samples: small enough for a dense Jacobian."""
    scene = json.loads(path.read_text())
    for e in scene["elements"]:
        if e["type"] == "lc_panel":
            active = e.pop("active_region", None)
            wide = active["cols"] if active else e["resolution"][0]
            pitch = float(e["pixel_pitch"].split()[0]) * wide / cols
            e["pixel_pitch"] = f"{pitch} {e['pixel_pitch'].split()[1]}"
            e["resolution"] = [cols, rows]
            e.update(extra.get("panel", {}))
        if e["type"] == "eye":
            e["views"] = [views, views]
            e["pupil_samples"] = [pupil, pupil]
    scene.update(extra.get("scene", {}))
    return layerlab.load_scene(scene, file=path.name).compile()


# Every display kind: multiplicative, additive, hybrid (half mirror; PBS with per-channel weights), time-
# multiplexed (subframes as branches), and the panels' diffraction and LC response in the map.
KINDS = {
    "multiplicative": (EXAMPLES / "multiplicative_2layer.json", {}, {}),
    "additive": (EXAMPLES / "additive_2layer.json", {}, {}),
    "hybrid": (EXAMPLES / "small" / "hybrid_small.json", {}, {}),
    "hybrid_pbs": (EXAMPLES / "small" / "hybrid_pbs_hwp_small.json", {}, {}),
    "subframes": (EXAMPLES / "tensor_display_rank2.json", {}, {}),
    "diffraction": (EXAMPLES / "multiplicative_2layer.json", {"panel": {"fill_factor": 0.6}},
                    {"panel_diffraction": True}),
    # Equal rise and fall times: the response is linear in the driven patterns (unequal ones: below).
    "lc_response": (EXAMPLES / "tensor_display_rank2.json", {"panel": {"rise_time": "5 ms", "fall_time": "5 ms"}},
                    {"lc_response": True}),
}


@pytest.fixture(scope="module", params=sorted(KINDS))
def display(request):
    path, extra, options = KINDS[request.param]
    op = layerlab.DisplayOperator(shrunk(path, **extra), **options)
    for name, asked in options.items():
        assert getattr(op, name) == asked, f"{request.param}: {name} not in the map"
    return op


def random_patterns(op, rng):
    return [rng.uniform(0.1, 0.9, s).astype(np.float32) for s in op.pattern_shapes]


def test_display_adjoint_identity(display):
    """<J x, v> = <x, J^T v> for each layer, J x formed from the forward map alone: the map is affine in
    one layer's pattern, so J_a x = L(t with t_a = x) - L(t with t_a = 0) (a layer shown in several
    subframes is one pattern per subframe)."""
    rng = np.random.default_rng(7)
    t = random_patterns(display, rng)
    v = rng.standard_normal(display.light_field_shape).astype(np.float32)
    gradient = display.adjoint(t, v)
    for a in range(len(t)):
        x = rng.standard_normal(t[a].shape).astype(np.float32)
        with_x, with_zero = list(t), list(t)
        with_x[a], with_zero[a] = x, np.zeros_like(x)
        jx = display.forward(with_x).astype(np.float64) - display.forward(with_zero)
        lhs = np.sum(jx * v)
        rhs = np.sum(x.astype(np.float64) * gradient[a])
        assert abs(lhs - rhs) <= 1e-6 * abs(lhs), f"layer {a}: <J x, v> = {lhs}, <x, J^T v> = {rhs}"


def test_display_adjoint_of_a_small_gradient(display):
    """A mean loss over millions of rays hands the adjoint a v far below the light: the adjoint is linear, so
    J^T (1e-7 v) is 1e-7 J^T v, kept to float precision (formed as L - v without scaling, v's digits below
    L's last would round away)."""
    rng = np.random.default_rng(3)
    t = random_patterns(display, rng)
    v = rng.standard_normal(display.light_field_shape).astype(np.float32)
    big = display.adjoint(t, v)
    small = display.adjoint(t, (v * np.float32(1e-7)).astype(np.float32))
    for a, (g, h) in enumerate(zip(big, small)):
        np.testing.assert_allclose(h.astype(np.float64) * 1e7, g, rtol=1e-5, atol=1e-5 * np.abs(g).max(),
                                   err_msg=f"layer {a}")
    zero = display.adjoint(t, np.zeros(display.light_field_shape, np.float32))
    assert all(not z.any() for z in zero)


def test_display_forward_is_synthesize_on_the_plain_model():
    """DisplayOperator.forward is layerlab.synthesize where both apply (no diffraction, no response)."""
    system = layerlab.load_scene(EXAMPLES / "small" / "hybrid_small.json").compile()
    op = layerlab.DisplayOperator(system)
    t = random_patterns(op, np.random.default_rng(3))
    np.testing.assert_array_equal(op.forward(t), layerlab.synthesize(system, t).rgb)


def test_retina_adjoint_identity():
    system = layerlab.load_scene(EXAMPLES / "small" / "hybrid_small.json").compile()
    eye = layerlab.RetinaOperator(system, [0.0, 0.7, 1.6, 2.6])
    rng = np.random.default_rng(11)
    x = rng.standard_normal(eye.geometry.shape).astype(np.float32)
    y = rng.standard_normal(eye.images_shape).astype(np.float32)
    lhs = np.sum(eye.forward(x).astype(np.float64) * y)
    rhs = np.sum(x.astype(np.float64) * eye.adjoint(y))
    assert abs(lhs - rhs) <= 1e-6 * abs(lhs)


def test_retina_of_a_uniform_light_field_is_uniform():
    """Every retinal sample is a mean of light-field values with weights summing to 1 (a sample inside the
    window): a uniform light field gives the same value there, at every focus."""
    system = layerlab.load_scene(EXAMPLES / "small" / "hybrid_small.json").compile()
    eye = layerlab.RetinaOperator(system, [0.4, 1.3])
    images = eye.forward(np.full(eye.geometry.shape, 0.25, np.float32))
    centre = images[:, images.shape[1] // 4: -images.shape[1] // 4, images.shape[2] // 4: -images.shape[2] // 4]
    np.testing.assert_allclose(centre, 0.25, rtol=1e-5)


def test_bad_arguments_are_named():
    system = shrunk(EXAMPLES / "multiplicative_2layer.json")
    op = layerlab.DisplayOperator(system)
    t = random_patterns(op, np.random.default_rng(1))
    with pytest.raises(ValueError, match="expected 2 patterns"):
        op.forward(t[:1])
    bad = [p.copy() for p in t]
    bad[1][2, 3, 1] = np.nan
    with pytest.raises(layerlab.ArgumentError, match=r"forward: pattern 1 \(front\): value at \(2, 3, 1\) is nan"):
        op.forward(bad)
    with pytest.raises(ValueError, match="light_field_gradient: expected shape"):
        op.adjoint(t, np.zeros((1, 2, 3, 3), np.float32))
    with pytest.raises(layerlab.ArgumentError, match="accommodation"):
        layerlab.RetinaOperator(system, [float("nan")])
    with pytest.raises(layerlab.ArgumentError, match="resolution_deg"):
        layerlab.RetinaOperator(system, [1.0], resolution_deg=-1)
    with pytest.raises(layerlab.ArgumentError, match=r"RetinaOperator: resolution_deg: 1e-09 deg over a field"):
        layerlab.RetinaOperator(system, [1.0], resolution_deg=1e-9)
    for make, said in ((lambda: layerlab.DisplayOperator("scene.json"), "DisplayOperator: system: expected a "
                                                                        "layerlab.System, got str"),
                       (lambda: layerlab.DisplayOperator(system, lc_response=1), "lc_response: expected a bool"),
                       (lambda: layerlab.DisplayOperator(system, geometry=3), "geometry: expected a layerlab."
                                                                             "LightFieldGeometry or None, got int"),
                       (lambda: op.forward(5), r"forward: patterns: expected a list of \(rows, cols, 3\) arrays"),
                       (lambda: layerlab.RetinaOperator(system, "1 D"), "accommodation: expected a list of numbers"),
                       (lambda: layerlab.RetinaOperator(system, [1.0, "2"]), r"accommodation\[1\]: expected a number")):
        with pytest.raises(TypeError, match=said):
            make()


def test_lc_response_adjoint_with_unequal_rise_and_fall():
    """With a rise time unlike the fall time each pixel relaxes by one or the other, as its drive rises or
    falls between subframes: the map is multilinear on each side of those switches, and the adjoint is the
    Jacobian's of the side t lies on. Subframe 0 is driven in [0.1, 0.4] and subframe 1 in [0.6, 0.9], and
    J_a x is the central difference over +-0.05 x (|x| <= 1), so no pixel changes side: on one side the map
    is affine in t_a, the difference exact, and only float32 rounding remains: about 1e-7 of the light over
    0.1, so the identity is held to 1e-6 of ||J x|| ||v||, the bound of <J x, v> (which cancels to 1e-3
    of it for a random v)."""
    system = shrunk(EXAMPLES / "tensor_display_rank2.json", panel={"rise_time": "8 ms", "fall_time": "3 ms"})
    op = layerlab.DisplayOperator(system, lc_response=True)
    assert op.lc_response
    rng = np.random.default_rng(4)
    t = [rng.uniform(*((0.1, 0.4) if layer.branch % 2 == 0 else (0.6, 0.9)), s).astype(np.float32)
         for layer, s in zip(system.layers, op.pattern_shapes)]
    v = rng.standard_normal(op.light_field_shape).astype(np.float32)
    gradient = op.adjoint(t, v)
    for a in range(len(t)):
        x = rng.uniform(-1, 1, t[a].shape).astype(np.float32)
        up, down = list(t), list(t)
        up[a], down[a] = t[a] + 0.05 * x, t[a] - 0.05 * x
        jx = (op.forward(up).astype(np.float64) - op.forward(down)) / 0.1
        lhs, rhs = np.sum(jx * v), np.sum(x.astype(np.float64) * gradient[a])
        bound = np.linalg.norm(jx) * np.linalg.norm(v.astype(np.float64))
        assert abs(lhs - rhs) <= 1e-6 * bound, f"layer {a}: <J x, v> = {lhs}, <x, J^T v> = {rhs}, bound {bound}"


def test_lc_response_forward_against_a_simulated_frame():
    """The response in the map, against the liquid crystal simulated here: each panel a first-order system
    x' = (t - x) / tau (tau = rise time / ln 9, rise = fall), driven by its subframes' values in turn and run
    to its periodic steady state by small Euler steps; the eye sees the frame's mean of each subframe's
    product x_front(s) x_rear(s). Uniform patterns make every ray within the panels alike, so the ratio of
    the light through the response to the instant panels' is the simulated ratio, whatever the branch weights."""
    rise_s, frame_hz, subframes = 5e-3, 60.0, 2
    system = shrunk(EXAMPLES / "tensor_display_rank2.json", views=3, panel={"rise_time": "5 ms", "fall_time": "5 ms"})
    drive = {(0, "front"): 0.2, (0, "rear"): 0.9, (1, "front"): 0.8, (1, "rear"): 0.3}
    t = [np.full(s, drive[(layer.subframe, layer.element)], np.float32)
         for layer, s in zip(system.layers, layerlab.DisplayOperator(system).pattern_shapes)]
    centre = lambda lf: lf[lf.shape[0] // 2, lf.shape[1] // 2, lf.shape[2] // 2, 1]
    instant = centre(layerlab.DisplayOperator(system).forward(t))
    seen = centre(layerlab.DisplayOperator(system, lc_response=True).forward(t))

    tau, sub_s, steps = rise_s / np.log(9), 1 / (frame_hz * subframes), 20000
    dt = sub_s / steps
    x = {"front": 0.5, "rear": 0.5}
    for _ in range(40):  # periods until the cycle repeats
        means = []
        for k in range(subframes):
            total = 0.0
            for _ in range(steps):
                before = x["front"] * x["rear"]
                for panel in x:
                    x[panel] += dt * (drive[(k, panel)] - x[panel]) / tau
                total += 0.5 * (before + x["front"] * x["rear"]) * dt
            means.append(total / sub_s)
    simulated = sum(means) / sum(drive[(k, "front")] * drive[(k, "rear")] for k in range(subframes))
    assert seen / instant == pytest.approx(simulated, rel=2e-4)
    assert abs(simulated - 1) > 0.05  # the response matters here


def test_retina_operator_focuses_where_a_plane_is_sharp():
    """The light field of a grating on a plane at 0.7 D (each ray's value the grating where the ray meets
    the plane, rays named as docs/lightfield-format.md names them): the retinal image's contrast peaks where
    the eye is focused on the plane, at 0.7 D, among states 0.1 D apart."""
    system = layerlab.load_scene(EXAMPLES / "small" / "hybrid_small.json").compile()
    g = layerlab.display_geometry(system)
    g.cols, g.rows, g.views_x, g.views_y = 640, 8, 9, 9
    plane_m, period_deg = 1 / 0.7, 0.3
    period_m = plane_m * np.tan(np.radians(period_deg))
    views_x = -g.eyebox_width / 2 + (np.arange(g.views_x) + 0.5) * g.eyebox_width / g.views_x
    window_x = g.window_left + (np.arange(g.cols) + 0.5) * g.window_width / g.cols
    lf = np.empty(g.shape, np.float32)
    for r in range(g.views_y):
        for c in range(g.views_x):
            on_plane = views_x[c] + (window_x - views_x[c]) * plane_m / g.origin_z
            lf[r * g.views_x + c] = (0.5 + 0.4 * np.cos(2 * np.pi * on_plane / period_m))[None, :, None]
    states = np.round(np.arange(0.2, 1.3, 0.1), 2)
    images = layerlab.RetinaOperator(system, list(states), geometry=g).forward(lf)
    middle = images[:, images.shape[1] // 2, images.shape[2] // 4: -images.shape[2] // 4, 1]
    contrast = middle.std(axis=1)
    assert states[np.argmax(contrast)] == pytest.approx(0.7)
    assert contrast.max() > 1.2 * contrast.min()  # the focus matters at this frequency
