"""``illuknit double``: two pictures in, ranked tile-based double-view candidates out.

For each candidate ``candidate_K/`` holds the pattern, its previews (head-on, view A, view B,
contact sheet), the repainted inputs (``repainted_a.png``/``repainted_b.png`` course by course,
``*_average.png`` as seen from afar), ``fills.json`` (the legend: which fill each picture colour
became and which tile each overlap pair uses), a chart and written instructions. The top folder
holds ``summary.txt``/``summary.json`` (a ranked table, the default candidate marked) and the
default candidate's ``pattern.json``.
"""

from __future__ import annotations

import functools
import json
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import click
import numpy as np

from illuknit.cli.design_files import fmt_number, summary_text, write_candidate, write_edits
from illuknit.cli.knitout_bridge import format_option, long_floats_option, machine_option
from illuknit.cli.options import knitout_option, outdir_option
from illuknit.design.tiles.perception import DEFAULT_POOL, POOL_SECONDS, RANK_KEYS
from illuknit.pictures.sizing import DEFAULT_MAX_WIDTH

__all__ = ["double", "run_design"]


def _choose_yarns(spec: str | None, n_colors: int, pictures: list[np.ndarray]) -> tuple[Any, ...]:
    from illuknit.core.pattern import parse_yarns

    if spec is not None and not spec.strip().isdigit():
        return parse_yarns(spec)
    n = int(spec) if spec is not None else n_colors
    if not 1 <= n <= 8:
        from illuknit.core.errors import YarnSpecError

        raise YarnSpecError(f"--yarns N must be between 1 and 8, got {n}")
    from illuknit.design.tiles.yarn_choice import choose_yarns

    return choose_yarns(pictures, n)


def run_design(
    path_a: Path,
    path_b: Path | None,
    outdir: Path,
    *,
    mode: str = "double",
    n_colors: int = 2,
    yarns: str | None = None,
    width: int | None = None,
    resize: bool = False,
    candidates: int = 5,
    pool: int | None = None,
    bank_file: Path | None = None,
    pick: int = 1,
    solver: str = "cpsat",
    soft_brightness: bool = False,
    one_sided: bool = False,
    tile: tuple[str, ...] = (),
    knitout: bool = False,
    machine: str | None = None,
    rank_by: str = "perception",
    knit_time: bool = False,
    simplify: bool = False,
    suggest: bool = False,
) -> dict[str, Any]:
    """Load, quantise, assign, compile and write every candidate (atomically into ``outdir``).

    ``mode`` is ``"double"`` (A from above, B from below) or ``"headon"`` (A head-on, B from
    both sides; B may be None for a plain side view). With ``knitout`` the default candidate is
    knit on ``machine`` (a preset name; a pattern wider than its bed is refused before the
    design work). ``pool`` tile designs (default :data:`~illuknit.design.tiles.perception.DEFAULT_POOL`,
    never fewer than ``candidates``) are searched and ranked; the best ``candidates`` are written.
    Returns the summary dict.
    """
    from illuknit.bench.metrics import knit_stats
    from illuknit.cli.knitout_bridge import resolve_machine
    from illuknit.core.errors import TileAssignmentError
    from illuknit.core.files import atomic_write_text, staged_dir
    from illuknit.design.tiles.perception import rank_designs, seen_targets
    from illuknit.outputs.previews import unit_scale

    if candidates < 1:
        raise TileAssignmentError(f"--candidates must be at least 1, got {candidates}")
    if pool is not None and pool < 1:
        raise TileAssignmentError(f"--pool must be at least 1, got {pool}")
    overrides = _parse_overrides(tile)
    spec = resolve_machine(machine)
    inp = _design_inputs(
        path_a,
        path_b,
        mode=mode,
        n_colors=n_colors,
        yarns=yarns,
        width=width,
        resize=resize,
        bank_file=bank_file,
        one_sided=one_sided,
        knitout_on=spec if knitout else None,
    )
    found, edits = _assign(
        inp,
        simplify=simplify,
        suggest=suggest,
        n_colors=n_colors,
        candidates=candidates,
        pool=DEFAULT_POOL if pool is None else pool,
        solver=solver,
        brightness="soft" if soft_brightness else "hard",
    )
    written = min(candidates, len(found))
    if not 1 <= pick <= written:
        raise TileAssignmentError(
            f"--pick must be between 1 and {written} (candidates found), got {pick}"
        )
    targets = seen_targets(inp.qa, inp.qb)
    ranked = rank_designs(
        found,
        targets,
        views=("A", "B") if mode == "double" else ("headon", "side"),
        overrides=overrides,
        rank_by=rank_by,
        knit_time=(
            functools.partial(knit_stats, machine=machine)
            if knit_time or rank_by == "knit-time"
            else None
        ),
        keep=candidates,
    )
    rows = []
    chosen = None
    overlap_lines: list[str] = []
    with staged_dir(outdir) as tmp:
        for rc in ranked:
            row, lines = write_candidate(
                rc,
                tmp,
                inp,
                pick=pick,
                overrides=overrides,
                seen_targets=targets,
                sources=[str(path_a), str(path_b) if path_b else None],
            )
            rows.append(row)
            if row["default"]:
                chosen, overlap_lines = rc.pattern, lines
        if edits:
            write_edits(edits, tmp / "suggestions", scale=max(2, unit_scale(inp.qa.shape)))
        shutil.copyfile(tmp / f"candidate_{pick}" / "pattern.json", tmp / "pattern.json")
        if knitout and chosen is not None:
            # The default candidate as a checked knitout program (mixed-colourwork scheduler).
            from illuknit.cli.knitout_bridge import write_program

            write_program(chosen, tmp, machine=spec)
        summary = {
            "mode": mode,
            "yarns": [{"name": y.name, "rgb": y.hex} for y in inp.yarns],
            "size": {"rows": int(inp.qa.shape[0]), "cols": int(inp.qa.shape[1])},
            "bank": {"name": inp.bank.name, "tiles": len(inp.bank)},
            "solver": solver,
            "ranked_by": rank_by,
            "searched": len(found),
            "edits": [e.to_json() for e in edits],
            "default": pick,
            "candidates": rows,
        }
        atomic_write_text(tmp / "summary.json", json.dumps(summary, indent=1) + "\n")
        atomic_write_text(tmp / "summary.txt", summary_text(summary, overlap_lines))
    return summary


