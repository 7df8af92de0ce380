"""The shipped type stubs (python/layerlab/*.pyi, PEP 561) against the module's real signatures: they are
what scripts/make_python_stubs.py writes for the module as built (a signature changed without them fails
here), each public name has one, and, with Debian's mypy, a typed use of the API checks and a wrong one is
reported."""

import ast
import os
import pathlib
import subprocess
import sys

import pytest

from conftest import SKIP_REASON, SOURCE_DIR, layerlab

pytestmark = pytest.mark.skipif(layerlab is None, reason=SKIP_REASON)

PACKAGE = SOURCE_DIR / "python" / "layerlab"
STUBS = ("_layerlab.pyi", "__init__.pyi")


def generate(out):
    subprocess.run([sys.executable, str(SOURCE_DIR / "scripts" / "make_python_stubs.py"), str(out)], check=True,
                   capture_output=True, env=dict(os.environ))


def has_ceres():
    return "needs Ceres" not in (layerlab.fit.__doc__ or "")


@pytest.mark.skipif(layerlab is None or not has_ceres(), reason="a build without Ceres binds fit() without its "
                    "options (python/src/fit_missing.cpp); the stubs are those of a full build")
def test_the_shipped_stubs_are_the_modules_signatures(tmp_path):
    generate(tmp_path)
    for name in STUBS:
        shipped = (PACKAGE / name).read_text()
        assert (tmp_path / name).read_text() == shipped, (
            f"python/layerlab/{name} differs from the module's signatures: run "
            "PYTHONPATH=build/python /usr/bin/python3 scripts/make_python_stubs.py")


def test_every_public_name_has_a_stub_and_every_stub_a_name():
    from layerlab import _layerlab

    stubbed = {}
    for name in STUBS:
        tree = ast.parse((PACKAGE / name).read_text())
        stubbed[name] = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
        stubbed[name] |= {a.asname for n in tree.body if isinstance(n, ast.ImportFrom) for a in n.names}
    native = {n for n in vars(_layerlab) if not n.startswith("_")}
    assert native - stubbed["_layerlab.pyi"] == set()
    assert set(layerlab.__all__) - stubbed["__init__.pyi"] == set()
    # Every public name of the package is in __all__, so in the stubs (its submodules apart).
    submodules = {"errors", "plot", "torch"}
    public = {n for n in dir(layerlab) if not n.startswith("_") and n not in submodules
              and not isinstance(getattr(layerlab, n), type(layerlab))}
    assert public - set(layerlab.__all__) == set(), "public names missing from __all__ and the stubs"
    for name in stubbed["__init__.pyi"] - {None}:
        assert hasattr(layerlab, name), f"__init__.pyi names {name}, which layerlab lacks"
    # Each class's members: the stub's methods and properties exist on the class.
    for node in ast.parse((PACKAGE / "_layerlab.pyi").read_text()).body:
        if isinstance(node, ast.ClassDef):
            for member in node.body:
                if isinstance(member, ast.FunctionDef):
                    assert hasattr(getattr(_layerlab, node.name), member.name), f"{node.name}.{member.name}"


def test_the_stubs_carry_the_keyword_signatures():
    tree = ast.parse((PACKAGE / "__init__.pyi").read_text())
    solve = next(n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "solve")
    keywords = {a.arg: ast.unparse(a.annotation) for a in solve.args.kwonlyargs}
    assert keywords["iterations"] == "Optional[int]" and keywords["time_budget"] == "Optional[float]"
    assert ast.unparse(solve.returns) == "Solution"


MYPY_OK = """
import layerlab
layerlab.set_verbosity("quiet")
system: layerlab.System = layerlab.load_scene("scene.json").compile()
fov: float = system.fov_x_deg
op = layerlab.DisplayOperator(system, sampling="bilinear")
solution = layerlab.solve(system, iterations=3)
images = layerlab.retina(solution, [0.4, 1.0], resolution_deg=0.1)
codes = layerlab.srgb(images[0])
eye = layerlab.RetinaOperator(system, [0.4, 1.0], resolution_deg=0.1)
"""
MYPY_WRONG = """
import layerlab
system = layerlab.load_scene("scene.json").compile()
name: int = system.name
layerlab.solve(system, iterations="3")
layerlab.DisplayOperator(system, lc_response="yes")
"""


def has_mypy():
    return subprocess.run([sys.executable, "-c", "import mypy"], capture_output=True).returncode == 0


@pytest.mark.skipif(not has_mypy(), reason="mypy (Debian's python3-mypy) is not installed")
def test_mypy_reads_the_stubs(tmp_path):
    env = dict(os.environ, MYPYPATH=str(pathlib.Path(layerlab.__file__).parent.parent))
    for name, text in (("ok.py", MYPY_OK), ("wrong.py", MYPY_WRONG)):
        (tmp_path / name).write_text(text)
    run = lambda f: subprocess.run([sys.executable, "-m", "mypy", "--no-incremental", "--cache-dir", str(tmp_path / "cache"),
                                    "--follow-imports=silent", str(tmp_path / f)], capture_output=True, text=True,
                                   env=env)
    ok = run("ok.py")
    assert ok.returncode == 0, ok.stdout + ok.stderr
    # The stubs themselves, every error reported (no --follow-imports=silent).
    package = pathlib.Path(layerlab.__file__).parent
    stubs = subprocess.run([sys.executable, "-m", "mypy", "--no-incremental", "--cache-dir", str(tmp_path / "cache"),
                            str(package / "__init__.pyi"), str(package / "_layerlab.pyi")], capture_output=True,
                           text=True, env=env, cwd=tmp_path)
    assert stubs.returncode == 0, stubs.stdout + stubs.stderr
    wrong = run("wrong.py")
    assert wrong.returncode == 1, wrong.stdout + wrong.stderr
    assert 'Incompatible types in assignment (expression has type "str", variable has type "int")' in wrong.stdout
    assert 'Argument "iterations" to "solve" has incompatible type "str"; expected "Optional[int]"' in wrong.stdout
    assert 'Argument "lc_response" to "DisplayOperator" has incompatible type "str"; expected "bool"' in wrong.stdout
