"""``illuknit double``: two pictures in, ranked tile-based double-view candidates out.

For each candidate ``candidate_K/`` holds the pattern, its previews (head-on, view A, view B,
contact sheet), the repainted inputs (``repainted_a.png``/``repainted_b.png`` course by course,
``*_average.png`` as seen from afar), ``fills.json`` (the legend: which fill each picture colour
became and which tile each overlap pair uses), a chart and written instructions. The top folder
holds ``summary.txt``/``summary.json`` (a ranked table, the default candidate marked) and the
default candidate's ``pattern.json``. The design is made and written by
:mod:`illuknit.cli.tile_design` (shared with ``illuknit headon``); this module holds the
command, its options and the summary it prints.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from illuknit.cli.design_files import (
    alternative_lines,
    by_hand,
    fmt_number,
    order_lines,
    reads_cells,
    verdict_lines,
)
from illuknit.cli.knitout_bridge import format_option, long_floats_option, machine_option
from illuknit.cli.options import (
    Decorator,
    InputFile,
    declared_option,
    knitout_option,
    old_flag,
    outdir_option,
)
from illuknit.cli.tile_design import DesignRequest, run_design, write_design
from illuknit.core.progress import work_bar
from illuknit.core.views import DEFAULT_SPLIT_SHARE
from illuknit.design.options import RankOptions, SearchOptions
from illuknit.pictures.sizing import DEFAULT_MAX_WIDTH

__all__ = ["DesignRequest", "double", "run_design", "write_design"]


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


#: The summary table's columns, most important first: on a narrow terminal the last ones are
#: dropped (summary.txt has them all).
SUMMARY_COLUMNS = (
    "rank",
    "",
    "perceptual",
    "reads A / B",
    "correlation",
    "ghosting (shows)",
    "contrast",
    "knit min",
    "fills A",
    "fills B",
    "cost ΔE",
)
#: ... and for a design made for hands (or ranked by hand-time), what it costs by hand, after
#: how it reads.
HAND_COLUMNS = ("rows by hand", "hours by hand")


def summary_columns(summary: dict[str, Any]) -> tuple[str, ...]:
    """The columns of ``summary``'s table, most important first."""
    if not by_hand(summary):
        return SUMMARY_COLUMNS
    k = SUMMARY_COLUMNS.index("reads A / B") + 1
    return (*SUMMARY_COLUMNS[:k], *HAND_COLUMNS, *SUMMARY_COLUMNS[k:])


def _summary_cells(r: dict[str, Any]) -> dict[str, str]:
    hand = r.get("hand")
    return {
        "rows by hand": "-" if not hand else f"{hand['knittable_rows']} of {hand['rows']}",
        "hours by hand": "-" if not hand else f"{hand['hours']:.1f}",
        "rank": str(r["rank"]),
        "": "default" if r["default"] else "",
        "perceptual": fmt_number(r["perceptual_score"]),
        "reads A / B": " / ".join(reads_cells(r)),
        "correlation": " / ".join(fmt_number(v) for v in r["readability"]),
        "contrast": " / ".join(fmt_number(v) for v in r["contrast"]),
        "ghosting (shows)": _worst_ghosting(r),
        "knit min": fmt_number(r["knit_minutes"], 1),
        # the tile search's cost (lower is better); a design without tiles has none
        "cost ΔE": "-" if r["score"] is None else f"{r['score']:.1f}",
        "fills A": "; ".join(r["fills_a"]) or r.get("method", ""),
        "fills B": "; ".join(r["fills_b"]),
    }


def summary_table(summary: dict[str, Any], width: int) -> tuple[Any, list[str]]:
    """The candidates table that fits ``width`` columns of terminal, and the columns dropped.

    Columns are dropped from the least important (``SUMMARY_COLUMNS`` order) until no header or
    number would be cut; long cells (the fills) wrap.
    """
    from rich.table import Table

    rows = [_summary_cells(r) for r in summary["candidates"]]
    every = summary_columns(summary)
    columns = list(every)
    title = (
        f"{summary['mode']}-view candidates "
        f"({summary['size']['rows']} x {summary['size']['cols']} units)"
    )
    while True:
        t = Table(title=title, header_style="bold")
        for col in columns:
            wraps = col.startswith("fills")
            # a header or a number is never cut ("perc...") nor broken: it fits whole or goes
            t.add_column(col, no_wrap=not wraps, overflow="fold" if wraps else "ellipsis")
        for cells in rows:
            t.add_row(*(cells[c] for c in columns))
        # each column at its widest cell (a wrapping column at 16), plus the borders
        need = 1 + sum(
            3 + (16 if c.startswith("fills") else max(len(c), *(len(r[c]) for r in rows)))
            for c in columns
        )
        fits = need <= width
        if fits or len(columns) <= 4:
            return t, [c for c in every if c not in columns]
        columns.pop()


