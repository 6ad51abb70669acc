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


# -- no import cycles between illuknit modules ------------------------------------------------
# Every import counts, module-level or inside a function: a function-local import that only
# dodges a cycle still ties the two modules into one room that cannot be read (or tested) alone.


def _modules(root: Path) -> dict[str, Path]:
    """Dotted module name -> file, for the package at ``root`` (following the solvers link)."""
    files = list(root.rglob("*.py")) + list((root / "solvers").glob("*.py"))
    mods = {}
    for path in files:
        parts = [root.name, *path.relative_to(root).with_suffix("").parts]
        if parts[-1] == "__init__":
            parts.pop()
        mods[".".join(parts)] = path
    return mods


def import_graph(root: Path) -> dict[str, set[str]]:
    """Module -> the package's modules it imports anywhere in its code (third-party left out)."""
    mods = _modules(root)

    def known(name: str) -> str | None:
        while name and name not in mods:
            name = name.rpartition(".")[0]
        return name or None

    graph: dict[str, set[str]] = {m: set() for m in mods}
    for mod, path in mods.items():
        package = mod if path.name == "__init__.py" else mod.rpartition(".")[0]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names: list[str] = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    up = package.split(".")[: len(package.split(".")) - node.level + 1]
                    base = ".".join([*up, *([base] if base else [])])
                names = [
                    f"{base}.{a.name}" if f"{base}.{a.name}" in mods else base for a in node.names
                ]
            for name in names:
                target = known(name) if name.split(".")[0] == root.name else None
                if target is not None and target != mod:
                    graph[mod].add(target)
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan), sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(found)


def test_no_two_illuknit_modules_import_each_other_even_inside_functions():
    assert cycles(import_graph(ROOTS[0])) == []


def test_the_cycle_finder_sees_a_cycle_hidden_in_a_function(tmp_path):
    pkg = tmp_path / "illuknit"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "solvers").mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from illuknit.sub import b\nimport numpy\n")
    (pkg / "sub" / "b.py").write_text("def f():\n    from . import c\n")
    (pkg / "sub" / "c.py").write_text("def g():\n    from ..a import x\n")
    (pkg / "d.py").write_text("import illuknit.a\n")
    graph = import_graph(pkg)
    assert graph["illuknit.d"] == {"illuknit.a"}
    assert cycles(graph) == [["illuknit.a", "illuknit.sub.b", "illuknit.sub.c"]]
    (pkg / "sub" / "c.py").write_text("def g():\n    import numpy\n")
    assert cycles(import_graph(pkg)) == []
