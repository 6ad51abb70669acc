"""No module of the package is longer than 600 lines (#36): a room a newcomer reads in one
sitting. A module that grows past it is split by concept, its old import path re-exporting
what moved."""

from __future__ import annotations

import importlib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LIMIT = 600

#: Modules allowed over the limit, each with why. Empty: keep it so. Each entry must exist and
#: still be over the limit (see the test below), so the list can only shrink.
ALLOWED: dict[str, str] = {}


def module_lengths(root: Path = ROOT) -> dict[str, int]:
    """Lines of every module of the package (``illuknit/`` and the top-level ``solvers/``), by
    path from the checkout's root; blank lines, comments and docstrings count."""
    found = {}
    for base in ("illuknit", "solvers"):
        for path in sorted((root / base).rglob("*.py")):
            found[path.relative_to(root).as_posix()] = len(path.read_text().splitlines())
    return found


def test_no_module_is_over_600_lines():
    long = {p: n for p, n in module_lengths().items() if n > LIMIT and p not in ALLOWED}
    assert long == {}, "split these modules by concept (at most 600 lines each)"


def test_every_allowed_module_exists_and_is_still_over_600_lines():
    lengths = module_lengths()
    stale = {p: lengths.get(p) for p in ALLOWED if lengths.get(p, 0) <= LIMIT}
    assert stale == {}, "take these off ALLOWED: they are gone or no longer over the limit"


def test_the_measure_sees_both_trees_and_counts_every_line(tmp_path):
    (tmp_path / "illuknit" / "sub").mkdir(parents=True)
    (tmp_path / "solvers").mkdir()
    (tmp_path / "illuknit" / "sub" / "a.py").write_text('"""Doc."""\n\n# why\n' + "x = 1\n" * LIMIT)
    (tmp_path / "solvers" / "b.py").write_text("y = 2\n")
    (tmp_path / "illuknit" / "notes.txt").write_text("not a module\n" * 700)
    assert module_lengths(tmp_path) == {"illuknit/sub/a.py": LIMIT + 3, "solvers/b.py": 1}


#: Modules split for #36 -> the modules that took their parts; the old module re-exports them.
SPLIT = {
    "illuknit.core.machine": ("illuknit.core.machine_spec", "illuknit.core.machine_timing"),
    "illuknit.core.files": ("illuknit.core.atomic_files", "illuknit.core.output_guard"),
    "illuknit.core.pattern": ("illuknit.core.yarns",),
    "illuknit.outputs.pattern_pdf": (
        "illuknit.outputs.pdf_document",
        "illuknit.outputs.pdf_materials",
        "illuknit.outputs.pdf_chart",
    ),
    "illuknit.app.store": ("illuknit.app.session_pickle",),
    "illuknit.app.sessions": ("illuknit.app.design_session",),
    "illuknit.design.tiles.perception": ("illuknit.design.tiles.candidate_measures",),
}


@pytest.mark.parametrize("old", sorted(SPLIT))
def test_a_split_module_still_offers_every_public_name_of_its_parts(old):
    """Splitting a module moves no import path: each public name of a part is the same object
    under the old module's name."""
    facade = importlib.import_module(old)
    for part in SPLIT[old]:
        module = importlib.import_module(part)
        missing = [n for n in module.__all__ if getattr(facade, n, None) is not getattr(module, n)]
        assert missing == [], f"{old} does not re-export these names of {part}"