def _assign(
    inp: _Inputs,
    *,
    simplify: bool,
    suggest: bool,
    n_colors: int,
    candidates: int,
    pool: int,
    solver: str,
    brightness: Literal["hard", "soft"],
) -> tuple[Any, list[Any]]:
    """The ranked-by-score tile assignments (``candidates``, or up to ``pool`` within
    :data:`~illuknit.design.tiles.perception.POOL_SECONDS`), after the suggested edits (and the edits)."""
    from illuknit.core.errors import OptionError
    from illuknit.design.tiles.assign import assign_tiles
    from illuknit.design.tiles.headon import uniform_side

    # one search, for the designs written and for measuring each suggested edit
    search: dict[str, Any] = dict(
        bank=inp.bank,
        candidates=candidates,
        pool=pool,
        pool_seconds=POOL_SECONDS,
        solver=solver,
        brightness=brightness,
    )
    edits: list[Any] = []
    first: Any = inp.qa
    second: Any = inp.qb if inp.qb is not None else uniform_side(inp.qa)
    if simplify or suggest:
        if inp.qb is None or inp.b is None or inp.mode != "double":
            raise OptionError("--simplify and --suggest work on double-view designs (two pictures)")
        first, second, edits = _simplified(
            inp.qa,
            inp.qb,
            apply=simplify,
            sources=[inp.a, inp.b],
            # re-quantising stays within the yarns the designer allows (and the --colors range)
            max_colors=min(4, max(n_colors, len(inp.yarns))),
            **search,
        )
    found = assign_tiles(first, second, views=inp.views, **search)  # type: ignore[arg-type]
    return found, edits


@dataclass(frozen=True, eq=False)
class _Inputs:
    """The sized, quantised pictures of a design, its yarns, views and tile bank."""

    mode: str
    a: np.ndarray
    b: np.ndarray | None
    yarns: tuple[Any, ...]
    qa: Any
    qb: Any
    quantised: dict[str, Any]
    views: tuple[str, ...]
    bank: Any