def _edits_found(summary: dict[str, Any]) -> str:
    """What the suggested edits found, in a line."""
    edits = summary.get("edits") or []
    if not edits:
        return "suggestions/: no edit to suggest (no specks, ragged outlines or tiny overlaps)"
    better = [e for e in edits if e["readability_after"] > e["readability_before"] + 1e-4]
    head = f"suggestions/: {len(edits)} edit(s) measured"
    if not better:
        return head + ", none makes the worse side read better (see suggestions/suggestions.json)"
    best = max(better, key=lambda e: e["readability_after"] - e["readability_before"])
    return (
        f"{head}, {len(better)} make(s) the worse side read better; best: {best['description']} "
        f"({best['readability_before']:.3f} -> {best['readability_after']:.3f}, ghosting "
        f"{best['ghosting_before']:.3f} -> {best['ghosting_after']:.3f})"
    )


def print_summary(summary: dict[str, Any], outdir: Path) -> None:
    from illuknit.cli.summary import console

    con = console()
    t, dropped = summary_table(summary, con.width)
    con.print(t)
    if dropped:
        con.print(f"(columns left out to fit the terminal: {', '.join(repr(c) for c in dropped)};"
                  " the full table is in summary.txt)")  # fmt: skip
    size, by_hand_size = summary.get("finished_size"), summary.get("hand_finished_size")
    if by_hand_size is not None:  # made for hands: the pattern's size first, the machine's after
        until = "; an estimate until your swatch says otherwise" if by_hand_size["estimate"] else ""
        con.print(
            f"finished size by hand: about [bold]{_size_text(by_hand_size)}[/] "
            f"({by_hand_size['gauge_source']}{until})"
        )
        if size is not None:
            con.print(f"  on the machine: {_size_text(size)} ({size['gauge_source']})")
    elif size is not None:
        con.print(
            f"finished size: [bold]{size['width_cm']} x {size['height_cm']} cm[/] "
            f"({size['width_in']} x {size['height_in']} in) at {size['gauge']} "
            f"({size['gauge_source']})"
        )
    for line in [*verdict_lines(summary), *alternative_lines(summary), *order_lines(summary)]:
        if line:
            con.print(line, markup=False, highlight=False)
    hand_line = _hand_line(summary)
    if hand_line:
        con.print(hand_line, markup=False, highlight=False)
    default = next((r for r in summary["candidates"] if r["default"]), None)
    if default is not None and default["overlaps"] is not None:  # None: a design without tiles
        for line in _overlap_digest(default["overlaps"]):
            con.print(line)
    n = len(summary["candidates"])
    model = " and the constraint model's design made for hands" if summary.get("hand_model") else ""
    con.print(
        f"wrote {n} candidate(s), the best-ranked of {summary['searched']} tile design(s){model} "
        f"searched, to [bold]{outdir}[/] (default: candidate_{summary['default']}):"
    )
    folders = sorted((p.name for p in outdir.iterdir() if p.is_dir()), key=_natural)
    files = sorted(p.name for p in outdir.iterdir() if p.is_file())
    con.print(f"  folders: {', '.join(f + '/' for f in folders)}")
    con.print(f"  files: {', '.join(files)}")
    for note in summary.get("notes", ()):
        con.print(f"note: {note}", markup=False)
    if "suggestions" in folders:
        con.print(f"  {_edits_found(summary)}")


def _size_text(size: dict[str, Any]) -> str:
    """``"144.9 x 34.6 cm (57.1 x 13.6 in) at 27.6 sts x 49.7 rows per 10 cm ..."``."""
    return (
        f"{size['width_cm']} x {size['height_cm']} cm ({size['width_in']} x {size['height_in']} "
        f"in) at {size['gauge']}"
    )


def _hand_line(summary: dict[str, Any]) -> str:
    """The default candidate as a hand knitter works it, one line ("" when not measured)."""
    hand = summary.get("hand")
    if not hand:
        return ""
    default = next((r for r in summary["candidates"] if r["default"]), None)
    reads = [] if default is None else [v for v in default["readability"] if v is not None]
    read = f"{min(reads):.3f}" if reads else "not measured"
    from illuknit.design.tiles.stripes import STRIPE_BANK_NAME

    made = "made for hands" if summary.get("made_for") == "hands" else "made for a machine"
    if summary["bank"] is None:
        made += f", the {summary.get('method', 'constraint model')}"
    elif summary["bank"]["name"] == STRIPE_BANK_NAME:
        made += ", shared stripes: every row in one yarn"
    line = (
        f"by hand ({made}): rows knittable by hand {hand['knittable_rows']} of {hand['rows']} "
        f"(2 yarns with floats of at most 7 sts, or at most 6 intarsia blocks), longest float "
        f"{hand['longest_float']} sts ({hand['catches']} catches), colour changes a row max "
        f"{hand['max_changes']} / mean {hand['mean_changes']:.1f}, about "
        f"{hand['hours']:.1f} hours (estimated); worse-view correlation {read}"
    )
    hm = summary.get("hand_model")
    if hm:
        where = f"ranks {hm['rank']}" if hm.get("rank") else "is not among those shown"
        line += (
            f"\n  the constraint model made for hands ({hm['status']} after "
            f"{hm['wall_time']:.1f} s): its design {where}"
        )
    machine = summary.get("machine_design")
    if machine:
        m = machine["hand"]
        line += (
            f"\n  the design made for a machine: rows knittable by hand {m['knittable_rows']} of "
            f"{m['rows']}, longest float {m['longest_float']} sts, colour changes a row max "
            f"{m['max_changes']} / mean {m['mean_changes']:.1f}, about {m['hours']:.1f} hours; "
            "worse-view correlation "
            f"{machine['worse_readability']:.3f}"
        )
    return line


