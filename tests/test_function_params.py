"""No function of the package takes more than 8 parameters (issue 36, "the spine").

A long argument list is options that travel together without a name: group them into a frozen,
typed option or context object (``RenderParams``, ``SearchOptions``, ``KnitOptions``, ...), as
cvxpy's and scikit-image's signatures do. Parameters are counted as the house counts them:
positional and keyword-only, not ``self`` / ``cls``, ``*args`` or ``**kwargs``. Click command
functions (decorated with ``@...command``) are exempt: their parameters are the command line's
options, which click hands over one by one.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LIMIT = 8

#: Functions allowed over the limit, with their counts (which may not grow). Empty: keep it so.
#: Each entry must exist and still be over the limit (see below), so the list can only shrink.
ALLOWED: dict[str, int] = {}


def _is_command(node: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    """Decorated with ``@...command`` or ``@...command(...)`` (click's commands)."""
    for decorator in node.decorator_list:
        target = decorator.func if isinstance(decorator, ast.Call) else decorator
        name = target.attr if isinstance(target, ast.Attribute) else getattr(target, "id", "")
        if name == "command":
            return True
    return False


def parameter_counts(source: str) -> dict[str, int]:
    """Parameters of every function in ``source`` but click commands, by qualified name
    (``Class.method``, ``outer.inner``)."""
    counts: dict[str, int] = {}

    def visit(node: ast.AST, prefix: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef):
                a = child.args
                named = [p.arg for p in (*a.posonlyargs, *a.args, *a.kwonlyargs)]
                n = len([p for p in named if p not in ("self", "cls")])
                if not _is_command(child):
                    counts[prefix + child.name] = max(n, counts.get(prefix + child.name, 0))
                visit(child, f"{prefix}{child.name}.")
            elif isinstance(child, ast.ClassDef):
                visit(child, f"{prefix}{child.name}.")
            else:
                visit(child, prefix)

    visit(ast.parse(source), "")
    return counts


def all_counts() -> dict[str, int]:
    found = {}
    for base in ("illuknit", "solvers"):
        for path in sorted((ROOT / base).rglob("*.py")):
            for name, n in parameter_counts(path.read_text()).items():
                found[f"{path.relative_to(ROOT).as_posix()}:{name}"] = n
    return found


def test_no_function_takes_more_than_8_parameters():
    counts = all_counts()
    over = {k: n for k, n in counts.items() if n > LIMIT and k not in ALLOWED}
    assert over == {}, "group these parameters into an option or context object"
    grown = {k: counts[k] for k in ALLOWED if counts.get(k, 0) > ALLOWED[k]}
    assert grown == {}, "allowlisted functions may not take more parameters than listed"


def test_the_allowlist_is_not_stale():
    """Every allowlisted function exists and is still over the limit: fixed ones leave the list."""
    counts = all_counts()
    gone = sorted(set(ALLOWED) - set(counts))
    fixed = sorted(k for k in ALLOWED if k in counts and counts[k] <= LIMIT)
    assert gone == [], "these allowlisted functions no longer exist: remove them from ALLOWED"
    assert fixed == [], "these now take at most 8 parameters: remove them from ALLOWED"


def test_the_count_skips_self_varargs_and_commands():
    source = (
        "class C:\n"
        "    def m(self, a, b, *args, c, **kwargs): pass\n"
        "@cli.command()\n"
        "def run(a, b, c, d, e, f, g, h, i): pass\n"
        "def f(a, /, b, *, c):\n"
        "    def inner(x): pass\n"
    )
    assert parameter_counts(source) == {"C.m": 3, "f": 3, "f.inner": 1}
