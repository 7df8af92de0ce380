"""solve()'s keyword arguments against the solver option table.

The table is read from docs/scene-reference.md's "solve" section, which
docs.scene_reference_current holds to solvers/solver_option_table.cpp: every
Python name of the table is a parameter of solve() or one of its option
keywords, documented in its docstring, and solve() takes no option the table
lacks.
"""
import inspect
import re
from pathlib import Path

import pytest

from conftest import SKIP_REASON

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)

REFERENCE = Path(__file__).resolve().parents[2] / "docs" / "scene-reference.md"
PARAMETERS = {"display", "target", "solver", "sampling", "callback"}  # solve()'s own, in its signature


def python_names():
    """The Python column of the solve section's tables."""
    text = REFERENCE.read_text()
    start = text.index("## `solve`")
    section = text[start:text.index("\n## ", start + 1)]
    names = set()
    for line in section.splitlines():
        cells = [c.strip().strip("`") for c in line.strip().strip("|").split("|")]
        if len(cells) == 8 and cells[0] not in ("key", "---") and cells[7]:
            names.add(cells[7])
    assert names, f"no solve option table in {REFERENCE}"
    return names


def test_every_python_name_of_the_table_is_a_keyword_and_no_other(small_system):
    table = python_names()
    signature = str(inspect.signature(layerlab.solve))
    own = {name for name in PARAMETERS if re.search(rf"\b{name}\b", signature)}
    assert own == PARAMETERS, signature
    options = table - PARAMETERS
    with pytest.raises(TypeError, match="unexpected option 'no_such_option'") as refused:
        layerlab.solve(small_system, None, no_such_option=1)
    listed = set(str(refused.value).split("options: ", 1)[1].split(", "))
    assert listed == options, "solve()'s option keywords differ from the table's Python names"
    for name in table & PARAMETERS:
        assert name in signature, name
    for name in options:
        # Taken, and checked for its type: refused naming itself, not as an unexpected option.
        with pytest.raises((TypeError, ValueError), match=rf"^{name}: ") as wrong:
            layerlab.solve(small_system, None, **{name: object()})
        assert "unexpected option" not in str(wrong.value)
        assert re.search(rf"^  {name}: ", layerlab.solve.__doc__, re.M), f"solve()'s docstring lacks {name}"
