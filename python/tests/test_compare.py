"""compare(): `layerlab compare` as columns, against the command's CSV files and numbers recomputed here."""

import csv
import os
import subprocess

import numpy as np
import pytest

from conftest import EXAMPLES, SKIP_REASON, has_embree

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)

SCENES = [EXAMPLES / "small" / "hybrid_small.json", EXAMPLES / "small" / "hybrid_pbs_hwp_small.json"]


@pytest.fixture(scope="module")
def target_folder(tmp_path_factory, small_system):
    patterns = [np.full((l.rows, l.cols, 3), 0.3 + 0.1 * k, np.float32) for k, l in enumerate(small_system.layers)]
    lf = layerlab.synthesize(small_system, patterns)
    lf.rgb[:, :, ::7] = 0.9  # something to solve for
    folder = tmp_path_factory.mktemp("compare") / "target"
    lf.save(folder)
    return folder


def test_the_table_is_the_commands(target_folder, tmp_path):
    table = layerlab.compare(SCENES, target_folder, solvers=["hybrid", "multiplicative"], iterations=2)
    out = tmp_path / "out"
    subprocess.run([os.environ["LAYERLAB_COMMAND"], "compare", *map(str, SCENES), "--target", str(target_folder),
                    "--solvers", "hybrid,multiplicative", "--iterations", "2", "--out", str(out)], check=True,
                   capture_output=True)
    rows = list(csv.DictReader(open(out / "compare.csv")))
    assert table["display"] == [r["display"] for r in rows] == ["hybrid_small", "hybrid_pbs_hwp_small"]
    assert table["solver"] == [r["solver"] for r in rows] == ["hybrid", "hybrid"]
    assert table["scene"] == [str(s) for s in SCENES]
    np.testing.assert_allclose(table["final_psnr_db"], [float(r["final_psnr_db"]) for r in rows], atol=1e-3)
    np.testing.assert_array_equal(table["iterations"], [int(r["iterations"]) for r in rows])
    np.testing.assert_array_equal(table["subframes"], [int(r["subframes"]) for r in rows])
    np.testing.assert_allclose(table["panel_refresh_hz"], [float(r["panel_refresh_hz"]) for r in rows], atol=1e-3)
    np.testing.assert_allclose(table["luminance_efficiency"], [float(r["luminance_efficiency"]) for r in rows],
                               atol=1e-6)
    np.testing.assert_allclose(table["efficiency"],
                               [[float(r[f"efficiency_{c}"]) for c in "rgb"] for r in rows], atol=1e-6)
    assert table["termination"] == [r["termination"] for r in rows]
    assert table["solver_options"] == [r["solver_options"] for r in rows] == ["shared", "shared"]  # like for like
    # The same warnings, in the same order, as the command wrote after its table.
    written = (out / "compare.txt").read_text().splitlines()
    assert table["warnings"] == [line[len("warning: "):] for line in written if line.startswith("warning: ")]
    # The multiplicative solver does not suit these displays: left out, as the command leaves it out.
    assert len(table["skipped"]) == 2 and all("multiplicative" in s for s in table["skipped"])
    traces = list(csv.DictReader(open(out / "traces.csv")))
    for k, trace in enumerate(table["trace"]):
        mine = [t for t in traces if t["display"] == table["display"][k]]
        np.testing.assert_array_equal(trace["iteration"], [int(t["iteration"]) for t in mine])
        np.testing.assert_allclose(trace["objective"], [float(t["objective"]) for t in mine], rtol=1e-7)
    assert table["table"].splitlines()[0].startswith("display")


def command_csv(tmp_path, scenes, target_args, *extra):
    out = tmp_path / "command"
    subprocess.run([os.environ["LAYERLAB_COMMAND"], "compare", *map(str, scenes), *target_args, *extra,
                    "--out", str(out)], check=True, capture_output=True)
    return list(csv.DictReader(open(out / "compare.csv")))


def test_like_for_like_unless_scene_options(target_folder, tmp_path):
    # hybrid_small's "solve" section asks for 8 iterations; like for like, every row runs the solver's defaults.
    defaults = layerlab.solve(layerlab.load_scene(SCENES[0]).compile(), layerlab.read_lightfield(target_folder),
                              solver="hybrid").report["iterations"]
    assert defaults != 8
    shared = layerlab.compare(SCENES[0], target_folder)
    own = layerlab.compare(SCENES[0], target_folder, scene_options=True)
    assert shared["solver_options"] == ["shared"] and list(shared["iterations"]) == [defaults]
    assert own["solver_options"] == ["scene"] and list(own["iterations"]) == [8]
    # The same rows as the command's, with and without --scene-options.
    for table, extra in ((shared, ()), (own, ("--scene-options",))):
        rows = command_csv(tmp_path / str(len(extra)), [SCENES[0]], ["--target", str(target_folder)], *extra)
        assert [r["solver_options"] for r in rows] == table["solver_options"]
        assert [int(r["iterations"]) for r in rows] == list(table["iterations"])
        np.testing.assert_allclose([float(r["final_psnr_db"]) for r in rows], table["final_psnr_db"], atol=1e-3)


