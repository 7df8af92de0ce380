"""contrast()'s keyword arguments against the contrast option table.

The table is read from docs/scene-reference.md's "run.contrast" section, which
docs.scene_reference_current holds to analysis/contrast_option_table.cpp:
every Python name of the table is a keyword of contrast(), documented in its
docstring, contrast() takes no option the table lacks, and a value beyond a
range's upper end is refused where the table's key is.
"""
import re
from pathlib import Path

import pytest

from conftest import SKIP_REASON

layerlab = pytest.importorskip("layerlab", reason=SKIP_REASON)

REFERENCE = Path(__file__).resolve().parents[2] / "docs" / "scene-reference.md"


def table_rows():
    """(key, type, range, python) of the run.contrast section's tables, and whether the scene holds the key."""
    text = REFERENCE.read_text()
    start = text.index("## `run.contrast`")
    section = text[start:text.index("\n## ", start + 1)]
    scene_part, other_part = section.split("Options the scene file does not set")
    rows = []
    for part, in_scene in ((scene_part, True), (other_part, False)):
        for line in part.splitlines():
            cells = [c.strip().strip("`") for c in line.strip().strip("|").split("|")]
            if len(cells) == 8 and cells[0] not in ("key", "---"):
                rows.append((cells[0], cells[1], cells[3], cells[7], in_scene))
    assert rows, f"no run.contrast option table in {REFERENCE}"
    return rows


def test_every_python_name_of_the_table_is_a_keyword_and_no_other(small_scene_path):
    names = {python for _, _, _, python, _ in table_rows() if python}
    with pytest.raises(TypeError, match="unexpected option 'no_such_option'") as refused:
        layerlab.contrast(small_scene_path, no_such_option=1)
    listed = set(str(refused.value).split("options: ", 1)[1].split(", "))
    assert listed == names, "contrast()'s keywords differ from the table's Python names"
    for name in names:
        assert re.search(rf"^  {name}: ", layerlab.contrast.__doc__, re.M), f"contrast()'s docstring lacks {name}"
        # Taken, and checked for its type: refused naming itself, not as an unexpected option.
        with pytest.raises((TypeError, ValueError), match=rf"\b{name}\b") as wrong:
            layerlab.contrast(small_scene_path, **{name: object()})
        assert "unexpected option" not in str(wrong.value)


def test_a_value_beyond_each_range_is_refused_at_its_key(small_scene_path):
    checked = 0
    for key, kind, cell, python, in_scene in table_rows():
        m = re.match(r"^[\[(]\s*[-\d.e+]+,\s*([-\d.e+]+)\s*([\])])", cell)
        if not (python and in_scene and m):
            continue
        top = float(m.group(1))
        value = top if m.group(2) == ")" else (int(top) + 1 if top.is_integer() else top * 1.5)
        unit = cell.rsplit(" ", 1)[1] if not cell.endswith((")", "]")) else ""
        if unit:
            value = f"{value} {unit}"
        if kind.startswith("array"):
            value = [value]
        with pytest.raises(layerlab.Error) as refused:
            layerlab.contrast(small_scene_path, **{python: value})
        assert refused.value.file == "contrast()", str(refused.value)
        assert refused.value.pointer.startswith(f"/run/contrast/{key}"), str(refused.value)
        checked += 1
    assert checked >= 4


def test_a_key_given_in_the_section_and_as_a_keyword_is_refused(small_scene_path):
    with pytest.raises(layerlab.ArgumentError, match="strip_rows is both in the section and a keyword"):
        layerlab.contrast(small_scene_path, {"strip_rows": 4}, strip_rows=4)
