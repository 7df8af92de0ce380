"""solve(): patterns and report, the callback, Ctrl-C, the GIL, no copy of the target."""

import gc
import os
import signal
import threading
import time

import numpy as np
import pytest

from conftest import SKIP_REASON, has_embree

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)


def ramps(system):
    """One pattern per layer the display can show: a horizontal ramp, a different slope per layer."""
    patterns = []
    for k, layer in enumerate(system.layers):
        ramp = np.linspace(0.2, 0.9, layer.cols, dtype=np.float32) ** (1 + k)
        patterns.append(np.repeat(np.repeat(ramp[None, :, None], layer.rows, 0), 3, 2))
    return patterns


@pytest.fixture(scope="module")
def target(small_system):
    return layerlab.synthesize(small_system, ramps(small_system))


def test_report_and_patterns_against_numpy(small_system, target):
    solution = layerlab.solve(small_system, target, solver="hybrid", iterations=4, threads=1)
    report = solution.report
    assert report["solver"] == "hybrid" and report["termination"] == "iteration limit"
    assert report["iterations"] == 4
    trace = report["trace"]
    np.testing.assert_array_equal(trace["iteration"], np.arange(5))
    assert np.all(np.diff(trace["seconds"]) >= 0)
    # The objective and PSNR, recomputed here from the patterns and the target.
    patterns = solution.patterns
    assert [p.shape for p in patterns] == [(l.rows, l.cols, 3) for l in small_system.layers]
    assert all(p.dtype == np.float32 and p.min() >= 0 and p.max() <= 1 for p in patterns)
    shown = layerlab.synthesize(small_system, patterns).rgb.astype(np.float64)
    np.testing.assert_array_equal(shown, solution.synthesize().rgb)
    objective = ((shown - target.rgb) ** 2).sum()
    assert report["final_objective"] == pytest.approx(objective, rel=1e-5)
    assert trace["objective"][-1] == report["final_objective"]
    assert report["final_psnr_db"] == pytest.approx(10 * np.log10(target.rgb.size / objective), abs=1e-4)
    assert trace["psnr_db"][-1] == report["final_psnr_db"]
    assert trace["objective"][-1] < trace["objective"][0]


def test_the_target_light_field_is_read_where_it_lies(small_system, target):
    solution = layerlab.solve(small_system, target, iterations=1)
    # The solver read the very light field passed (no copy on the way in).
    assert solution.target is target
    assert solution.target.rgb.ctypes.data == target.rgb.ctypes.data


def test_the_solver_reads_the_arrays_memory(small_system, target):
    # A change written through the NumPy view between two iterations is what the next iteration measures: the
    # solver reads the array's own memory (one copy is made only when target values exceed what the display
    # shows: target_range clip or scale, solvers/objective.h).
    lf = layerlab.LightField(np.array(target.rgb), target.geometry)
    address = lf.rgb.ctypes.data

    def callback(it):
        if it["iteration"] == 0:
            lf.rgb[:] = 0.25
        return it["iteration"] == 1

    solution = layerlab.solve(small_system, lf, iterations=5, callback=callback)
    assert solution.target.rgb.ctypes.data == address
    trace = solution.report["trace"]
    shown = layerlab.synthesize(small_system, solution.patterns).rgb.astype(np.float64)
    assert trace["objective"][1] == pytest.approx(((shown - 0.25) ** 2).sum(), rel=1e-5)
    assert trace["objective"][0] == pytest.approx(
        ((layerlab.synthesize(small_system, [np.full_like(p, 0.5) for p in solution.patterns]).rgb.astype(
            np.float64) - target.rgb) ** 2).sum(), rel=1e-5)


def test_a_numpy_target_of_the_display_geometry(small_system, target):
    array = np.array(target.rgb)
    solution = layerlab.solve(small_system, array, iterations=2)
    np.testing.assert_array_equal(solution.target.rgb, array)  # wrapped: one copy
    with pytest.raises(ValueError, match=r"expected shape \(25, 40, 80, 3\)"):
        layerlab.solve(small_system, array[:, :, :40])


def test_patterns_are_views_that_keep_the_solution_alive(small_system, target):
    solution = layerlab.solve(small_system, target, iterations=1)
    first = solution.patterns[0]
    assert np.shares_memory(first, solution.patterns[0])
    copy = first.copy()
    del solution
    gc.collect()
    np.testing.assert_array_equal(first, copy)


