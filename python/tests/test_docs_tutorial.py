"""docs/python.md runs: its `python` blocks, in order and in one namespace, in a fresh folder of the build
tree (build/python/tests/tutorial) where examples/ is the repository's; the figures go to its out/. A block
that fails is named by its first line in the page. The page holds no other code than `python` and `sh`
blocks (the sh ones build and install: python.readme and python.pip_install run those)."""

import pathlib
import re
import shutil

import pytest

from conftest import SKIP_REASON, SOURCE_DIR, has_embree, layerlab

pytestmark = pytest.mark.skipif(layerlab is None, reason=SKIP_REASON)

PAGE = SOURCE_DIR / "docs" / "python.md"
FENCE = re.compile(r"^```(\w*)\n(.*?)^```\n", re.M | re.S)


def blocks():
    text = PAGE.read_text()
    return [(m.group(1), text.count("\n", 0, m.start()) + 2, m.group(2)) for m in FENCE.finditer(text)]


def test_every_block_is_python_or_a_command_line():
    kinds = {kind for kind, _, _ in blocks()}
    assert kinds <= {"python", "sh"}, f"docs/python.md has blocks of {kinds - {'python', 'sh'}}"
    # No indented code block (four spaces after a blank line, outside a list): code that no test would run.
    lines = FENCE.sub(lambda m: "\n" * m.group(0).count("\n"), PAGE.read_text()).splitlines()
    indented = [i + 1 for i, line in enumerate(lines)
                if line.startswith("    ") and i > 1 and lines[i - 1] == "" and not lines[i - 2].startswith(("- ", "  "))]
    assert indented == [], f"docs/python.md: indented code at lines {indented}; write it as a python block"


@pytest.mark.skipif(not has_embree(), reason="this build has no Embree: the tutorial renders its target")
def test_the_tutorial_runs(monkeypatch):
    folder = pathlib.Path.cwd() / "tutorial"
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir()
    (folder / "examples").symlink_to(SOURCE_DIR / "examples")
    monkeypatch.chdir(folder)
    ceres = "needs Ceres" not in (layerlab.fit.__doc__ or "")
    namespace = {"__name__": "__tutorial__"}
    python = [(line, body) for kind, line, body in blocks() if kind == "python"]
    assert len(python) >= 10
    for line, body in python:
        if not ceres and "layerlab.fit(" in body:
            continue  # a build without Ceres: fit() says so (python.fit checks that)
        try:
            exec(compile(body, f"docs/python.md:{line}", "exec"), namespace)
        except Exception as e:
            raise AssertionError(f"docs/python.md, the block at line {line}: {type(e).__name__}: {e}") from e
    for figure in ("patterns.png", "psnr.png", "focal_stack.png", "contrast.png", "adam_patterns.png"):
        assert (folder / "out" / figure).stat().st_size > 0
