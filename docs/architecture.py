"""Draw docs/img/architecture.svg from the code: the pipeline's stages, where each lives, its IR.

Each box is a stage function looked up by its dotted name; the box shows the function and the
file that defines it, and each arrow is labelled with the type the function is annotated to return
(its IR). Renaming or moving a stage, or changing what it returns, changes the picture; a stage
that no longer exists stops the script. ``python docs/architecture.py --check`` exits 1 when the
SVG on disk is not what the code draws (the test suite runs it).
"""

from __future__ import annotations

import importlib
import inspect
import re
import sys
from html import escape
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "docs" / "img" / "architecture.svg"

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


def main(argv: list[str]) -> int:
    svg = draw()
    if "--check" in argv:
        current = OUT.read_text(encoding="utf-8") if OUT.exists() else ""
        if current != svg:
            print(f"{OUT.relative_to(ROOT)} is out of date: run python docs/architecture.py")
            return 1
        return 0
    OUT.write_text(svg, encoding="utf-8")
    print(f"wrote {OUT.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
