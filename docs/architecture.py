"""Draw docs/img/architecture.svg from the code, and write the floor table of docs/architecture.md.

The picture: the pipeline's stages, where each lives, its IR. Each box is a stage function looked
up by its dotted name; the box shows the function and the file that defines it, and each arrow is
labelled with the type the function is annotated to return (its IR). Renaming or moving a stage,
or changing what it returns, changes the picture; a stage that no longer exists stops the script.

The floor table: the floors are ``FLOORS`` of tests/test_layers.py (read here as a literal, so
the table and the layer test cannot disagree); what lives in each package is :data:`PACKAGES`
below, one entry per package. A package on a floor without an entry here, an entry for a package
no floor lists, or a file or folder an entry names (in backticks, ``x.py`` or ``x/``) that is not
in its package stops the script.

``python docs/architecture.py`` writes both; ``--check`` exits 1 when the SVG or the table on
disk is not what the code gives (the test suite runs it).
"""

from __future__ import annotations

import ast
import importlib
import inspect
import re
import sys
from html import escape
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "docs" / "img" / "architecture.svg"
DOC = ROOT / "docs" / "architecture.md"
LAYER_TEST = ROOT / "tests" / "test_layers.py"
TABLE_START = (
    "<!-- floor table: written by python docs/architecture.py from tests/test_layers.py -->"
)
TABLE_END = "<!-- end of floor table -->"

#: What lives in each package of a floor, by package name (the names of ``FLOORS`` in
#: tests/test_layers.py); a file or folder in backticks is one of the package's own.
PACKAGES: dict[str, str] = {
    "core": "the types every floor shares: `LogicalPattern` and its file (`pattern.py`), its "
    "yarns (`yarns.py`), what a viewer sees (`views.py`: `can_see`), colours (`colors.py`), every "
    "exception (`errors.py`), the machine description `MachineSpec` and its presets "
    "(`machine_spec.py`, the carriage's timing in `machine_timing.py`, found by name in "
    "`machine.py`), the ranges of machine values with their sources (`machine_ranges.py`), atomic "
    "file writing (`atomic_files.py`, folders in `files.py`), never over an input "
    "(`output_guard.py`), options declared once (`declared.py`), reading the user's files within "
    "limits (`documents.py`), progress bars (`progress.py`), lazy public names (`lazy.py`)",
    "pictures": "picture input: decoding files (`decode.py`), quantising to yarns (`images.py`), "
    "sizing one or two pictures to one grid (`sizing.py`), pictures drawn by code (`drawings.py`)",
    "design": "from pictures to patterns: single view (`single_view.py`), tiles (`tiles/`), "
    "the illusion models (`models/`) with the domain algorithms that register as solver backends "
    "(`models/backends/`: the DP, block descent, Lagrangian bound, gradient design, warm starts), "
    "the renderer and gradient design (`render/`), and the measures designs are ranked by "
    "(`measures.py`)",
    "solvers": "the solver layer, which knows no knitting: a top-level folder installed as "
    "`illuknit.solvers`, with the neutral form (the constraint `Model` in `model.py`, its variable "
    "pool in `var_pool.py`, the CNF encodings in `cnf_encodings.py`), the backends that solve it "
    "(`cpsat.py`, `rc2.py`, `lsu.py`, `fm.py`, `hermax.py`, `wcnf.py`) with their declared "
    "capabilities and the `Solution` contract (`base.py`), typed solve statistics (`stats.py`), "
    "and the registry and `solve` (`__init__.py`) that domain backends register with",
    "knit": "from a pattern to a machine program: stitches (`stitches.py`), carriage-pass "
    "schedules (`schedule.py`, `mixed.py`), their lowering to a `KnitoutProgram` (`knitout.py`), "
    "the time model (`timing.py`)",
    "knitout": "the knitout program as data, below the scheduler that lowers to it: one typed "
    "operation vocabulary (`Opcode`, `Bed`, `Direction`, `Needle`, `Operation` with the schedule "
    "step it came from) and `KnitoutProgram` with `format_knitout`, the one text writer "
    "(`program.py`); the parser (`parse.py`); what a float is and how long it may be "
    "(`floats.py`); the comment line a program declares its split or tall bumps in (`bumps.py`)",
    "check": "the checker: a program run on a simulated machine (`simulate.py`), its rules "
    "(`rules.py`) and fabric findings (`fabric.py`)",
    "formats": "the machine files (Shima `.dat`, Kniterate `.kc`) with the passes the SWG machine "
    "runs (`swg_passes.py`)",
    "knitting": "the whole knitting path in one call, `knit_pattern` (`pipeline.py`), measured on "
    "the machine that runs it (`carriage.py` counts the machine's passes with `illuknit.formats`)",
    "pipeline": "the design stages as one call each, from pictures to ranked designs and what "
    "knitting them costs, one module a stage (`single.py`, `tiles.py` with its search and ranking "
    "in `tile_search.py`, `solve.py`, `measure.py`; their results in `designs.py`, the checks and "
    "`PictureOptions` they share in `inputs.py`; `stages.py` names them all), and the smallest "
    "width at which a double view reads (`legible.py`)",
    "outputs": "what a user reads: previews (`previews.py`), the hand-knitting chart and "
    "instructions (`chart.py`, `hand_pattern.py`, `pattern_pdf.py` with its pages in "
    "`pdf_document.py`, `pdf_materials.py`, `pdf_chart.py`), the pattern folder "
    "(`export.py`), the machine set-up sheet (`machine_sheet.py`)",
    "cli": "the callers: the command line",
    "app": "the local web app",
    "bench": "the benchmark",
}