@pytest.mark.skipif(not has_embree(), reason="this build has no Embree (a target scene is rendered)")
def test_a_target_scene_is_rendered_as_the_command_renders_it(tmp_path):
    target_scene = EXAMPLES / "small" / "small_dice_target.json"
    table = layerlab.compare(SCENES[0], target_scene, iterations=2)
    rendered = layerlab.compare(SCENES[0], layerlab.render_target(target_scene), iterations=2)
    np.testing.assert_array_equal(table["final_psnr_db"], rendered["final_psnr_db"])
    rows = command_csv(tmp_path, [SCENES[0]], ["--target-scene", str(target_scene)], "--iterations", "2")
    np.testing.assert_allclose([float(r["final_psnr_db"]) for r in rows], table["final_psnr_db"], atol=1e-3)


def test_each_row_against_its_display(target_folder):
    table = layerlab.compare(SCENES[0], target_folder, iterations=3)
    system = layerlab.load_scene(SCENES[0]).compile()
    scene = layerlab.load_scene(SCENES[0])
    assert table["solver"] == ["hybrid"]  # the scene's own
    trace = table["trace"][0]
    np.testing.assert_array_equal(trace["iteration"], np.arange(4))
    # PSNR from the objective, recomputed: peak 1 over every ray and channel of the target.
    rays = np.prod(layerlab.read_lightfield(target_folder).rgb.shape)
    np.testing.assert_allclose(trace["psnr_db"], 10 * np.log10(rays / trace["objective"]), atol=1e-9)
    assert table["final_psnr_db"][0] == trace["psnr_db"][-1]
    np.testing.assert_allclose(table["efficiency"][0], system.brightness_efficiency, rtol=1e-12)
    assert table["subframes"][0] == scene.subframes
    assert table["panel_refresh_hz"][0] == pytest.approx(scene.subframes * scene.frame_rate_hz)


def test_a_light_field_target_all_solvers_and_the_callback(target_folder):
    lf = layerlab.read_lightfield(target_folder)
    seen = []

    def callback(row):
        seen.append(row)
        return row["iteration"] == 1  # stops the first run there, and the comparison with it

    table = layerlab.compare([SCENES[0]], lf, solvers="all", iterations=5, callback=callback)
    assert len(table["solver"]) == 1 and table["termination"] == ["interrupted"]
    assert [(r["display"], r["iteration"]) for r in seen] == [("hybrid_small", 0), ("hybrid_small", 1)]
    assert [r["objective"] for r in seen] == list(table["trace"][0]["objective"])
    everything = layerlab.compare([SCENES[0]], lf, solvers="all", iterations=1)
    suitable = []
    for name in layerlab.solvers():
        try:
            layerlab.solve(layerlab.load_scene(SCENES[0]).compile(), lf, solver=name, iterations=1)
            suitable.append(name)
        except ValueError:
            pass
    assert sorted(everything["solver"]) == sorted(suitable)


def test_errors(target_folder, tmp_path):
    with pytest.raises(layerlab.Error, match="no-such-solver"):
        layerlab.compare(SCENES, target_folder, solvers="no-such-solver")
    with pytest.raises(ValueError, match="iterations"):
        layerlab.compare(SCENES, target_folder, iterations=0)
    with pytest.raises(layerlab.Error, match="no display and solver"):
        layerlab.compare(SCENES, target_folder, solvers="multiplicative")
    with pytest.raises(layerlab.Error):
        layerlab.compare(SCENES, tmp_path / "no_such_target")
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "layerlab-scene/1", "elements": [{"type": "eye", "name": "eye"}]}')
    with pytest.raises(layerlab.SceneError) as info:
        layerlab.compare([bad], target_folder)
    assert info.value.file == str(bad) and info.value.pointer.startswith("/elements/0")


