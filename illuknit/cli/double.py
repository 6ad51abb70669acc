"""``illuknit double``: two pictures in, ranked tile-based double-view candidates out.

For each candidate ``candidate_K/`` holds the pattern, its previews (head-on, view A, view B,
contact sheet), the repainted inputs (``repainted_a.png``/``repainted_b.png`` course by course,
``*_average.png`` as seen from afar), ``fills.json`` (the legend: which fill each picture colour
became and which tile each overlap pair uses), a chart and written instructions. The top folder
holds ``summary.txt``/``summary.json`` (a ranked table, the default candidate marked) and the
default candidate's ``pattern.json``.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any

import click
import numpy as np

from illuknit.cli.knitout_bridge import format_option, long_floats_option, machine_option
from illuknit.cli.options import knitout_option, outdir_option
from illuknit.sizing import DEFAULT_MAX_WIDTH
from illuknit.tiles.perception import RANK_KEYS

__all__ = ["double", "run_design"]


def _choose_yarns(spec: str | None, n_colors: int, pictures: list[np.ndarray]) -> tuple[Any, ...]:
    from illuknit.pattern import parse_yarns

    if spec is not None and not spec.strip().isdigit():
        return parse_yarns(spec)
    n = int(spec) if spec is not None else n_colors
    if not 1 <= n <= 8:
        from illuknit.errors import YarnSpecError

        raise YarnSpecError(f"--yarns N must be between 1 and 8, got {n}")
    from illuknit.tiles.yarn_choice import choose_yarns

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
    design work). Returns the summary dict.
    """
    from illuknit.cli.knitout_bridge import check_fits, resolve_machine
    from illuknit.errors import OptionError, TileAssignmentError
    from illuknit.export import export_pattern
    from illuknit.images import quantise_image
    from illuknit.outputs import atomic_write_text, staged_dir
    from illuknit.previews import save_png, unit_scale, upscale
    from illuknit.sizing import size_pair
    from illuknit.tiles.assign import assign_tiles
    from illuknit.tiles.bank import canonical_bank, load_bank
    from illuknit.tiles.compile import repainted_rgb
    from illuknit.tiles.headon import HEADON_VIEWS, uniform_side
    from illuknit.tiles.overlaps import group_overlaps
    from illuknit.tiles.perception import rank_designs

    if candidates < 1:
        raise TileAssignmentError(f"--candidates must be at least 1, got {candidates}")
    overrides = _parse_overrides(tile)
    spec = resolve_machine(machine)
    if knitout and width is not None:
        check_fits(spec, width)
    pair = size_pair(path_a, path_b, width=width, stretch=resize)
    a, b = pair.a, pair.b
    if knitout:
        check_fits(spec, a.shape[1])
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
    second: Any = qb if qb is not None else uniform_side(qa)
    first: Any = qa
    edits: list[Any] = []
    if simplify or suggest:
        if qb is None or b is None or mode != "double":
            raise OptionError("--simplify and --suggest work on double-view designs (two pictures)")
        first, second, edits = _simplified(
            qa,
            qb,
            apply=simplify,
            sources=[a, b],
            # re-quantising stays within the yarns the designer allows (and the --colors range)
            max_colors=min(4, max(n_colors, len(ys))),
            candidates=candidates,
            bank=bank,
            solver=solver,
            brightness="soft" if soft_brightness else "hard",
        )
    found = assign_tiles(
        first,
        second,
        bank=bank,
        candidates=candidates,
        brightness="soft" if soft_brightness else "hard",
        solver=solver,
        views=views,  # type: ignore[arg-type]
    )
    if not 1 <= pick <= len(found):
        raise TileAssignmentError(
            f"--pick must be between 1 and {len(found)} (candidates found), got {pick}"
        )
    names = (
        ("front (head-on)", "side") if mode == "headon" else ("A (from above)", "B (from below)")
    )
    # What each view should show: the designer's quantised pictures (a plain side otherwise).
    seen_targets: list[np.ndarray] = [qa.rgb()]
    if qb is not None:
        seen_targets.append(qb.rgb())
    else:
        side_idx, side_colors = uniform_side(qa)
        seen_targets.append(np.asarray(side_colors, dtype=np.uint8)[np.asarray(side_idx)])
    ranked = rank_designs(
        found,
        seen_targets,
        views=("A", "B") if mode == "double" else ("headon", "side"),
        overrides=overrides,
        rank_by=rank_by,
        knit_time=knit_time,
        machine=machine,
    )
    rows = []
    chosen = None
    overlap_lines: list[str] = []
    with staged_dir(outdir) as tmp:
        for rc in ranked:
            cand, pattern, report, meas = rc.assignment, rc.pattern, rc.report, rc.measures
            if cand.rank == pick:
                chosen = pattern
            sub = tmp / f"candidate_{cand.rank}"
            s = max(2, unit_scale(pattern.shape))
            for over, rows_spec in overrides.items():  # the tiles as knit, overrides included
                cand = cand.with_tile(over, rows_spec)
            cand_json = cand.to_json()  # its "fills" is cand.describe()
            table = group_overlaps(cand)
            overlaps = table.to_json()
            if cand.rank == pick:
                overlap_lines = table.lines()
            report_json = report.to_json()
            rep = {
                "mode": mode,
                "sources": [str(path_a), str(path_b) if path_b else None],
                "assignment": cand_json,
                "tiles_report": report_json,
                "measures": meas.to_json(),
                "default": cand.rank == pick,
            }
            ra = repainted_rgb(cand, 0)
            rb = repainted_rgb(cand, 1)
            export_pattern(
                pattern,
                sub,
                quantised=quantised,
                report=rep,
                title=f"{mode}-view illusion, candidate {cand.rank}",
                targets={f"{names[0]} repainted": ra, f"{names[1]} repainted": rb},
            )
            for which, letter, striped in ((0, "a", ra), (1, "b", rb)):
                average = repainted_rgb(cand, which, mode="average")
                save_png(upscale(striped, s), sub / f"repainted_{letter}.png")
                save_png(upscale(average, s), sub / f"repainted_{letter}_average.png")
            diagnostics = _write_diagnostics(pattern, seen_targets, sub, mode=mode, scale=s)
            fills = cand_json["fills"]
            legend = {
                "views": list(views),
                "fills": fills,
                "tiles": cand_json["tiles"],
                "overlaps": overlaps,
            }
            atomic_write_text(sub / "fills.json", json.dumps(legend, indent=1) + "\n")
            rows.append(
                {
                    "rank": cand.rank,
                    "default": cand.rank == pick,
                    "score": round(cand.score, 2),
                    "score_rank": rc.score_rank,
                    **_measure_fields(meas),
                    "diagnostics": diagnostics,
                    "fills_a": [f["fill"] for f in fills if f["input"] == "A"],
                    "fills_b": [f["fill"] for f in fills if f["input"] == "B"],
                    "error_repainted": report_json["error_repainted"],
                    "error_repainted_interior": report_json["error_repainted_interior"],
                    "color_changes_per_course_max": report_json["color_changes_per_course"]["max"],
                    "overlaps": overlaps,
                    "folder": sub.name,
                }
            )
        if edits:
            _write_edits(edits, tmp / "suggestions", scale=max(2, unit_scale(qa.shape)))
        shutil.copyfile(tmp / f"candidate_{pick}" / "pattern.json", tmp / "pattern.json")
        if knitout and chosen is not None:
            # The default candidate as a checked knitout program (mixed-colourwork scheduler).
            from illuknit.cli.knitout_bridge import write_program

            write_program(chosen, tmp, machine=spec)
        summary = {
            "mode": mode,
            "yarns": [{"name": y.name, "rgb": y.hex} for y in ys],
            "size": {"rows": int(qa.shape[0]), "cols": int(qa.shape[1])},
            "bank": {"name": bank.name, "tiles": len(bank)},
            "solver": solver,
            "ranked_by": rank_by,
            "edits": [e.to_json() for e in edits],
            "default": pick,
            "candidates": rows,
        }
        atomic_write_text(tmp / "summary.json", json.dumps(summary, indent=1) + "\n")
        atomic_write_text(tmp / "summary.txt", _summary_text(summary, overlap_lines))
    return summary