def _natural(name: str) -> tuple[str, int]:
    """``candidate_10`` after ``candidate_9``."""
    stem, _, num = name.rpartition("_")
    return (stem, int(num)) if num.isdigit() else (name, -1)


def design_options(func: Any) -> Any:
    """Options shared by ``double`` and ``headon``."""
    opts: list[Decorator] = [
        click.option("--colors", "n_colors", type=click.IntRange(2, 4), default=None,
                     help="Colours each picture is quantised to [the pictures' own count when each "
                     "is drawn in the same 3 or 4 flat colours, else 2; a note says which]."),
        click.option("--yarns", default=None, metavar="N|LIST",
                     help="Number of yarns chosen from the pictures, or a list like 'black,white,#c03030'. Default: --colors."),
        click.option("--width", type=click.IntRange(2, 1000), default=None,
                     help=f"Pattern width in units (pictures are resized; default: picture width, at most {DEFAULT_MAX_WIDTH})."),
        click.option("--resize", is_flag=True, help="Stretch the second picture onto the first when their aspect ratios differ."),
        declared_option(SearchOptions, "candidates"),
        declared_option(SearchOptions, "pool"),
        click.option("--bank", "bank_file", type=InputFile("tile bank"), default=None,
                     help="Custom tile bank (JSON; see docs/tiles.md)."),
        click.option("--pick", type=click.IntRange(1, 50), default=1, show_default=True,
                     help="Which candidate is the default (copied to OUTDIR/pattern.json)."),
        declared_option(RankOptions, "rank_by"),
        declared_option(RankOptions, "made_for"),
        declared_option(RankOptions, "knit_time"),
        click.option("--suggest", is_flag=True,
                     help="Try simplifying edits of the pictures (one colour fewer or more, merge specks, smooth outlines, drop tiny "
                     "overlaps) and write each as before | after with its effect to OUTDIR/suggestions/."),
        click.option("--simplify", is_flag=True,
                     help="Like --suggest, and design with the edits that raise the worse view's readability."),
        declared_option(RankOptions, "angle"),
        declared_option(RankOptions, "distance", note="Each candidate's seen.png shows the "
                        "view from there beside the view up close and its picture."),
        declared_option(SearchOptions, "solver"),
        declared_option(SearchOptions, "brightness"),
        old_flag("--soft-brightness", SearchOptions, "brightness", "soft"),
        declared_option(SearchOptions, "one_sided"),
        declared_option(SearchOptions, "split_bumps"),
        declared_option(SearchOptions, "split_share", default=None,
                        note=f"[default: {DEFAULT_SPLIT_SHARE:g}, an estimate]; implies --split-bumps."),
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
@click.argument("image_a", type=InputFile("picture"))
@click.argument("image_b", type=InputFile("picture"))
@declared_option(
    RankOptions,
    "read",
    default=None,
    note="[default: when tesseract is installed] "
    "Word pairs ranked by the reader (--rank-by auto) are read all the same, and the "
    "summary notes it; --rank-by perception --no-read reads nothing.",
)
@declared_option(
    SearchOptions,
    "hand_model_seconds",
    default=None,
    note="[default: 20] With --for hands; its design is ranked with the tile designs and "
    "written as a candidate like them (no tiles, fills or repainted pictures).",
)
@design_options
def double(image_a: Path, image_b: Path, outdir: Path, **kw: Any) -> None:
    """Design a double-view illusion: IMAGE_A seen from above, IMAGE_B from below.

    Each picture colour is repainted with a solid or striped fill so that every place where a
    colour of A lies over a colour of B can be knit with a tile of the bank. Writes the ranked
    candidates, each with pattern, previews and repainted inputs, and a summary table.
    Exit code 2 with an explanation when no assignment exists.
    """
    with work_bar("double") as report:
        request = DesignRequest.from_switches(image_a, image_b, outdir, mode="double", **kw)
        summary = run_design(request, progress=report)
    print_summary(summary, outdir)
