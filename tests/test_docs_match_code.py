"""The docs name what exists: the floor table of docs/architecture.md is the one written from the
layer test's floors, every module, file and dotted name the docs cite is still there, and each
stage and IR of docs/architecture.md is in the module the doc says it is in."""

from __future__ import annotations

import ast
import importlib
import re
import runpy
import warnings
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SCRIPT = ROOT / "docs" / "architecture.py"
DOCS = [*sorted((ROOT / "docs").glob("*.md")), ROOT / "README.md"]
#: Where a bare file name (``sizing.py``) cited in a doc may live.
TREES = ("illuknit", "solvers", "tests", "benchmarks", "docs", "instances")
#: Package names a doc may cite without the ``illuknit.`` prefix (``sizing.size_pair`` is not one:
#: only the first part is looked up).
SHORT = ("core", "pictures", "design", "solvers", "knit", "knitout", "check", "formats")
SHORT += ("knitting", "pipeline", "outputs", "cli", "app", "bench")
#: A dotted word ending so is a file name (``knit.json``), not a module path.
FILE_ENDINGS = ("json", "csv", "md", "txt", "k", "png", "pdf", "svg", "toml", "dat", "kc", "py")


@pytest.fixture(scope="module")
def architecture():
    return runpy.run_path(str(SCRIPT))


def test_the_floor_table_is_the_one_the_floors_give(architecture):
    doc = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    table = architecture["floor_table"]()
    assert architecture["with_table"](doc, table) == doc, "run: python docs/architecture.py"
    assert "| `illuknit/pipeline/` |" in table


def test_the_table_has_a_row_per_floor_of_the_layer_test(architecture):
    floors = runpy.run_path(str(ROOT / "tests" / "test_layers.py"))["FLOORS"]
    assert architecture["read_floors"]() == floors
    rows = architecture["floor_table"]().splitlines()[2:]
    assert [int(r.split("|")[1]) for r in rows] == list(range(1, len(floors) + 1))
    for row, floor in zip(rows, floors, strict=True):
        cells = [c.strip("` ") for c in row.split("|")[2].split(",")]
        assert [c.rstrip("/").rpartition("/")[2] for c in cells] == list(floor), row


def test_every_package_says_what_lives_there(architecture):
    assert architecture["floor_problems"](architecture["read_floors"]()) == []


@pytest.mark.parametrize(
    ("floors", "entry", "problem"),
    [
        ((("core",), ("newpackage",)), None, "newpackage: on a floor but not in PACKAGES"),
        ((("core",),), None, "pictures: in PACKAGES but on no floor"),
        (None, ("core", "the types (`gone.py`)"), "core: names `gone.py`"),
    ],
)
def test_the_table_refuses_floors_it_cannot_describe(architecture, floors, entry, problem):
    check = architecture["floor_problems"]
    packages = architecture["PACKAGES"]
    saved = dict(packages)
    try:
        if entry:
            packages[entry[0]] = entry[1]
        found = check(floors or architecture["read_floors"]())
    finally:
        packages.clear()
        packages.update(saved)
    assert any(p.startswith(problem) for p in found), found


def _file_exists(cited: str) -> bool:
    if "/" not in cited:
        return any(any((ROOT / tree).rglob(cited)) for tree in TREES)
    return any(any(base.glob(cited)) for base in (ROOT, ROOT / "illuknit"))


def _dotted_exists(dotted: str) -> bool:
    """Whether ``illuknit.a.b.name`` imports (as a module, then attributes), without a
    DeprecationWarning: a doc that cites an old path is out of date too."""
    parts = dotted.split(".")
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        for cut in range(len(parts), 0, -1):
            try:
                obj = importlib.import_module(".".join(parts[:cut]))
            except ModuleNotFoundError:
                continue
            try:
                for attribute in parts[cut:]:
                    obj = getattr(obj, attribute)
            except (AttributeError, DeprecationWarning):
                return False
            return True
    return False


