"""Shared fixtures. Without the compiled module (LAYERLAB_WITH_PYTHON=OFF, or
PYTHONPATH not pointing at build/python) every test file is skipped with a
reason (pytest.importorskip), unless LAYERLAB_PYTHON_REQUIRED is set (ctest
sets it): then a module that does not import is an error."""

import os
import pathlib

import pytest

try:
    import layerlab
except ImportError:
    if os.environ.get("LAYERLAB_PYTHON_REQUIRED"):
        raise
    layerlab = None

SKIP_REASON = ("layerlab module not importable: build with LAYERLAB_WITH_PYTHON and set "
               "PYTHONPATH=build/python (docs/python.md)")

SOURCE_DIR = pathlib.Path(os.environ.get("LAYERLAB_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
EXAMPLES = SOURCE_DIR / "examples"


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
