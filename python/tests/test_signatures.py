"""solve() and contrast() name every option in their signatures (issue 47: help() showed **kwargs)."""

import inspect

import pytest

from conftest import SKIP_REASON, has_embree

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)


@pytest.mark.parametrize("name, table", [("solve", "_solve_keywords"), ("contrast", "_contrast_keywords")])
def test_every_option_is_a_typed_keyword_only_parameter(name, table):
    function = getattr(layerlab, name)
    parameters = inspect.signature(function).parameters
    assert not any(p.kind == inspect.Parameter.VAR_KEYWORD for p in parameters.values()), "no **kwargs left"
    keywords = getattr(layerlab._layerlab, table)
    assert keywords, "the option table is empty"
    for option, annotation, _ in keywords:
        p = parameters[option]
        assert p.kind == inspect.Parameter.KEYWORD_ONLY and p.default is None, option
        assert p.annotation is {"int": int, "float": float, "list": list, "bool": bool, "str": str,
                                "object": object}[annotation], option
        assert f"\n  {option}: " in "\n" + function.__doc__, f"{name}()'s docstring lacks {option}"
    assert not function.__doc__.startswith(name + "("), "pybind11's signature line, with **kwargs, is gone"
    assert "time_budget: wall-clock budget (s)" in layerlab.solve.__doc__, "a real option's unit is documented"


@pytest.mark.skipif(not has_embree(), reason="the small scene's target is rendered with Embree")
def test_the_wrapper_passes_options_through_and_leaves_none_out(small_scene_path):
    scene = layerlab.load_scene(small_scene_path)
    layerlab.set_verbosity("quiet")
    try:
        report = layerlab.solve(scene, iterations=2, threads=1, tolerance=None).report
        assert report["iterations"] == 2 and report["threads"] == 1
        with pytest.raises(TypeError, match="unexpected option 'iteration'"):
            layerlab.solve(scene, iteration=2)
    finally:
        layerlab.set_verbosity("normal")


def test_no_signature_names_a_cpp_type():
    """pybind11 writes a C++ type's name ("layerlab::DisplaySystem") where a class was not yet registered."""
    import layerlab._layerlab as module

    lines = []
    for name in dir(module):
        item = getattr(module, name)
        members = [item] + [getattr(item, a) for a in vars(item)] if inspect.isclass(item) else [item]
        for member in members:
            doc = getattr(member, "__doc__", None) or ""
            lines += [line for line in doc.splitlines() if "::" in line]
    assert not lines, lines