def cited_names(text: str) -> tuple[list[str], list[str]]:
    """(files, dotted names) a markdown text cites in backticks."""
    files = re.findall(r"`([^`\s]+\.py)`", text)
    dotted = re.findall(r"`(illuknit(?:\.[A-Za-z_]\w*)+)", text)
    short = re.findall(rf"`((?:{'|'.join(SHORT)})(?:\.[A-Za-z_]\w*)+)", text)
    dotted += [f"illuknit.{d}" for d in short if d.rpartition(".")[2] not in FILE_ENDINGS]
    return files, dotted


def test_citations_are_found():
    files, dotted = cited_names(
        "`knit/schedule.py`, `grad.py`, `illuknit.solvers.solve(model, ...)`, `knit.json`, "
        "`sizing.size_pair`, `knitting.knit_pattern`"
    )
    assert files == ["knit/schedule.py", "grad.py"]
    assert dotted == ["illuknit.solvers.solve", "illuknit.knitting.knit_pattern"]
    assert _dotted_exists("illuknit.knitting.knit_pattern")
    assert not _dotted_exists("illuknit.knit.knit_pattern")
    assert not _dotted_exists("illuknit.core.views.seen_shares")
    assert _file_exists("knit/schedule.py") and _file_exists("tests/knit/test_*.py")
    assert not _file_exists("tests/test_check_programs.py")


@pytest.mark.parametrize("doc", DOCS, ids=lambda p: p.name)
def test_every_module_and_name_a_doc_cites_exists(doc):
    files, dotted = cited_names(doc.read_text(encoding="utf-8"))
    missing = [f for f in dict.fromkeys(files) if not _file_exists(f)]
    missing += [d for d in dict.fromkeys(dotted) if not _dotted_exists(d)]
    assert missing == [], f"{doc.name} cites what is not there"


# -- docs/architecture.md: each stage and IR where the doc says it lives -------------------------

ARCHITECTURE = ROOT / "docs" / "architecture.md"


def _names_bound(path: Path) -> set[str]:
    """Every name a module (or every module of a folder) defines, assigns or imports."""
    names: set[str] = set()
    for file in [path] if path.is_file() else sorted(path.rglob("*.py")):
        for node in ast.walk(ast.parse(file.read_text(encoding="utf-8"))):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
                names.add(node.name)
            elif isinstance(node, ast.Import | ast.ImportFrom):
                names |= {(a.asname or a.name).rpartition(".")[2] for a in node.names}
            elif isinstance(node, ast.Assign | ast.AnnAssign):
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]
                names |= {t.id for t in targets if isinstance(t, ast.Name)}
    return names


def _cited_paths(cell: str) -> list[Path]:
    """The files and folders a table cell cites: relative to illuknit/ or the checkout, or (a
    bare name) beside the one cited before it."""
    paths: list[Path] = []
    for token in re.findall(r"`([\w./]+(?:\.py|/))`", cell):
        bases = [ROOT / "illuknit", ROOT]
        if paths:
            bases.append(paths[-1] if paths[-1].is_dir() else paths[-1].parent)
        found = next((base / token for base in bases if (base / token).exists()), None)
        assert found is not None, f"docs/architecture.md cites `{token}`, which is not there"
        paths.append(found)
    return paths


def _stage_rows() -> list[list[str]]:
    text = ARCHITECTURE.read_text(encoding="utf-8")
    table = text[text.index("| stage | function | module |") :].split("\n\n")[0]
    return [[c.strip() for c in row.strip("|").split("|")] for row in table.splitlines()[2:]]


@pytest.mark.parametrize("row", _stage_rows(), ids=lambda row: row[0])
def test_each_stage_is_in_the_module_its_row_names(row):
    _, functions, modules, _ = row
    bound = set().union(*(_names_bound(p) for p in _cited_paths(modules)))
    missing = [f for f in re.findall(r"`([A-Za-z_]\w*)`", functions) if f not in bound]
    assert missing == [], f"{row[0]}: not in {modules}"


def test_each_ir_is_in_the_module_the_doc_names():
    text = ARCHITECTURE.read_text(encoding="utf-8")
    found = re.findall(r"\*\*((?:`\w+`(?:,? (?:and )?)?)+)\*\*\s*\(`([\w./]+)`", text)
    assert len(found) >= 10
    for names, where in found:
        bound = _names_bound(_cited_paths(f"`{where}`")[0])
        assert set(re.findall(r"`(\w+)`", names)) <= bound, (names, where)
