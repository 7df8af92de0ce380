"""`import layerlab` from an install prefix (ctest: after package.install)."""

import os
import pathlib
import subprocess
import sys

import pytest

from conftest import EXAMPLES, SKIP_REASON

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)

prefix = os.environ.get("LAYERLAB_INSTALL_PREFIX")
site = os.environ.get("LAYERLAB_PYTHON_INSTALL_DIR")


@pytest.mark.skipif(not prefix or not site or not pathlib.Path(prefix).is_dir(),
                    reason="no install prefix (ctest's package.install makes one)")
def test_import_from_the_install_prefix():
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = str(pathlib.Path(prefix) / site)
    code = ("import layerlab; s = layerlab.load_scene(%r).compile(); print(layerlab.__file__); "
            "print(layerlab.__version__, len(s.layers))" % str(EXAMPLES / "small" / "hybrid_small.json"))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True).stdout
    where, summary = out.splitlines()
    assert pathlib.Path(where).resolve().is_relative_to(pathlib.Path(prefix).resolve())
    assert summary == f"{layerlab.__version__} 4"
