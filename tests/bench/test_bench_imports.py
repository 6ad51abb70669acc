"""No module of illuknit.bench imports another module's private (``_name``) helpers: what one
module needs from another is public there (split.py took ``_add_grouped`` and ``_Flat``)."""

from __future__ import annotations

import ast
from pathlib import Path

import illuknit.bench

BENCH = Path(illuknit.bench.__file__).parent


def _private_imports(path: Path) -> list[str]:
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            found += [
                f"{path.name}:{node.lineno}: {node.module}.{a.name}"
                for a in node.names
                if a.name.startswith("_") and not a.name.startswith("__")
            ]
    return found


def test_no_bench_module_imports_private_names():
    modules = sorted(BENCH.glob("*.py"))
    assert len(modules) > 10
    found = [hit for path in modules for hit in _private_imports(path)]
    assert found == []