def test_the_callback_sees_every_iteration(small_system, target):
    seen = []
    solution = layerlab.solve(small_system, target, iterations=5, callback=lambda it: seen.append(it))
    trace = solution.report["trace"]
    assert [it["iteration"] for it in seen] == list(range(6))
    assert [it["psnr_db"] for it in seen] == list(trace["psnr_db"])
    assert [it["objective"] for it in seen] == list(trace["objective"])  # the very numbers the trace holds
    assert [it["seconds"] for it in seen] == pytest.approx(list(trace["seconds"]))
    # The objective the callback saw last, recomputed here from the patterns: sum of squared errors.
    shown = layerlab.synthesize(small_system, solution.patterns).rgb.astype(np.float64)
    assert seen[-1]["objective"] == pytest.approx(((shown - target.rgb) ** 2).sum(), rel=1e-5)
    assert seen[-1]["psnr_db"] == pytest.approx(10 * np.log10(target.rgb.size / seen[-1]["objective"]), abs=1e-9)


def test_the_callback_stops_the_solve(small_system, target):
    solution = layerlab.solve(small_system, target, iterations=50, callback=lambda it: it["iteration"] == 3)
    assert solution.report["iterations"] == 3
    assert solution.report["termination"] == "interrupted"
    assert len(solution.report["trace"]["iteration"]) == 4


def test_an_error_in_the_callback_stops_the_solve_and_propagates(small_system, target):
    calls = []

    def callback(it):
        calls.append(it)
        if it["iteration"] == 2:
            raise ZeroDivisionError("from the callback")

    with pytest.raises(ZeroDivisionError, match="from the callback"):
        layerlab.solve(small_system, target, iterations=50, callback=callback)
    assert len(calls) == 3


def test_ctrl_c_interrupts_the_solve_and_keeps_the_last_iteration(small_system, target):
    started = threading.Event()

    def callback(it):
        if it["iteration"] == 2:
            started.set()

    def press_ctrl_c():
        started.wait(60)
        os.kill(os.getpid(), signal.SIGINT)

    presser = threading.Thread(target=press_ctrl_c)
    presser.start()
    try:
        with pytest.raises(KeyboardInterrupt) as info:
            layerlab.solve(small_system, target, iterations=1_000_000, time_budget=60, callback=callback)
    finally:
        presser.join()
    assert isinstance(info.value, layerlab.Interrupted)
    report = info.value.solution.report
    assert report["termination"] == "interrupted" and 2 <= report["iterations"] < 1_000_000
    assert len(info.value.solution.patterns) == len(small_system.layers)


def test_the_gil_is_released_while_solving(small_system, target):
    count = 0
    done = threading.Event()

    def count_while_solving():
        nonlocal count
        while not done.is_set():
            count += 1
            time.sleep(0.001)

    counter = threading.Thread(target=count_while_solving)
    counter.start()
    time.sleep(0.05)
    before = count
    layerlab.solve(small_system, target, iterations=1_000_000, time_budget=0.5)
    during = count - before
    done.set()
    counter.join()
    # Holding the GIL for 0.5 s, the counter would move once or not at all.
    assert during > 20


def test_options_are_checked(small_system, target):
    with pytest.raises(TypeError, match="unexpected option 'iteratons'"):
        layerlab.solve(small_system, target, iteratons=3)
    with pytest.raises(ValueError, match="iterations"):
        layerlab.solve(small_system, target, iterations=-1)
    with pytest.raises(layerlab.Error, match="quasi-newton"):
        layerlab.solve(small_system, target, solver="no-such-solver")
    with pytest.raises(ValueError, match="multiplicative"):
        layerlab.solve(small_system, target, solver="multiplicative")
    assert "hybrid" in layerlab.solvers()


def test_save_writes_what_the_command_writes(small_system, target, tmp_path):
    solution = layerlab.solve(small_system, target, iterations=2)
    written = solution.save(tmp_path / "out")
    assert {"trace.csv", "report.txt", "report.json"} <= set(written)
    assert any(f.startswith("patterns/") for f in written)


@pytest.mark.skipif(not has_embree(), reason="this build has no Embree")
def test_the_scene_solve_section(small_scene_path):
    solution = layerlab.solve(layerlab.load_scene(small_scene_path), iterations=2)
    assert solution.solver == "hybrid" and solution.report["iterations"] == 2
    assert solution.target.rgb.shape == (25, 40, 80, 3)


def test_ctrl_c_without_a_callback(small_system, target):
    # No Python code runs during this solve: the signal is seen by the solve loop's check between iterations.
    presser = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    presser.start()
    try:
        with pytest.raises(layerlab.Interrupted) as info:
            layerlab.solve(small_system, target, iterations=1_000_000, time_budget=60)
    finally:
        presser.join()
    assert info.value.solution.report["iterations"] > 0
    assert info.value.solution.report["seconds"] < 30


