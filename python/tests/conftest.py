"""Shared fixtures. Without the compiled module (LAYERLAB_WITH_PYTHON=OFF, or
PYTHONPATH not pointing at build/python) every test is skipped with a reason,
unless LAYERLAB_PYTHON_REQUIRED is set (ctest sets it)."""

import os
import pathlib

import pytest

try:
    import layerlab  # noqa: F401

    _missing = None
except ImportError as e:  # the module is not built, or not on PYTHONPATH
    if os.environ.get("LAYERLAB_PYTHON_REQUIRED"):
        raise
    _missing = str(e)

SOURCE_DIR = pathlib.Path(os.environ.get("LAYERLAB_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
EXAMPLES = SOURCE_DIR / "examples"


def pytest_collection_modifyitems(config, items):
    if _missing:
        skip = pytest.mark.skip(reason=f"layerlab module not importable ({_missing}); build with "
                                       "LAYERLAB_WITH_PYTHON and set PYTHONPATH=build/python")
        for item in items:
            item.add_marker(skip)


@pytest.fixture(scope="session")
def small_scene_path():
    return EXAMPLES / "small" / "hybrid_small.json"


@pytest.fixture(scope="session")
def small_system(small_scene_path):
    return layerlab.load_scene(small_scene_path).compile()


def has_embree():
    """Whether this build renders target scenes (LAYERLAB_WITH_EMBREE)."""
    try:
        layerlab.render_target(EXAMPLES / "no_such_target.json")
    except layerlab.Error as e:
        return "needs Embree" not in str(e)
    return True
