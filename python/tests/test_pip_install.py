"""`pip install .` (pyproject.toml, setup.py) offline with Debian's setuptools into a virtual environment on
Debian's Python with its site packages, and `python3 -m build --wheel`: the package then imports from any
folder, with its stubs, and the source tree is left as it was. LAYERLAB_BUILD_DIR hands setup.py the module
this build made, so no compiler runs here (setup.py's CMake path is the same commands scripts/setup.sh runs)."""

import os
import pathlib
import subprocess
import sys
import zipfile

import pytest

from conftest import SKIP_REASON, SOURCE_DIR, layerlab

pytestmark = pytest.mark.skipif(layerlab is None, reason=SKIP_REASON)


def build_dir():
    return pathlib.Path(layerlab.__file__).resolve().parents[2]


def clean_env():
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PIP_REQUIRE_VIRTUALENV")}
    env["LAYERLAB_BUILD_DIR"] = str(build_dir())
    env["PIP_NO_INDEX"] = "1"  # offline: nothing from PyPI
    return env


def source_listing():
    """Every path under the source tree outside build folders and .git, with its modification time."""
    listing = {}
    for root, dirs, files in os.walk(SOURCE_DIR):
        dirs[:] = [d for d in dirs if not (root == str(SOURCE_DIR) and (d.startswith("build") or d == ".git"))]
        for f in files:
            p = os.path.join(root, f)
            listing[p] = os.stat(p).st_mtime_ns
    return listing


def needs(module):
    found = subprocess.run([sys.executable, "-c", f"import {module}"], capture_output=True).returncode == 0
    return pytest.mark.skipif(not found, reason=f"{module} is not installed (scripts/setup.sh installs it)")


@needs("venv")
@needs("pip")
def test_pip_install_into_a_virtual_environment(tmp_path):
    before = source_listing()
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True)
    python = str(venv / "bin" / "python")
    install = subprocess.run([python, "-m", "pip", "install", "--no-build-isolation", "--no-deps", str(SOURCE_DIR)],
                             capture_output=True, text=True, env=clean_env(), cwd=tmp_path)
    assert install.returncode == 0, install.stdout + install.stderr
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    probe = ("import layerlab, pathlib; p = pathlib.Path(layerlab.__file__).parent; "
             "print(p); print(sorted(f.name for f in p.iterdir() if f.suffix in ('.pyi', '.typed')));"
             "print(layerlab.__version__)")
    seen = subprocess.run([python, "-c", probe], capture_output=True, text=True, cwd=elsewhere,
                          env={k: v for k, v in clean_env().items() if k != "LAYERLAB_BUILD_DIR"})
    assert seen.returncode == 0, seen.stderr
    where, stubs, version = seen.stdout.split("\n")[:3]
    assert where.startswith(str(venv)), f"layerlab imported from {where}, not the environment"
    assert stubs == "['__init__.pyi', '_layerlab.pyi', 'py.typed']"
    assert version == layerlab.__version__
    # The installed package works from there: compile and synthesize a shipped example.
    use = ("import sys, layerlab, numpy; s = layerlab.load_scene(sys.argv[1]).compile(); "
           "op = layerlab.DisplayOperator(s); print(layerlab.__file__); "
           "print(op.forward([numpy.full(p, 0.5, numpy.float32) for p in op.pattern_shapes]).shape)")
    scene = SOURCE_DIR / "examples" / "multiplicative_2layer.json"
    used = subprocess.run([python, "-c", use, str(scene)], capture_output=True, text=True, cwd=elsewhere,
                          env={k: v for k, v in clean_env().items() if k != "LAYERLAB_BUILD_DIR"})
    assert used.returncode == 0, used.stderr
    module, shape = used.stdout.split("\n")[:2]
    assert module.startswith(str(venv))
    assert shape == str(layerlab.DisplayOperator(layerlab.load_scene(scene).compile()).light_field_shape)
    assert source_listing() == before, "pip install wrote into or changed the source tree"


@needs("build")
def test_build_a_wheel(tmp_path):
    before = source_listing()
    made = subprocess.run([sys.executable, "-m", "build", "--wheel", "--no-isolation", "--outdir", str(tmp_path),
                           str(SOURCE_DIR)], capture_output=True, text=True, env=clean_env(), cwd=tmp_path)
    assert made.returncode == 0, made.stdout + made.stderr
    wheels = list(tmp_path.glob("layerlab-*.whl"))
    assert len(wheels) == 1
    names = set(zipfile.ZipFile(wheels[0]).namelist())
    for f in ("__init__.py", "__init__.pyi", "_layerlab.pyi", "py.typed", "torch.py", "plot.py", "errors.py"):
        assert f"layerlab/{f}" in names
    assert any(n.startswith("layerlab/_layerlab") and n.endswith(".so") for n in names)
    assert source_listing() == before, "building the wheel wrote into or changed the source tree"


def test_setup_py_names_a_missing_module(tmp_path):
    """LAYERLAB_BUILD_DIR without a built module: setup.py says what is missing, nothing is built."""
    env = dict(clean_env(), LAYERLAB_BUILD_DIR=str(tmp_path / "empty"))
    (tmp_path / "empty").mkdir()
    failed = subprocess.run([sys.executable, "-m", "build", "--wheel", "--no-isolation", "--outdir", str(tmp_path),
                             str(SOURCE_DIR)], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert failed.returncode != 0
    assert "expected one _layerlab" in failed.stdout + failed.stderr and "module in" in failed.stdout + failed.stderr
