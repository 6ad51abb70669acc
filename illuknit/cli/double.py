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
from typing import Any, Literal

import click

from illuknit.cli.design_files import (
    fmt_number,
    reads_cells,
    summary_text,
    verdict_lines,
    write_candidate,
    write_edits,
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
from illuknit.core.gauge import finished_size
from illuknit.core.progress import Report, work_bar
from illuknit.core.views import DEFAULT_SPLIT_SHARE
from illuknit.design.options import MadeFor, RankOptions, SearchOptions
from illuknit.pictures.sizing import DEFAULT_MAX_WIDTH

__all__ = ["double", "run_design", "write_design"]


def _yarns_option(spec: str | None) -> tuple[Any, ...] | int | None:
    """``--yarns``: a number of yarns to choose from the pictures, or a list of yarns."""
    from illuknit.core.pattern import parse_yarns

    if spec is not None and not spec.strip().isdigit():
        return parse_yarns(spec)
    if spec is None:
        return None
    n = int(spec)
    if not 1 <= n <= 8:
        from illuknit.core.errors import YarnSpecError

        raise YarnSpecError(f"--yarns N must be between 1 and 8, got {n}")
    return n


def run_design(
    path_a: Path,
    path_b: Path | None,
    outdir: Path,
    *,
    mode: Literal["double", "headon"] = "double",
    n_colors: int | None = None,
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
    split_bumps: bool = False,
    split_share: float | None = None,
    tile: tuple[str, ...] = (),
    knitout: bool = False,
    machine: str | None = None,
    rank_by: str = "perception",
    knit_time: bool = False,
    simplify: bool = False,
    suggest: bool = False,
    distance: float = 3.0,
    angle: float = 30.0,
    read: bool | None = None,
    made_for: str = "machine",
    progress: Report | None = None,
) -> dict[str, Any]:
    """Parse the options, call :func:`~illuknit.pipeline.stages.design_double` (or
    :func:`~illuknit.pipeline.stages.design_headon`) and write every candidate (atomically into
    ``outdir``); with ``knitout`` the default candidate is knit on ``machine``.
    ``progress(fraction, message)`` hears how far the work is (the command line's bar); the
    designs are judged from ``angle`` degrees and ``distance`` metres; ``read`` asks the reader
    whether each side of the written candidates reads (None: when it is installed);
    ``made_for="hands"`` ranks the designs a hand knitter can work first. Returns the summary."""
    from illuknit.cli.knitout_bridge import design_unit_aspect, resolve_machine
    from illuknit.core.errors import ImageInputError, LongFloatError, TileAssignmentError
    from illuknit.core.views import DEFAULT_SPLIT_SHARE
    from illuknit.design.options import Brightness, PictureEdits, RankBy, RankOptions, SearchOptions
    from illuknit.pipeline.stages import design_double, design_headon

    _check_counts(
        candidates, pool, edits=(simplify or suggest) and (mode != "double" or not path_b)
    )
    overrides = tuple(_parse_overrides(tile).items())
    ranking = RankOptions(
        RankBy(rank_by), knit_time, machine, overrides, angle, distance, read=_read(read, mode),
        made_for=MadeFor(made_for),
    )  # fmt: skip
    spec = resolve_machine(machine)
    search = SearchOptions(
        candidates=candidates,
        solver=solver,
        brightness=Brightness.SOFT if soft_brightness else Brightness.HARD,
        one_sided=one_sided,
        split_bumps=split_bumps or split_share is not None,
        split_share=DEFAULT_SPLIT_SHARE if split_share is None else split_share,
        edits=PictureEdits("apply" if simplify else "suggest" if suggest else "none"),
        **({} if pool is None else {"pool": pool}),
    )
    report: Report = progress or (lambda fraction, message: None)
    pictures = [p for p in (path_a, path_b) if p is not None]
    n_colors, notes = _colour_count(pictures, n_colors, given_yarns=yarns is not None)
    kw: dict[str, Any] = dict(
        n_colors=n_colors,
        yarns=_yarns_option(yarns),
        width=width,
        stretch=resize,
        bank=bank_file,
        search=search,
        ranking=ranking,
        knit_on=spec if knitout else None,
        progress=lambda f, message: report(0.7 * f, message),
        unit_aspect=design_unit_aspect(spec),
    )
    if mode == "double" and path_b is None:
        raise ImageInputError("a double-view design needs two pictures (A and B)")
    redo: Any = design_double if mode == "double" else design_headon
    design = redo(path_a, path_b, **kw)
    written = len(design.designs)
    if not 1 <= pick <= written:
        raise TileAssignmentError(
            f"--pick must be between 1 and {written} (candidates found), got {pick}"
        )
    notes += _split_note(design, search)
    try:
        return write_design(
            design, outdir, pick=pick, sources=[str(path_a), str(path_b) if path_b else None],
            machine=spec if knitout else None, progress=report, gauge=spec.fabric_gauge,
            distance=distance, angle=angle, notes=notes,
        )  # fmt: skip
    except LongFloatError as e:
        report(0.97, "the knitting was refused: measuring what knits it")
        kw["progress"] = lambda f, message: None
        raise _share_remedy(e, outdir, lambda s: redo(path_a, path_b, **{**kw, "search": s}),
                            search, spec) from None  # fmt: skip


def _check_counts(candidates: int, pool: int | None, *, edits: bool) -> None:
    """Refuse counts below one, and picture edits where there are no two pictures."""
    from illuknit.core.errors import OptionError, TileAssignmentError

    if candidates < 1:
        raise TileAssignmentError(f"--candidates must be at least 1, got {candidates}")
    if pool is not None and pool < 1:
        raise TileAssignmentError(f"--pool must be at least 1, got {pool}")
    if edits:
        raise OptionError("--simplify and --suggest work on double-view designs (two pictures)")


def _share_remedy(error: Any, outdir: Path, redesign: Any, search: Any, machine: Any) -> Any:
    """``error`` (a knitting refusal of a split-bump design, the folder written) with the
    default split share measured as a remedy: the design made again at that share and its best
    candidate knit. Said in the error and in the folder's note; ``error`` itself otherwise."""
    import warnings
    from dataclasses import replace

    from illuknit.cli.knitout_bridge import REFUSAL_NOTE
    from illuknit.core.errors import LongFloatError
    from illuknit.core.files import atomic_write_text
    from illuknit.core.views import DEFAULT_SPLIT_SHARE
    from illuknit.knitting import knit_pattern

    if not search.split_bumps or search.split_share <= DEFAULT_SPLIT_SHARE:
        return error
    share = DEFAULT_SPLIT_SHARE
    best = redesign(replace(search, split_share=share, candidates=1)).designs[0].pattern
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            knit = knit_pattern(best, machine=machine).summary()
        line = (
            f"designed again with --split-share {share:g}, it knits (measured: "
            f"{int(best.split.sum())} split bumps, longest float {knit['longest_float']} "
            f"needles skipped, {knit['passes']} passes)"
        )
    except LongFloatError as again:
        line = (
            f"--split-share {share:g} was tried and does not help (a float of {again.length} stays)"
        )
    note, summary = outdir / REFUSAL_NOTE, outdir / "summary.json"
    if note.exists():
        atomic_write_text(note, note.read_text() + f"{line[0].upper()}{line[1:]}\n")
    if summary.exists():
        doc = json.loads(summary.read_text())
        doc["program_refused"] = f"{error}; {line}"
        atomic_write_text(summary, json.dumps(doc, indent=1) + "\n")
    return LongFloatError(
        f"{error}; {line}",
        length=error.length, carrier=error.carrier, from_needle=error.from_needle,
        to_needle=error.to_needle, course=error.course, where=error.where, limit=error.limit,
        count=error.count,
    )  # fmt: skip


#: Most distinct colours a picture may have to count as drawn in flat colours.
_FLAT_MAX = 8


def _flat_colours(path: Path) -> int | None:
    """How many colours ``path`` is drawn in, when it is drawn in a few flat ones (None for a
    photo, a drawing with soft edges, or a picture ``design_*`` will refuse with its own error)."""
    from illuknit.core.errors import ImageInputError
    from illuknit.pictures.decode import read_picture
    from illuknit.pictures.images import flat_color_count

    try:
        return flat_color_count(read_picture(path).rgb, most=_FLAT_MAX)
    except ImageInputError:
        return None


def _colour_count(
    pictures: list[Path], n_colors: int | None, *, given_yarns: bool
) -> tuple[int, list[str]]:
    """The colours each picture is quantised to, and a note saying what was chosen and how to
    change it. Given ``--colors``, that; else the pictures' own count when each is drawn in
    the same 2 to 4 flat colours, else 2 (with a note naming any picture that has more)."""
    if n_colors is not None:
        return n_colors, []
    if given_yarns:  # the yarns decide: no picture is read for its colours
        return 2, []
    counts = [_flat_colours(p) for p in pictures]
    if counts and len(set(counts)) == 1 and counts[0] in (3, 4):
        n = counts[0]
        return n, [f"colours: {n}, the pictures' own count (each is drawn in {n} flat colours); "
                   "--colors N chooses another"]  # fmt: skip
    more = [f"{p.name} has {c}" for p, c in zip(pictures, counts, strict=True) if c and c > 2]
    if more:
        return 2, [f"colours: each picture quantised to 2 (the default), though {', '.join(more)} "
                   "flat colours; --colors 3 or 4 keeps more"]  # fmt: skip
    return 2, []


def _split_note(design: Any, search: Any) -> list[str]:
    """A note when split bumps were allowed but no candidate uses one, and why."""
    if not search.split_bumps or any(int(d.pattern.split.sum()) for d in design.designs):
        return []
    n = len(design.designs)
    return [
        f"--split-bumps changed nothing: none of the {n} candidate(s) uses a split bump. At "
        f"split share {search.split_share:g} (each side sees {100 * search.split_share:.0f} % "
        "of a split bump's colour from its own course) the tile search found plain tiles at "
        "least as good for every overlap; a split share measured higher on a swatch "
        "(--split-share, docs/split-bumps.md) may let it choose them"
    ]


def write_design(
    design: Any,
    outdir: Path,
    *,
    pick: int = 1,
    sources: list[str | None],
    machine: Any = None,
    progress: Report | None = None,
    gauge: Any = None,
    distance: float = 3.0,
    angle: float = 30.0,
    notes: list[str] | None = None,
) -> dict[str, Any]:
    """Write a :class:`~illuknit.pipeline.stages.TileDesign` into ``outdir`` (atomically): each
    candidate's folder, the suggested edits, the default candidate's pattern (and, given a
    machine, its knitout program) and the summary. Returns the summary dict. ``gauge`` (the
    fabric's :class:`~illuknit.core.gauge.Gauge`; default the default machine's) gives the
    finished size; ``angle`` and ``distance`` (metres) the views of each candidate's
    ``seen.png``; ``notes`` (what a switch did or did not do) go into the summary."""
    from illuknit.core.files import atomic_write_text, staged_dir
    from illuknit.outputs.previews import unit_scale

    if gauge is None:
        from illuknit.core.machine import resolve_machine

        gauge = resolve_machine(None).fabric_gauge
    report: Report = progress or (lambda fraction, message: None)

    qa = design.quantised["A"]
    rows = []
    chosen = None
    overlap_lines: list[str] = []
    refused: list[Any] = []  # a knitting refusal, raised once the design is written
    with staged_dir(outdir) as tmp:
        for k, d in enumerate(design.designs):
            n = len(design.designs)
            report(0.7 + 0.24 * k / n, f"writing candidate {k + 1} of {n}")
            row, lines = write_candidate(
                d,
                tmp,
                design,
                pick=pick,
                overrides=design.ranking.override_map,
                seen_targets=list(design.targets),
                sources=sources,
                gauge=gauge,
                distance=distance,
                angle=angle,
            )
            rows.append(row)
            if row["default"]:
                chosen, overlap_lines = d.pattern, lines
        if design.edits:
            write_edits(list(design.edits), tmp / "suggestions", scale=max(2, unit_scale(qa.shape)))
        for name in ("pattern.json", "pattern.pdf", "chart.svg"):  # the picked design's
            shutil.copyfile(tmp / f"candidate_{pick}" / name, tmp / name)
        if machine is not None and chosen is not None:
            # The default candidate as a checked knitout program (mixed-colourwork scheduler).
            from illuknit.cli.knitout_bridge import write_program

            report(0.94, "knitting the default candidate and checking it")
            write_program(chosen, tmp, machine=machine, refused=refused)
        summary = {
            "mode": design.mode,
            "yarns": [{"name": y.name, "rgb": y.hex} for y in design.yarns],
            "size": {"rows": int(qa.shape[0]), "cols": int(qa.shape[1])},
            "finished_size": finished_size(qa.shape, gauge).as_dict(),
            "bank": {"name": design.bank.name, "tiles": len(design.bank)},
            "solver": design.search.solver,
            "ranked_by": design.ranking.rank_by.value,
            "made_for": design.ranking.made_for.value,
            "hand": _hand_json(design.designs[pick - 1]),
            "searched": design.searched,
            "edits": [e.to_json() for e in design.edits],
            "default": pick,
            "candidates": rows,
            **({"program_refused": str(refused[0])} if refused else {}),
            "notes": list(notes or ()),
        }
        if rows and rows[0].get("legibility"):
            summary["read_by"] = rows[0]["legibility"]["reader"]
        atomic_write_text(tmp / "summary.json", json.dumps(summary, indent=1) + "\n")
        text = summary_text(summary, overlap_lines)
        atomic_write_text(tmp / "summary.txt", text + "".join(f"note: {n}\n" for n in notes or ()))
    if refused:
        raise refused[0]
    return summary


def _read(read: bool | None, mode: str) -> bool:
    """``--read/--no-read``: None reads a double view's sides when the reader is installed."""
    if read is not None:
        return read
    from illuknit.design.legibility import reader_available

    return mode == "double" and reader_available()


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


def _summary_cells(r: dict[str, Any]) -> dict[str, str]:
    return {
        "rank": str(r["rank"]),
        "": "default" if r["default"] else "",
        "perceptual": fmt_number(r["perceptual_score"]),
        "reads A / B": " / ".join(reads_cells(r)),
        "correlation": " / ".join(fmt_number(v) for v in r["readability"]),
        "contrast": " / ".join(fmt_number(v) for v in r["contrast"]),
        "ghosting (shows)": _worst_ghosting(r),
        "knit min": fmt_number(r["knit_minutes"], 1),
        "cost ΔE": f"{r['score']:.1f}",  # the tile search's cost (lower is better)
        "fills A": "; ".join(r["fills_a"]),
        "fills B": "; ".join(r["fills_b"]),
    }


def summary_table(summary: dict[str, Any], width: int) -> tuple[Any, list[str]]:
    """The candidates table that fits ``width`` columns of terminal, and the columns dropped.

    Columns are dropped from the least important (``SUMMARY_COLUMNS`` order) until no header or
    number would be cut; long cells (the fills) wrap.
    """
    from rich.table import Table

    rows = [_summary_cells(r) for r in summary["candidates"]]
    columns = list(SUMMARY_COLUMNS)
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
            return t, [c for c in SUMMARY_COLUMNS if c not in columns]
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
    size = summary.get("finished_size")
    if size is not None:
        con.print(
            f"finished size: [bold]{size['width_cm']} x {size['height_cm']} cm[/] "
            f"({size['width_in']} x {size['height_in']} in) at {size['gauge']} "
            f"({size['gauge_source']})"
        )
    for line in verdict_lines(summary):
        if line:
            con.print(line, markup=False, highlight=False)
    hand_line = _hand_line(summary)
    if hand_line:
        con.print(hand_line, markup=False, highlight=False)
    default = next((r for r in summary["candidates"] if r["default"]), None)
    if default is not None:
        for line in _overlap_digest(default["overlaps"]):
            con.print(line)
    n = len(summary["candidates"])
    con.print(
        f"wrote {n} candidate(s), the best-ranked of {summary['searched']} tile design(s) "
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


def _hand_json(d: Any) -> dict[str, Any] | None:
    hand = getattr(d.measures, "hand", None)
    return None if hand is None else dict(hand.to_json())


def _hand_line(summary: dict[str, Any]) -> str:
    """The default candidate as a hand knitter works it, one line ("" when not measured)."""
    hand = summary.get("hand")
    if not hand:
        return ""
    default = next((r for r in summary["candidates"] if r["default"]), None)
    reads = [] if default is None else [v for v in default["readability"] if v is not None]
    read = f"{min(reads):.3f}" if reads else "not measured"
    made = "made for hands" if summary.get("made_for") == "hands" else "made for a machine"
    return (
        f"by hand ({made}): rows knittable by hand {hand['knittable_rows']} of {hand['rows']} "
        f"(2 yarns with floats of at most 7 sts, or at most 6 intarsia blocks), longest float "
        f"{hand['longest_float']} sts ({hand['catches']} catches), colour changes a row max "
        f"{hand['max_changes']} / mean {hand['mean_changes']:.1f}; worse-view readability {read}"
    )


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
@declared_option(RankOptions, "read", default=None, note="[default: when tesseract is installed]")
@design_options
def double(image_a: Path, image_b: Path, outdir: Path, **kw: Any) -> None:
    """Design a double-view illusion: IMAGE_A seen from above, IMAGE_B from below.

    Each picture colour is repainted with a solid or striped fill so that every place where a
    colour of A lies over a colour of B can be knit with a tile of the bank. Writes the ranked
    candidates, each with pattern, previews and repainted inputs, and a summary table.
    Exit code 2 with an explanation when no assignment exists.
    """
    with work_bar("double") as report:
        kw["soft_brightness"] = kw.pop("brightness") == "soft"
        summary = run_design(image_a, image_b, outdir, mode="double", progress=report, **kw)
    print_summary(summary, outdir)
