"""The README's Python command, taken from README.md and run as written from the repository's root."""

import os
import re
import subprocess

import pytest

from conftest import SKIP_REASON, SOURCE_DIR, has_embree

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)


def readme_command():
    lines = (SOURCE_DIR / "README.md").read_text().splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("    PYTHONPATH=build/python /usr/bin/python3 -c"))
    command = []
    for line in lines[start:]:
        command.append(line.strip())
        if not line.endswith("\\"):
            break
    return " ".join(c[:-1].rstrip() if c.endswith("\\") else c for c in command)


@pytest.mark.skipif(not has_embree(), reason="this build has no Embree (the reduced example renders its target)")
def test_the_readme_command_solves_the_shipped_example():
    command = readme_command()
    assert "import layerlab" in command and "examples/small/hybrid_small.json" in command
    # Run as the README says, with this build's module for build/python (the build folder may lie elsewhere).
    command = command.replace("PYTHONPATH=build/python", "PYTHONPATH=" + os.environ["PYTHONPATH"], 1)
    done = subprocess.run(["bash", "-c", command], cwd=SOURCE_DIR, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert re.search(r"hybrid: iteration limit after 10 iterations in [0-9.]+ s, PSNR [0-9.]+ dB", done.stdout), \
        done.stdout