def _simplified(
    qa: Any, qb: Any, *, apply: bool, sources: list[np.ndarray], max_colors: int, **assign: Any
) -> tuple[Any, Any, list[Any]]:
    """Suggested edits of both pictures, each measured by the best design it leads to against
    the ORIGINAL pictures; with ``apply`` the improving ones are kept (tiles.simplify)."""
    from illuknit.tiles.simplify import review_edits

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


def _write_edits(edits: list[Any], folder: Path, *, scale: int) -> None:
    """``suggestions/``: each edit as before | after pictures, and ``suggestions.json``."""
    from illuknit.outputs import atomic_write_text
    from illuknit.previews import save_png, upscale

    folder.mkdir(parents=True, exist_ok=True)
    for e in edits:
        s = e.suggestion
        for letter, before_rgb, after_rgb in zip(
            "ab", s.pictures(edited=False), s.pictures(), strict=True
        ):
            gap = np.full((before_rgb.shape[0], 2, 3), 255, np.uint8)
            pair = np.concatenate([before_rgb, gap, after_rgb], axis=1)
            save_png(upscale(pair, scale), folder / f"{s.name}_{letter}.png")
    data = {"edits": [e.to_json() for e in edits]}
    atomic_write_text(folder / "suggestions.json", json.dumps(data, indent=1) + "\n")