def _design_inputs(
    path_a: Path,
    path_b: Path | None,
    *,
    mode: str,
    n_colors: int,
    yarns: str | None,
    width: int | None,
    resize: bool,
    bank_file: Path | None,
    one_sided: bool,
    knitout_on: Any,
) -> _Inputs:
    """Size and quantise the pictures, choose the yarns and load the bank.

    ``knitout_on`` (a MachineSpec, or None without ``--knitout``): a pattern wider than its bed
    is refused before any design work.
    """
    from illuknit.cli.knitout_bridge import check_fits
    from illuknit.design.tiles.bank import canonical_bank, load_bank
    from illuknit.design.tiles.headon import HEADON_VIEWS
    from illuknit.pictures.images import quantise_image
    from illuknit.pictures.sizing import size_pair

    if knitout_on is not None and width is not None:
        check_fits(knitout_on, width)
    pair = size_pair(path_a, path_b, width=width, stretch=resize)
    a, b = pair.a, pair.b
    if knitout_on is not None:
        check_fits(knitout_on, a.shape[1])
    pictures = [a] if b is None else [a, b]
    ys = _choose_yarns(yarns, n_colors, pictures)
    qa = quantise_image(a, n_colors=n_colors)
    qb = quantise_image(b, n_colors=n_colors) if b is not None else None
    quantised = {"A": qa} if qb is None else {"A": qa, "B": qb}
    views = ("A", "B") if mode == "double" else HEADON_VIEWS
    if bank_file is not None:
        bank = load_bank(bank_file, yarns=ys)
    else:
        bank = canonical_bank(ys, views=views, one_sided_stripes=one_sided)  # type: ignore[arg-type]
    return _Inputs(mode, a, b, ys, qa, qb, quantised, views, bank)


def _simplified(
    qa: Any, qb: Any, *, apply: bool, sources: list[np.ndarray], max_colors: int, **assign: Any
) -> tuple[Any, Any, list[Any]]:
    """Suggested edits of both pictures, each measured by the best design it leads to against
    the ORIGINAL pictures; with ``apply`` the improving ones are kept (tiles.simplify)."""
    from illuknit.design.tiles.simplify import review_edits

    review = review_edits(
        qa,
        qb,
        apply=apply,
        targets=[qa.rgb(), qb.rgb()],
        sources=sources,
        max_colors=max_colors,
        **assign,
    )
    return review.a, review.b, list(review.results)


def _parse_overrides(specs: tuple[str, ...]) -> dict[tuple[int, int], str]:
    """``("0,1=0/1/0^", ...)`` -> ``{(0, 1): "0/1/0^"}`` (colour a of A, colour b of B)."""
    from illuknit.core.errors import TileAssignmentError

    out: dict[tuple[int, int], str] = {}
    for spec in specs:
        pair, sep, rows = spec.partition("=")
        try:
            a, b = (int(v) for v in pair.split(","))
        except ValueError:
            a = b = -1
        if not sep or not rows.strip() or a < 0 or b < 0:
            raise TileAssignmentError(
                f"--tile must look like 'A,B=ROWS' (e.g. '0,1=0/1/0^'), got {spec!r}"
            )
        out[a, b] = rows.strip()
    return out


def _overlap_digest(table: dict[str, Any]) -> list[str]:
    """The default candidate's overlap groups, one line each (details in summary.txt)."""
    views = table["views"]
    by = "both views" if table["grouped_by"] == "both" else table["grouped_by"]
    out = [
        f"default candidate: {table['pairs']} overlap pairs ({views[0]} over {views[1]}), "
        f"grouped by the fill seen from {by}:"
    ]
    for g in table["groups"]:
        out.append(f"  {g['fill']}: {len(g['overlaps'])} overlap(s), {100 * g['share']:.1f} %")
    rare = table["rare"]
    if rare["count"]:
        out.append(
            f"  {rare['count']} rare overlaps (each under {100 * table['rare_below']:.1f} %): "
            f"{100 * rare['share']:.1f} % of the units together"
        )
    return out


def _worst_ghosting(row: dict[str, Any]) -> str:
    """``"0.293 (0.038)"``: the worst view's ghosting and how much of it shows."""
    ghost = [abs(g) for g in row["ghosting"] if g is not None]
    shows = [v for v in row["visible_ghosting"] if v is not None]
    return f"{max(ghost):.3f} ({max(shows):.3f})" if ghost and shows else "-"


def print_summary(summary: dict[str, Any], outdir: Path) -> None:
    from rich.console import Console
    from rich.table import Table

    con = Console(highlight=False, soft_wrap=True)
    t = Table(
        title=f"{summary['mode']}-view candidates ({summary['size']['rows']} x {summary['size']['cols']} units)",
        header_style="bold",
    )
    for col in (
        "rank",
        "",
        "perceptual",
        "readability",
        "contrast",
        "worst ghosting (shows)",
        "knit min",
        "score",
        "fills A",
        "fills B",
    ):
        t.add_column(col)
    for r in summary["candidates"]:
        t.add_row(
            str(r["rank"]),
            "default" if r["default"] else "",
            fmt_number(r["perceptual_score"]),
            " / ".join(fmt_number(v) for v in r["readability"]),
            " / ".join(fmt_number(v) for v in r["contrast"]),
            _worst_ghosting(r),
            fmt_number(r["knit_minutes"], 1),
            f"{r['score']:.1f}",
            "; ".join(r["fills_a"]),
            "; ".join(r["fills_b"]),
        )
    con.print(t)
    default = next((r for r in summary["candidates"] if r["default"]), None)
    if default is not None:
        for line in _overlap_digest(default["overlaps"]):
            con.print(line)
    con.print(
        f"wrote {len(summary['candidates'])} candidate(s), the best-ranked of {summary['searched']} tile "
        f"design(s) searched, to [bold]{outdir}[/] (default: candidate_{summary['default']})"
    )