def test_retina_of_uniform_patterns(small_system):
    # Every pattern at 0.5 on the half-mirror hybrid: each branch (weight 1) shows 0.5 * 0.5, so the eye sees
    # 0.5 wherever both branches cover its view, at any focus.
    half = [np.full((l.rows, l.cols, 3), 0.5, np.float32) for l in small_system.layers]
    solution = layerlab.solve(small_system, layerlab.synthesize(small_system, half), iterations=1, initial_value=0.5)
    assert all((p == 0.5).all() for p in solution.patterns)
    images = solution.retina([0.4, 1.3], resolution_deg=0.2)
    assert images.dtype == np.float32 and images.shape[0] == 2 and images.shape[3] == 3
    rows, cols = images.shape[1:3]
    np.testing.assert_allclose(images[:, rows // 4:3 * rows // 4, cols // 4:3 * cols // 4], 0.5, rtol=1e-5)
    assert images.shape[2] == pytest.approx(small_system.fov_x_deg / 0.2, abs=1)
    np.testing.assert_array_equal(layerlab.retina(solution, [0.4, 1.3], resolution_deg=0.2), images)
    diopters, stack = layerlab.focal_stack(solution, 0.0, 1.0, 0.5, resolution_deg=0.2, field_deg=(4, 2))
    np.testing.assert_allclose(diopters, [0, 0.5, 1.0])
    assert stack.shape == (3, 10, 20, 3)
    with pytest.raises(ValueError, match="resolution"):
        solution.retina([1.0], resolution_deg=0)


def test_natural_viewing_of_the_target(small_system):
    # Every view the same picture, a function of the column alone, on a light field whose origin plane lies at
    # 1 m: focused there, every pupil point's ray through a retinal sample at angle a meets that plane at
    # x = tan(a) (m), so the eye sees the pixel column holding x, sharp, whatever the pupil.
    g = layerlab.display_geometry(small_system, 1.0)
    assert g.origin_z == pytest.approx(1.0)
    picture = np.random.default_rng(3).uniform(0.1, 0.9, (g.cols, 3)).astype(np.float32)
    lf = layerlab.LightField(g)
    lf.rgb[:] = picture[None, None, :, :]
    solution = layerlab.solve(small_system, lf, iterations=1)
    resolution, field = 0.1, (2.0, 1.0)
    display, natural = solution.retina([1.0, 0.0], resolution_deg=resolution, field_deg=field, natural=True)
    assert natural.shape == display.shape == (2, 10, 20, 3) and natural.dtype == np.float32
    np.testing.assert_array_equal(display, solution.retina([1.0, 0.0], resolution_deg=resolution, field_deg=field))
    angles = np.radians((np.arange(20) + 0.5 - 10) * resolution)
    columns = np.floor((g.origin_z * np.tan(angles) - g.window_left) / (g.window_width / g.cols)).astype(int)
    np.testing.assert_allclose(natural[0], np.broadcast_to(picture[columns], (10, 20, 3)), rtol=2e-5)
    # Focused at infinity the same plane blurs: the columns mix.
    assert np.abs(natural[1] - natural[0]).max() > 0.05
    diopters, images, seen = layerlab.focal_stack(solution, 0.0, 1.0, 1.0, resolution_deg=resolution, field_deg=field,
                                                  natural=True)
    np.testing.assert_array_equal(seen[::-1], natural)
    np.testing.assert_array_equal(images[::-1], display)


def test_the_trace_has_the_columns_of_trace_csv(small_system, target, tmp_path):
    """The dict, the callback's rows and trace.csv name the same columns in one order, with the same values;
    the dict also has the columns this solve did not measure (the focal stack's), NaN, which trace.csv leaves out."""
    seen = []
    solution = layerlab.solve(small_system, target, iterations=2, callback=seen.append)
    solution.save(tmp_path / "out")
    with open(tmp_path / "out" / "trace.csv") as f:
        header = f.readline().strip().split(",")
        rows = [line.strip().split(",") for line in f]
    trace = solution.report["trace"]
    unmeasured = ["focal_stack_psnr_db", "focal_stack_ssim", "focal_stack_ms_ssim", "focal_stack_jnd"]
    assert list(trace.keys()) == header + unmeasured
    for name in unmeasured:
        assert np.all(np.isnan(trace[name])), name
    assert [list(row.keys()) for row in seen] == [list(trace.keys())] * len(rows)
    for k, name in enumerate(header):
        np.testing.assert_allclose([float(r[k]) for r in rows], trace[name], rtol=1e-8, atol=1e-6, err_msg=name)
