"""``tests/`` mirrors the package (docs/STYLE: "tests/ mirrors the package"): every package of
``illuknit/`` (and the top-level ``solvers/``, installed as ``illuknit.solvers``) has its
``tests/<name>/`` folder, and every folder of ``tests/`` is named for a package.

The two allowlists are today's gaps (tests still at the top level of ``tests/``, and the render
and tile tests not yet under ``tests/design/``). They may only shrink: a gap that has been closed
fails here until it is taken off its list.
"""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TESTS = ROOT / "tests"

#: Packages without a tests/<name>/ folder (none: keep it so).
NO_TEST_FOLDER_YET: frozenset[str] = frozenset()
#: Folders of tests/ that are not named for a package of illuknit/ (none: keep it so).
NOT_A_PACKAGE_YET: frozenset[str] = frozenset()


def packages() -> set[str]:
    """The packages directly under illuknit/, and solvers."""
    found = {p.name for p in (ROOT / "illuknit").iterdir() if (p / "__init__.py").is_file()}
    return found | {"solvers"}


def folders_of_tests() -> set[str]:
    """The folders of tests/ that hold tests (not data, caches or helpers)."""
    return {
        p.name
        for p in TESTS.iterdir()
        if p.is_dir() and not p.name.startswith((".", "_")) and any(p.rglob("test_*.py"))
    }


def test_every_package_has_its_test_folder():
    missing = packages() - folders_of_tests()
    assert missing <= NO_TEST_FOLDER_YET, f"give these packages a tests/<name>/: {sorted(missing)}"


def test_every_test_folder_is_named_for_a_package():
    strays = folders_of_tests() - packages()
    assert strays <= NOT_A_PACKAGE_YET, f"tests/ folders that name no package: {sorted(strays)}"


def test_the_allowlists_only_shrink():
    closed = NO_TEST_FOLDER_YET - (packages() - folders_of_tests())
    closed |= NOT_A_PACKAGE_YET - (folders_of_tests() - packages())
    assert closed == set(), f"these gaps are closed: take them off the allowlists: {sorted(closed)}"