#: (dotted stage function, column, row). Columns: 0 single view, 1 tiles, 2 constraint models and
#: solvers, 3 gradient design; the shared stages span the middle.
STAGES: tuple[tuple[str, float, int], ...] = (
    ("illuknit.pictures.images.load_image", 1.5, 0),
    ("illuknit.pictures.sizing.size_pair", 1.5, 1),
    ("illuknit.pictures.images.quantise_image", 1.5, 2),
    ("illuknit.design.single_view.compile_single_view", 0, 3),
    ("illuknit.design.tiles.assign.assign_tiles", 1, 3),
    ("illuknit.design.models.illusion_models.build_model", 2, 3),
    ("illuknit.design.render.optimise.optimise_design", 3, 3),
    ("illuknit.design.tiles.compile.compile_tiles", 1, 4),
    ("illuknit.solvers.solve", 2, 4),
    ("illuknit.design.models.illusion_report.pattern_from_solution", 2, 5),
    ("illuknit.core.pattern.LogicalPattern", 1.5, 6),
    ("illuknit.core.views.can_see", 0, 6),
    ("illuknit.design.render.raycast.render_views", 3, 6),
    ("illuknit.knit.stitches.lower_to_stitches", 1.5, 7),
    ("illuknit.knit.schedule.schedule_courses", 1, 8),
    ("illuknit.knit.mixed.schedule_mixed", 2, 8),
    ("illuknit.knit.knitout.write_knitout", 1.5, 9),
    ("illuknit.knitout.parse.parse_knitout", 0.5, 10),
    ("illuknit.check.check_knitout", 0.5, 11),
    ("illuknit.formats.dat.knitout_to_dat", 1.5, 10),
    ("illuknit.formats.kc.knitout_to_kc", 2.5, 10),
)

#: (from, to) by function name; the label is the IR ``from`` returns.
EDGES: tuple[tuple[str, str], ...] = (
    ("load_image", "size_pair"),
    ("size_pair", "quantise_image"),
    ("quantise_image", "compile_single_view"),
    ("quantise_image", "assign_tiles"),
    ("quantise_image", "build_model"),
    ("quantise_image", "optimise_design"),
    ("assign_tiles", "compile_tiles"),
    ("build_model", "solve"),
    ("solve", "pattern_from_solution"),
    ("compile_single_view", "LogicalPattern"),
    ("compile_tiles", "LogicalPattern"),
    ("pattern_from_solution", "LogicalPattern"),
    ("optimise_design", "LogicalPattern"),
    ("LogicalPattern", "can_see"),
    ("LogicalPattern", "render_views"),
    ("LogicalPattern", "lower_to_stitches"),
    ("lower_to_stitches", "schedule_courses"),
    ("lower_to_stitches", "schedule_mixed"),
    ("schedule_courses", "write_knitout"),
    ("schedule_mixed", "write_knitout"),
    ("write_knitout", "parse_knitout"),
    ("parse_knitout", "check_knitout"),
    ("write_knitout", "knitout_to_dat"),
    ("write_knitout", "knitout_to_kc"),
)

