"""docs/library.md runs: its Python blocks, in order, in one namespace, in an empty folder, and
each block prints what its ``# ...`` comment lines after the code say it prints."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

DOC = Path(__file__).resolve().parent.parent / "docs" / "library.md"


def _blocks(text: str) -> list[str]:
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


def _expected(block: str) -> list[str]:
    """The ``# `` lines that close a block: what it prints."""
    lines = block.rstrip("\n").splitlines()
    out: list[str] = []
    while lines and lines[-1].startswith("# "):
        out.insert(0, lines.pop()[2:])
    return out


def test_the_library_walk_through_runs_and_prints_what_it_says(tmp_path, monkeypatch):
    blocks = _blocks(DOC.read_text())
    assert len(blocks) >= 10
    monkeypatch.chdir(tmp_path)
    namespace: dict[str, object] = {"__name__": "library_doc"}
    for k, block in enumerate(blocks):
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            exec(compile(block, f"docs/library.md block {k + 1}", "exec"), namespace)
        expected = _expected(block)
        if expected:
            assert printed.getvalue().splitlines() == expected, f"block {k + 1}"


@pytest.mark.parametrize("name", ["design_single", "design_double", "solve_design", "knit_pattern"])
def test_the_walk_through_names_the_stages(name):
    assert f"`{name}`" in DOC.read_text()
