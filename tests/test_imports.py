"""illuknit never catches an import error of its own code (it would hide a bug as a missing
feature); optional third-party extras are probed with importlib.util.find_spec instead."""

from __future__ import annotations

import ast
from pathlib import Path

import illuknit

ROOTS = [Path(illuknit.__file__).parent]
CATCHING = {"ImportError", "ModuleNotFoundError", "Exception", "BaseException"}


def _caught(handler: ast.ExceptHandler) -> set[str]:
    if handler.type is None:
        return {"BaseException"}
    nodes = handler.type.elts if isinstance(handler.type, ast.Tuple) else [handler.type]
    return {n.id for n in nodes if isinstance(n, ast.Name)}


def _own_imports(body: list[ast.stmt]) -> list[str]:
    found = []
    for stmt in body:
        for node in ast.walk(stmt):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("illuknit"):
                found.append(str(node.module))
            elif isinstance(node, ast.Import):
                found += [a.name for a in node.names if a.name.startswith("illuknit")]
    return found


def offenders(roots: list[Path]) -> list[str]:
    out = []
    for root in roots:
        for path in sorted(root.rglob("*.py")):
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if not isinstance(node, ast.Try):
                    continue
                own = _own_imports(node.body)
                if own and any(_caught(h) & CATCHING for h in node.handlers):
                    out.append(f"{path.relative_to(root.parent)}:{node.lineno} ({', '.join(own)})")
    return out


def test_no_import_of_illuknit_is_wrapped_in_a_handler_that_would_swallow_its_failure():
    assert offenders(ROOTS) == []


def test_the_checker_finds_a_swallowed_import(tmp_path):
    bad = tmp_path / "illuknit"
    bad.mkdir()
    (bad / "m.py").write_text("try:\n    import illuknit.knit\nexcept ImportError:\n    pass\n")
    (bad / "ok.py").write_text("try:\n    import uvicorn\nexcept ImportError:\n    pass\n")
    assert offenders([bad]) == ["illuknit/m.py:1 (illuknit.knit)"]