#: What a stage that returns a plain type (text, bytes, an array) returns, in words.
PLAIN = {
    "load_image": "RGB array (H, W, 3)",
    "can_see": "yarn index array (N, M)",
    "write_knitout": "knitout text",
    "knitout_to_dat": "Shima .dat bytes",
    "knitout_to_kc": "Kniterate .kc text",
}
SKIP = {"list", "tuple", "dict", "NDArray", "ndarray", "Any", "None", "int", "float", "np", "numpy"}

BOX_W, BOX_H, COL_W, ROW_H, MARGIN = 276, 44, 296, 78, 24


def describe(dotted: str) -> tuple[str, str, str]:
    """(name, defining file, IR it returns) of a stage function (or an IR class)."""
    module, _, name = dotted.rpartition(".")
    obj = getattr(importlib.import_module(module), name)
    path = Path(inspect.getfile(obj)).resolve()
    where = path.relative_to(ROOT).as_posix()
    where = where.replace("/__init__.py", "/").replace("illuknit/solvers/", "solvers/")
    if where.startswith("illuknit/"):
        where = where[len("illuknit/") :]
    if inspect.isclass(obj):
        return name, where, name
    ret = inspect.signature(obj).return_annotation
    text = ret if isinstance(ret, str) else getattr(ret, "__name__", str(ret))
    if text in ("str", "bytes") or text.startswith("NDArray"):
        return name, where, PLAIN[name]
    words = [w for w in re.findall(r"[A-Za-z_]\w*", text) if w not in SKIP]
    return name, where, (words[0] if words else text)


def draw() -> str:
    """The SVG text of the pipeline."""
    nodes = {}
    for dotted, col, row in STAGES:
        name, where, ir = describe(dotted)
        x = MARGIN + col * COL_W
        y = MARGIN + row * ROW_H
        nodes[name] = (x, y, where, ir, dotted.endswith("LogicalPattern"))
    width = int(MARGIN * 2 + 3 * COL_W + BOX_W)
    height = int(MARGIN * 2 + max(row for _, _, row in STAGES) * ROW_H + BOX_H)
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
        f'viewBox="0 0 {width} {height}" font-family="sans-serif">',
        '<defs><marker id="a" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="7" '
        'markerHeight="7" orient="auto"><path d="M0,0 L10,5 L0,10 z" fill="#555"/></marker></defs>',
        f'<rect width="{width}" height="{height}" fill="#ffffff"/>',
    ]
    for src, dst in EDGES:
        x0, y0, _, ir, _ = nodes[src]
        x1, y1, *_ = nodes[dst]
        if y0 == y1:  # a side stage on the same row (the views of a pattern)
            left = x1 < x0
            ax, ay = (x0, y0 + BOX_H / 2) if left else (x0 + BOX_W, y0 + BOX_H / 2)
            bx, by = (x1 + BOX_W, y1 + BOX_H / 2) if left else (x1, y1 + BOX_H / 2)
        else:
            ax, ay = x0 + BOX_W / 2, y0 + BOX_H
            bx, by = x1 + BOX_W / 2, y1
        out.append(
            f'<line x1="{ax:.0f}" y1="{ay:.0f}" x2="{bx:.0f}" y2="{by:.0f}" stroke="#555" '
            'stroke-width="1.3" marker-end="url(#a)"/>'
        )
        fan = src in ("quantise_image", "LogicalPattern", "write_knitout")
        if y0 != y1 and not fan and dst != "LogicalPattern":
            out.append(
                f'<text x="{(ax + bx) / 2 + 6:.0f}" y="{(ay + by) / 2 + 4:.0f}" font-size="11" '
                f'font-style="italic" fill="#1d4e89">{escape(ir)}</text>'
            )
    for name, (x, y, where, ir, is_ir) in nodes.items():
        fill, stroke = ("#fdf1d6", "#b7791f") if is_ir else ("#eef3fb", "#1d4e89")
        out.append(
            f'<rect x="{x:.0f}" y="{y:.0f}" width="{BOX_W}" height="{BOX_H}" rx="6" '
            f'fill="{fill}" stroke="{stroke}"/>'
        )
        title = name if is_ir else f"{name}()"
        out.append(
            f'<text x="{x + BOX_W / 2:.0f}" y="{y + 18:.0f}" font-size="13" text-anchor="middle" '
            f'font-weight="bold">{escape(title)}</text>'
        )
        label = f"{where} -> {ir}"
        if is_ir:
            label = f"{where}: every design path ends here"
        elif name in ("can_see", "render_views"):
            label = f"{where}: what each side shows"
        out.append(
            f'<text x="{x + BOX_W / 2:.0f}" y="{y + 35:.0f}" font-size="11" text-anchor="middle" '
            f'fill="#444">{escape(label)}</text>'
        )
    out.append("</svg>")
    return "\n".join(out) + "\n"


