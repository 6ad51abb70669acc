"""Every import of the package points down its floors (docs/architecture.md).

The floors, bottom to top, spell the pipeline: core types, picture input, design (with the
top-level ``solvers/``), knitting, the knitout IR, the checker and machine formats, the knitting
path measured on the machine, what users get, and the callers (CLI, app, benchmark). A module may
import its own floor and the floors below it, never one above; every import counts, including the
ones inside functions and under ``TYPE_CHECKING``. A new subpackage must be given a floor here.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: Bottom to top; packages on one floor may import each other.
FLOORS: tuple[tuple[str, ...], ...] = (
    ("core",),
    ("pictures",),
    ("solvers",),
    ("design",),
    ("knitout",),
    ("knit",),
    ("check", "formats"),
    ("knitting",),
    ("pipeline",),
    ("outputs",),
    ("cli", "app", "bench"),
)
FLOOR = {package: i for i, floor in enumerate(FLOORS) for package in floor}
#: Modules directly in ``illuknit/``: the package's lazy public names sit on the core floor (they
#: import nothing but :mod:`illuknit.core.lazy`), ``python -m illuknit`` on the callers'.
TOP_MODULES = {"illuknit": 0, "illuknit.__main__": len(FLOORS) - 1}


def module_files() -> dict[str, Path]:
    """Every module of the package by dotted name (``solvers/`` installs as illuknit.solvers)."""
    files = {}
    for base, prefix in (
        (ROOT / "illuknit", ("illuknit",)),
        (ROOT / "solvers", ("illuknit", "solvers")),
    ):
        for path in sorted(base.rglob("*.py")):
            if any(p.is_symlink() for p in [path, *path.parents] if p.is_relative_to(base)):
                continue
            parts = [*prefix, *path.relative_to(base).with_suffix("").parts]
            if parts[-1] == "__init__":
                parts.pop()
            files[".".join(parts)] = path
    return files


def imported_modules(source: str, module: str, *, is_package: bool) -> list[tuple[int, str]]:
    """(line, dotted name) of every import of an ``illuknit`` module in ``source``."""
    package = module if is_package else module.rpartition(".")[0]
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                name = ".".join([*base, *([node.module] if node.module else [])])
            else:
                name = node.module or ""
            # `from illuknit import tiles` imports the module illuknit.tiles, not the package
            found += [(node.lineno, name)]
            if name == "illuknit":
                found += [(node.lineno, f"illuknit.{a.name}") for a in node.names]
    return [(line, name) for line, name in found if name.split(".")[0] == "illuknit"]


def floor_of(module: str) -> int | None:
    """The floor of a module of the package; None for one no floor lists."""
    if module in TOP_MODULES:
        return TOP_MODULES[module]
    parts = module.split(".")
    if len(parts) < 2:
        return None
    return FLOOR.get(parts[1])


def upward_imports(files: dict[str, Path]) -> list[str]:
    bad = []
    for module, path in files.items():
        mine = floor_of(module)
        assert mine is not None, f"{module} is on no floor: add its package to FLOORS"
        is_package = path.name == "__init__.py"
        where = path.relative_to(ROOT) if path.is_relative_to(ROOT) else path
        for line, target in imported_modules(path.read_text(), module, is_package=is_package):
            theirs = floor_of(target)
            if theirs is None:
                # `from illuknit import __version__` and names the root re-exports
                theirs = 0 if target.count(".") == 1 and target.split(".")[1] not in FLOOR else None
            if theirs is None:
                bad.append(f"{where}:{line}: {target} is on no floor")
            elif theirs > mine:
                bad.append(
                    f"{where}:{line}: {module} (floor {mine}) imports {target} (floor {theirs})"
                )
    return bad


def test_every_import_points_down():
    files = module_files()
    assert "illuknit.core.pattern" in files and "illuknit.solvers" in files
    assert upward_imports(files) == []


def test_every_package_has_a_floor():
    packages = {p.name for p in (ROOT / "illuknit").iterdir() if (p / "__init__.py").exists()}
    packages |= {"solvers"}
    assert packages <= set(FLOOR), sorted(packages - set(FLOOR))


@pytest.mark.parametrize(
    ("module", "source", "expected"),
    [
        ("illuknit.core.pattern", "from illuknit.knit.schedule import Pass\n", 1),
        ("illuknit.knit.stitches", "def f():\n    from illuknit.check import check_knitout\n", 1),
        ("illuknit.design.tiles.bank", "from illuknit import outputs\n", 1),
        ("illuknit.cli.knit", "from illuknit.knitting import knit_pattern\n", 0),
        ("illuknit.design.models.model", "from illuknit.solvers import solve\n", 0),
        (
            "illuknit.knit.timing",
            "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
            "    from illuknit.knitting.carriage import MachineRun\n",
            1,
        ),
    ],
)
def test_the_check_sees_an_upward_import(tmp_path, module, source, expected):
    path = tmp_path / "m.py"
    path.write_text(source)
    assert len(upward_imports({module: path})) == expected