def test_objectives_each_row_with_both_psnrs(target_folder, tmp_path):
    table = layerlab.compare(SCENES[0], target_folder, solvers=["hybrid", "quasi-newton"],
                             objectives=["lightfield", "retinal"], iterations=1)
    assert table["solver"] == ["hybrid", "quasi-newton", "quasi-newton"]
    assert table["objective"] == ["lightfield", "lightfield", "retinal"]
    assert len(table["skipped"]) == 1 and "hybrid / retinal" in table["skipped"][0]
    # Every row measured the focal stack; its final value is the trace's last.
    for k, trace in enumerate(table["trace"]):
        assert np.all(np.isfinite(trace["focal_stack_psnr_db"]))
        assert table["final_focal_stack_psnr_db"][k] == trace["focal_stack_psnr_db"][-1]
    rows = command_csv(tmp_path, [SCENES[0]], ["--target", str(target_folder)], "--solvers", "hybrid,quasi-newton",
                       "--objectives", "lightfield,retinal", "--iterations", "1")
    assert [r["objective"] for r in rows] == table["objective"]
    np.testing.assert_allclose([float(r["final_focal_stack_psnr_db"]) for r in rows],
                               table["final_focal_stack_psnr_db"], atol=1e-3)
    with pytest.raises(ValueError, match='"retina" is not one of lightfield or retinal'):
        layerlab.compare(SCENES[0], target_folder, objectives="retina")
    plain = layerlab.compare(SCENES[0], target_folder, iterations=1)
    assert plain["objective"] == ["lightfield"] and np.isnan(plain["final_focal_stack_psnr_db"][0])


def test_metrics_beside_psnr_at_the_rows_that_measure_them(target_folder, tmp_path):
    table = layerlab.compare(SCENES[0], target_folder, solvers="hybrid", metrics=["ssim", "jnd"], iterations=6)
    assert "final_focal_stack_ms_ssim" not in table
    trace = table["trace"][0]
    # Measured at iterations 0, 1, 2, 3, 5 (each about 1.5 x the last) and the last, 6; the focal stack's PSNR at all.
    measured = [int(i) for i, v in zip(trace["iteration"], trace["focal_stack_ssim"]) if np.isfinite(v)]
    assert measured == [0, 1, 2, 3, 5, 6]
    assert np.all(np.isfinite(trace["focal_stack_psnr_db"]))
    assert np.array_equal(np.isfinite(trace["focal_stack_jnd"]), np.isfinite(trace["focal_stack_ssim"]))
    assert table["final_focal_stack_ssim"][0] == trace["focal_stack_ssim"][-1]
    assert 0 < trace["focal_stack_ssim"][-1] <= 1 and trace["focal_stack_ssim"][-1] > trace["focal_stack_ssim"][0]
    assert trace["focal_stack_jnd"][-1] < trace["focal_stack_jnd"][0]  # the solve lowers the visible error
    rows = command_csv(tmp_path, [SCENES[0]], ["--target", str(target_folder)], "--solvers", "hybrid", "--metrics",
                       "ssim,jnd", "--iterations", "6")
    np.testing.assert_allclose([float(rows[0]["final_focal_stack_ssim"])], table["final_focal_stack_ssim"], atol=1e-6)
    np.testing.assert_allclose([float(rows[0]["final_focal_stack_jnd"])], table["final_focal_stack_jnd"], rtol=1e-6)
    with pytest.raises(ValueError, match='compare: metrics: "lpips" is not a metric'):
        layerlab.compare(SCENES[0], target_folder, metrics="lpips")
    # A metric the light field's grid is too small for: the solve stands, the metric is left unmeasured, and the
    # warning says why.
    small = layerlab.compare(SCENES[0], target_folder, metrics="ms_ssim", iterations=1)
    assert small["termination"] == ["iteration limit"]
    assert np.all(np.isnan(small["trace"][0]["focal_stack_ms_ssim"]))
    assert any("ms_ssim needs images of at least 176 x 176 samples; these are 80 x 40" in w for w in small["warnings"])


def test_fovea_and_the_jnd_exponent_as_the_commands_and_bad_ones_refused(target_folder, tmp_path):
    args = dict(solvers="hybrid", metrics="jnd", iterations=2)
    plain = layerlab.compare(SCENES[0], target_folder, **args)
    weighted = layerlab.compare(SCENES[0], target_folder, fovea_deg=(3, -2), jnd_exponent=2, **args)
    assert weighted["final_focal_stack_jnd"][0] != plain["final_focal_stack_jnd"][0]
    rows = command_csv(tmp_path, [SCENES[0]], ["--target", str(target_folder)], "--solvers", "hybrid", "--metrics",
                       "jnd", "--iterations", "2", "--fovea", "3,-2", "--jnd-exponent", "2")
    np.testing.assert_allclose([float(rows[0]["final_focal_stack_jnd"])], weighted["final_focal_stack_jnd"], rtol=1e-6)
    with pytest.raises(ValueError, match="compare: jnd_exponent: 0.5.*must be 1 or more"):
        layerlab.compare(SCENES[0], target_folder, jnd_exponent=0.5, **args)
    with pytest.raises(ValueError, match="give metrics"):
        layerlab.compare(SCENES[0], target_folder, solvers="hybrid", fovea_deg=(1, 1))
    # A display of one subframe does not flicker: no verdict.
    assert plain["flicker_visible"] == [None] and np.isnan(plain["flicker_visibility"][0])