def read_floors() -> tuple[tuple[str, ...], ...]:
    """``FLOORS`` of tests/test_layers.py, bottom to top (read from its source, not imported)."""
    for node in ast.parse(LAYER_TEST.read_text(encoding="utf-8")).body:
        target = node.target if isinstance(node, ast.AnnAssign) else None
        if isinstance(node, ast.Assign) and len(node.targets) == 1:
            target = node.targets[0]
        if isinstance(target, ast.Name) and target.id == "FLOORS" and node.value is not None:
            floors = ast.literal_eval(node.value)
            return tuple(tuple(floor) for floor in floors)
    raise SystemExit(f"{LAYER_TEST.relative_to(ROOT)} defines no FLOORS")


def package_dir(name: str) -> Path:
    """Where a package of the floors lives: ``illuknit/<name>/``, or a top-level folder installed
    into the package (``solvers/``)."""
    inside = ROOT / "illuknit" / name
    return inside if inside.is_dir() or not (ROOT / name).is_dir() else ROOT / name


def floor_problems(floors: tuple[tuple[str, ...], ...]) -> list[str]:
    """Why the floors and :data:`PACKAGES` cannot make a table (empty when they can)."""
    listed = [name for floor in floors for name in floor]
    problems = [f"{n}: on a floor but not in PACKAGES" for n in listed if n not in PACKAGES]
    problems += [f"{n}: in PACKAGES but on no floor" for n in PACKAGES if n not in listed]
    for name, text in PACKAGES.items():
        for entry in re.findall(r"`([\w./]+(?:\.py|/))`", text):
            if not (package_dir(name) / entry).exists():
                problems.append(f"{name}: names `{entry}`, which {package_dir(name)} lacks")
    return problems


def floor_table() -> str:
    """The floor table of docs/architecture.md (markdown, bottom floor first)."""
    floors = read_floors()
    problems = floor_problems(floors)
    if problems:
        raise SystemExit("the floor table cannot be written:\n  " + "\n  ".join(problems))
    rows = ["| floor | package | what lives there |", "|---|---|---|"]
    for number, floor in enumerate(floors, start=1):
        where = ", ".join(f"`{package_dir(n).relative_to(ROOT).as_posix()}/`" for n in floor)
        rows.append(f"| {number} | {where} | {'; '.join(PACKAGES[n] for n in floor)} |")
    return "\n".join(rows) + "\n"


def with_table(doc: str, table: str) -> str:
    """``doc`` with the text between the table's two marker lines replaced by ``table``."""
    start, end = doc.find(TABLE_START), doc.find(TABLE_END)
    if start < 0 or end < start:
        raise SystemExit(f"{DOC.relative_to(ROOT)} lacks the floor table's marker lines")
    head = doc[: start + len(TABLE_START)]
    return f"{head}\n{table}{doc[end:]}"


def main(argv: list[str]) -> int:
    svg = draw()
    doc = DOC.read_text(encoding="utf-8")
    new_doc = with_table(doc, floor_table())
    if "--check" in argv:
        current = OUT.read_text(encoding="utf-8") if OUT.exists() else ""
        stale = [path for path, ok in ((OUT, current == svg), (DOC, doc == new_doc)) if not ok]
        for path in stale:
            print(f"{path.relative_to(ROOT)} is out of date: run python docs/architecture.py")
        return 1 if stale else 0
    OUT.write_text(svg, encoding="utf-8")
    DOC.write_text(new_doc, encoding="utf-8")
    print(f"wrote {OUT.relative_to(ROOT)} and the floor table of {DOC.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))  # this checkout's illuknit, whichever one is installed
    sys.exit(main(sys.argv[1:]))
