"""run(): the main job of `layerlab run`, the same library call."""

import csv
import gc
import json

import numpy as np
import pytest

from conftest import SKIP_REASON, has_embree

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)


@pytest.mark.skipif(not has_embree(), reason="this build has no Embree (the reduced example renders its target)")
def test_run_the_reduced_example(small_scene_path, tmp_path):
    out = tmp_path / "small"
    outcome = layerlab.run(small_scene_path, out, iterations=3)
    assert outcome["solved"] and outcome["solver"] == "hybrid" and outcome["iterations"] == 3
    assert "index.html" in outcome["written"]
    assert outcome["index_html"].endswith("index.html")
    on_disk = {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()}
    assert set(outcome["written"]) <= on_disk  # beside them the run's own manifest
    report = json.loads((out / "solve" / "report.json").read_text())
    assert report["final_psnr_db"] == pytest.approx(outcome["psnr_db"], abs=1e-9)
    check_the_arrays_and_tables(outcome, out, small_scene_path)


def rows(path):
    return list(csv.DictReader(open(path)))


def check_the_arrays_and_tables(outcome, out, scene_path):
    """What run() returns beside the files, against the files and against numbers recomputed here."""
    system = layerlab.load_scene(scene_path).compile()
    # The report, with the trace the run wrote.
    trace = rows(out / "solve" / "trace.csv")
    np.testing.assert_array_equal(outcome["report"]["trace"]["iteration"], [int(r["iteration"]) for r in trace])
    np.testing.assert_allclose(outcome["report"]["trace"]["objective"], [float(r["objective"]) for r in trace],
                               rtol=1e-5)
    # The patterns: one float32 (rows, cols, 3) array per layer; shown on the display against the target the
    # run rendered, their squared error is the report's objective.
    patterns = outcome["patterns"]
    assert [p.shape for p in patterns] == [(l.rows, l.cols, 3) for l in system.layers]
    assert all(p.dtype == np.float32 for p in patterns)
    target = layerlab.read_lightfield(out / "target" / "lightfield")
    shown = layerlab.synthesize(system, patterns, target.geometry).rgb.astype(np.float64)
    assert ((shown - target.rgb) ** 2).sum() == pytest.approx(outcome["report"]["final_objective"], rel=1e-5)
    # Retina: the states of retina.csv, the images stacked; their mean luminance (Rec. 709 weights) is the
    # csv's cd/m2 up to the one white level of the display.
    retina = outcome["retina"]
    written = rows(out / "retina" / "retina.csv")
    np.testing.assert_allclose(retina["diopters"], [float(r["accommodation_D"]) for r in written], atol=1e-4)
    np.testing.assert_allclose(retina["display_mean_cd_m2"], [float(r["display_mean_cd_m2"]) for r in written],
                               rtol=1e-5)
    states = len(written)
    # Each state's PSNR: the display's image against natural viewing, over pixels and channels, peak 1.
    error = ((retina["display"].astype(np.float64) - retina["natural"]) ** 2).mean(axis=(1, 2, 3))
    np.testing.assert_allclose(retina["psnr_db"], 10 * np.log10(1 / error), atol=1e-9)
    np.testing.assert_allclose(retina["psnr_db"], [float(r["psnr_db"]) for r in written], atol=1e-4)
    # The metrics the scene's run.retina asks for ("ssim,jnd"): SSIM against scikit-image's on the sRGB-encoded
    # luminance; the JND as csf_jnd() gives it on the luminance in cd/m2 (white from the mean columns).
    structural = pytest.importorskip("skimage.metrics", reason="scikit-image (python3-skimage) is not installed")
    white = retina["display_mean_cd_m2"][0] / (retina["display"][0].astype(np.float64) @ [0.2126, 0.7152, 0.0722]).mean()
    for k in range(states):
        y = [np.maximum(images[k].astype(np.float64) @ [0.2126, 0.7152, 0.0722], 0)
             for images in (retina["display"], retina["natural"])]
        encoded = [np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055) for v in y]
        ssim = structural.structural_similarity(encoded[0], encoded[1], gaussian_weights=True, sigma=1.5,
                                                use_sample_covariance=False, data_range=1.0)
        assert retina["ssim"][k] == pytest.approx(ssim, abs=1e-4)
        assert float(written[k]["ssim"]) == pytest.approx(ssim, abs=2e-6)
        jnd = layerlab.csf_jnd(y[1] * white, y[0] * white, 0.2)
        assert retina["jnd"][k] == pytest.approx(jnd, rel=1e-4)
    assert "ms_ssim" not in retina and "ms_ssim" not in written[0]
    for images, means in ((retina["display"], retina["display_mean_cd_m2"]),
                          (retina["natural"], retina["natural_mean_cd_m2"])):
        assert images.dtype == np.float32 and images.shape[0] == states and images.shape[3] == 3
        luminance = (images.astype(np.float64) @ [0.2126, 0.7152, 0.0722]).mean(axis=(1, 2))
        white = means / luminance
        np.testing.assert_allclose(white, white[0], rtol=1e-6)
    assert (out / "retina" / "display" / (retina["names"][0] + ".exr")).is_file()
    assert f"retina ({states} accommodation states)" in (out / "index.html").read_text()  # the report's steps
    # Contrast: the curves of contrast.csv.
    curves = rows(out / "contrast" / "contrast.csv")
    assert len(outcome["contrast"]) == len({(r["display"], r["target_D"], r["frequency_cpd"]) for r in curves})
    for c in outcome["contrast"]:
        mine = [r for r in curves if r["display"] == c["display"] and float(r["target_D"]) == pytest.approx(
            c["target_diopters"]) and float(r["frequency_cpd"]) == pytest.approx(c["frequency"])]
        np.testing.assert_allclose(c["accommodation"], [float(r["accommodation_D"]) for r in mine], atol=1e-4)
        np.testing.assert_allclose(c["contrast"], [float(r["normalized_contrast"]) for r in mine], atol=1e-6)
    # Compare: the columns of compare.csv.
    compared = rows(out / "compare" / "compare.csv")
    assert outcome["compare"]["display"] == [r["display"] for r in compared]
    assert outcome["compare"]["solver_options"] == [r["solver_options"] for r in compared]
    np.testing.assert_allclose(outcome["compare"]["final_psnr_db"], [float(r["final_psnr_db"]) for r in compared],
                               atol=1e-3)
    assert outcome["compare"]["final_psnr_db"][0] == outcome["psnr_db"]  # the main solve is the first row
    # The patterns are views of the outcome's buffers: they outlive the dict.
    first = patterns[0]
    copy = first.copy()
    assert first.base is not None and not first.flags.owndata
    del outcome, patterns
    gc.collect()
    np.testing.assert_array_equal(first, copy)


def test_run_a_bad_scene_is_an_error(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "layerlab-scene/1", "elements": [{"type": "eye", "name": "eye"}]}')
    with pytest.raises(layerlab.SceneError) as info:
        layerlab.run(bad, tmp_path / "out")
    assert info.value.file == str(bad) and info.value.pointer.startswith("/elements/0")
    assert not (tmp_path / "out").exists()