def design_options(func: Any) -> Any:
    """Options shared by ``double`` and ``headon``."""
    opts = [
        click.option("--colors", "n_colors", type=click.IntRange(2, 4), default=2, show_default=True,
                     help="Colours each picture is quantised to."),
        click.option("--yarns", default=None, metavar="N|LIST",
                     help="Number of yarns chosen from the pictures, or a list like 'black,white,#c03030'. Default: --colors."),
        click.option("--width", type=click.IntRange(2, 1000), default=None,
                     help=f"Pattern width in units (pictures are resized; default: picture width, at most {DEFAULT_MAX_WIDTH})."),
        click.option("--resize", is_flag=True, help="Stretch the second picture onto the first when their aspect ratios differ."),
        click.option("--candidates", type=click.IntRange(1, 50), default=5, show_default=True,
                     help="How many ranked candidates to write."),
        click.option("--pool", type=click.IntRange(1, 200), default=None,
                     help=f"How many tile designs to search and rank before writing the best --candidates "
                     f"[default: {DEFAULT_POOL}; designs past --candidates only within {POOL_SECONDS:g} s]."),
        click.option("--bank", "bank_file", type=click.Path(dir_okay=False, path_type=Path), default=None,
                     help="Custom tile bank (JSON; see docs/tiles.md)."),
        click.option("--pick", type=click.IntRange(1, 50), default=1, show_default=True,
                     help="Which candidate is the default (copied to OUTDIR/pattern.json)."),
        click.option("--rank-by", type=click.Choice(RANK_KEYS), default="perception", show_default=True,
                     help="Order of the candidates: how the views read (perception: worse view's readability, "
                     "contrast floor, ghosting), the assignment's score, or one measure."),
        click.option("--knit-time/--no-knit-time", default=False, show_default=True,
                     help="Also knit every candidate and show the machine's knitting time (ties in the ranking)."),
        click.option("--suggest", is_flag=True,
                     help="Try simplifying edits of the pictures (one colour fewer or more, merge specks, smooth outlines, drop tiny "
                     "overlaps) and write each as before | after with its effect to OUTDIR/suggestions/."),
        click.option("--simplify", is_flag=True,
                     help="Like --suggest, and design with the edits that raise the worse view's readability."),
        click.option("--solver", default="cpsat", show_default=True, help="Solver backend: cpsat, rc2, ..."),
        click.option("--soft-brightness", is_flag=True,
                     help="Prefer, rather than require, keeping each picture's brightness order."),
        click.option("--one-sided", is_flag=True, help="Only tiles that are solid from at least one side."),
        click.option("--tile", multiple=True, metavar="A,B=ROWS",
                     help="Override the tile of overlap pair (colour A of the first picture, colour B "
                     "of the second), e.g. '0,1=0/1/0^' (see fills.json for the pairs). Repeatable."),
        knitout_option("Also compile the default candidate to OUTDIR/program.k and check it."),
        machine_option(),
        format_option(),
        long_floats_option(),
        outdir_option(),
    ]  # fmt: skip
    for opt in reversed(opts):
        func = opt(func)
    return func


@click.command("double")
@click.argument("image_a", type=click.Path(dir_okay=False, path_type=Path))
@click.argument("image_b", type=click.Path(dir_okay=False, path_type=Path))
@design_options
def double(image_a: Path, image_b: Path, outdir: Path, **kw: Any) -> None:
    """Design a double-view illusion: IMAGE_A seen from above, IMAGE_B from below.

    Each picture colour is repainted with a solid or striped fill so that every place where a
    colour of A lies over a colour of B can be knit with a tile of the bank. Writes the ranked
    candidates, each with pattern, previews and repainted inputs, and a summary table.
    Exit code 2 with an explanation when no assignment exists.
    """
    summary = run_design(image_a, image_b, outdir, mode="double", **kw)
    print_summary(summary, outdir)