def _measure_fields(m: Any) -> dict[str, Any]:
    """A candidate's perceptual measures as summary-table fields (see tiles.perception)."""
    j = m.to_json()
    return {
        "perceptual_score": j["perceptual_score"],
        "readability": j["readability"],
        "contrast": j["contrast"],
        "ghosting": j["ghosting"],
        "knit_minutes": j["knit_minutes"],
        "machine_passes": j["machine_passes"],
    }


def _write_diagnostics(
    pattern: Any, pictures: list[np.ndarray], sub: Path, *, mode: str, scale: int
) -> dict[str, dict[str, float]]:
    """``diagnostic_<view>.png`` per view: where it shows the wrong shade, where the other
    picture ghosts through. Returns the fractions of units marked, per view."""
    from illuknit.previews import save_png, upscale
    from illuknit.tiles.perception import diagnostic_rgb

    views = ("A", "B") if mode == "double" else ("headon", "A")
    out = {}
    for k, (letter, view) in enumerate(zip(("a", "b"), views, strict=True)):
        other = pictures[1 - k] if mode == "double" else None
        img, stats = diagnostic_rgb(pattern, pictures[k], other, view=view)
        save_png(upscale(img, scale), sub / f"diagnostic_{letter}.png")
        out[letter.upper()] = {key: round(v, 4) for key, v in stats.items()}
    return out


def _parse_overrides(specs: tuple[str, ...]) -> dict[tuple[int, int], str]:
    """``("0,1=0/1/0^", ...)`` -> ``{(0, 1): "0/1/0^"}`` (colour a of A, colour b of B)."""
    from illuknit.errors import TileAssignmentError

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


def _summary_text(summary: dict[str, Any], overlap_lines: list[str]) -> str:
    lines = [
        f"{summary['mode']}-view tile design, {summary['size']['rows']} x {summary['size']['cols']} units, "
        f"yarns: {', '.join(y['name'] + ' ' + y['rgb'] for y in summary['yarns'])}",
        f"bank {summary['bank']['name']} ({summary['bank']['tiles']} tiles), solver {summary['solver']}",
        "",
        f"ranked by {summary.get('ranked_by', 'score')}; readability / contrast / ghosting per view",
        "rank  default  percept  read A  read B  contr A  contr B  ghost  minutes  score    fills of input A | fills of input B",
    ]
    for r in summary["candidates"]:
        mark = "  *    " if r["default"] else "       "
        rd, ct = r["readability"], r["contrast"]
        ghost = max((abs(g) for g in r["ghosting"] if g is not None), default=None)
        lines.append(
            f"{r['rank']:>4}  {mark}  {_fmt(r['perceptual_score']):>7}  {_fmt(rd[0]):>6}  "
            f"{_fmt(rd[1]):>6}  {_fmt(ct[0]):>7}  {_fmt(ct[1]):>7}  {_fmt(ghost):>5}  "
            f"{_fmt(r['knit_minutes'], 1):>7}  {r['score']:>7.2f}  "
            f"{'; '.join(r['fills_a'])} | {'; '.join(r['fills_b'])}"
        )
    lines.append("")
    lines.append(
        "* = default candidate (its pattern is also ./pattern.json); each is in candidate_K/"
    )
    if overlap_lines:
        lines += ["", f"default candidate: {overlap_lines[0]}", *overlap_lines[1:]]
    return "\n".join(lines) + "\n"


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


def _fmt(x: float | None, digits: int = 3) -> str:
    return "-" if x is None else f"{x:.{digits}f}"


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
        "ghosting",
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
            _fmt(r["perceptual_score"]),
            " / ".join(_fmt(v) for v in r["readability"]),
            " / ".join(_fmt(v) for v in r["contrast"]),
            " / ".join(_fmt(v) for v in r["ghosting"]),
            _fmt(r["knit_minutes"], 1),
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
        f"wrote {len(summary['candidates'])} candidate(s) to [bold]{outdir}[/] (default: candidate_{summary['default']})"
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
