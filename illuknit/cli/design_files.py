"""The output folder of a tile design (``illuknit double`` and ``illuknit headon``).

One folder per ranked candidate (pattern, previews, repainted inputs, ``fills.json``,
diagnostics), the suggested edits, and the text of ``summary.txt``.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from illuknit.core.gauge import Gauge
    from illuknit.pipeline.designs import RankedDesign, TileDesign

__all__ = [
    "HAND_TABLE_HEADS",
    "alternative_lines",
    "by_hand",
    "fmt_number",
    "hand_table",
    "order_lines",
    "reads_cells",
    "summary_text",
    "verdict_lines",
    "write_candidate",
    "write_edits",
    "write_seen",
]


def write_candidate(
    rc: RankedDesign,
    tmp: Path,
    inp: TileDesign,
    *,
    pick: int,
    sources: list[str | None],
    gauge: Gauge | None = None,
    distance: float = 3.0,
    angle: float = 30.0,
) -> tuple[dict[str, Any], list[str]]:
    """Write one ranked candidate of the design ``inp`` into its folder under ``tmp``; returns
    its summary row and overlap lines.

    The tiles are written as knit, with the ranking's overrides; the views are measured against
    what the design's views should show (``inp.targets``). ``gauge`` (an
    :class:`illuknit.core.gauge.Gauge`) is the fabric's: finished size and previews. ``angle``
    and ``distance`` (metres) are the views' in ``seen.png``."""
    if rc.assignment is None:  # the constraint model's design made for hands: no tiles
        return _write_model_candidate(
            rc, tmp, inp, pick=pick, sources=sources, gauge=gauge, distance=distance, angle=angle
        )
    from illuknit.cli.knitout_bridge import chart_kind, hand_border
    from illuknit.core.files import atomic_write_text
    from illuknit.design.tiles.compile import repainted_rgb
    from illuknit.design.tiles.overlaps import group_overlaps
    from illuknit.outputs.export import export_pattern
    from illuknit.outputs.previews import save_png, unit_scale, upscale

    mode = inp.mode
    overrides, seen_targets = inp.ranking.override_map, list(inp.targets)
    names = (
        ("front (head-on)", "side") if mode == "headon" else ("A (from above)", "B (from below)")
    )
    cand, pattern, report, meas = rc.assignment, rc.pattern, rc.report, rc.measures
    sub = tmp / f"candidate_{cand.rank}"
    s = max(2, unit_scale(pattern.shape))
    for over, rows_spec in overrides.items():  # the tiles as knit, overrides included
        cand = cand.with_tile(over, rows_spec)
    cand_json = cand.to_json()  # its "fills" is cand.describe()
    table = group_overlaps(cand)
    overlaps = table.to_json()
    report_json = report.to_json()
    rep = {
        "mode": mode,
        "sources": sources,
        "assignment": cand_json,
        "tiles_report": report_json,
        "measures": meas.to_json(),
        "legibility": _legibility_json(rc),
        "default": cand.rank == pick,
    }
    ra = repainted_rgb(cand, 0)
    rb = repainted_rgb(cand, 1)
    export_pattern(
        pattern,
        sub,
        quantised=inp.quantised,
        report=rep,
        title=f"{mode}-view illusion, candidate {cand.rank}",
        targets={f"{names[0]} repainted": ra, f"{names[1]} repainted": rb},
        gauge=gauge,
        chart=chart_kind(),
        border=hand_border(),
    )
    for which, letter, striped in ((0, "a", ra), (1, "b", rb)):
        average = repainted_rgb(cand, which, mode="average")
        save_png(upscale(striped, s), sub / f"repainted_{letter}.png")
        save_png(upscale(average, s), sub / f"repainted_{letter}_average.png")
    diagnostics = _write_diagnostics(pattern, seen_targets, sub, mode=mode, scale=s)
    write_seen(pattern, seen_targets, sub, mode=mode, gauge=gauge, distance=distance, angle=angle)
    fills = cand_json["fills"]
    legend = {
        "views": list(inp.views),
        "fills": fills,
        "tiles": cand_json["tiles"],
        "overlaps": overlaps,
    }
    atomic_write_text(sub / "fills.json", json.dumps(legend, indent=1) + "\n")
    row = {
        "rank": cand.rank,
        "default": cand.rank == pick,
        "score": round(cand.score, 2),
        "score_rank": rc.score_rank,
        "bank": cand.bank.name,
        **_measure_fields(meas),
        "legibility": _legibility_json(rc),
        "diagnostics": diagnostics,
        "fills_a": [f["fill"] for f in fills if f["input"] == "A"],
        "fills_b": [f["fill"] for f in fills if f["input"] == "B"],
        "error_repainted": report_json["error_repainted"],
        "error_repainted_interior": report_json["error_repainted_interior"],
        "color_changes_per_course_max": report_json["color_changes_per_course"]["max"],
        "overlaps": overlaps,
        "folder": sub.name,
    }
    return row, table.lines() if cand.rank == pick else []


def _write_model_candidate(
    rc: RankedDesign,
    tmp: Path,
    inp: TileDesign,
    *,
    pick: int,
    sources: list[str | None],
    gauge: Gauge | None,
    distance: float,
    angle: float,
) -> tuple[dict[str, Any], list[str]]:
    """:func:`write_candidate` for a design without a tile assignment (the constraint model's
    design made for hands, :mod:`illuknit.pipeline.hand_model`): its pattern, previews and
    diagnostics against what the views should show; no fills, tiles or repainted pictures."""
    from illuknit.cli.knitout_bridge import chart_kind, hand_border
    from illuknit.outputs.export import export_pattern
    from illuknit.outputs.previews import unit_scale

    mode, pattern, meas = inp.mode, rc.pattern, rc.measures
    sub = tmp / f"candidate_{rc.rank}"
    names = ("A (from above)", "B (from below)")
    seen_targets = list(inp.targets)
    rep = {
        "mode": mode,
        "sources": sources,
        "method": rc.label,
        "solver": dict(inp.hand_model or {}),
        "measures": meas.to_json(),
        "legibility": _legibility_json(rc),
        "default": rc.rank == pick,
    }
    export_pattern(
        pattern,
        sub,
        quantised=inp.quantised,
        report=rep,
        title=f"{mode}-view illusion, candidate {rc.rank} ({rc.label})",
        targets=dict(zip(names, seen_targets, strict=True)),
        gauge=gauge,
        chart=chart_kind(),
        border=hand_border(),
    )
    s = max(2, unit_scale(pattern.shape))
    diagnostics = _write_diagnostics(pattern, seen_targets, sub, mode=mode, scale=s)
    write_seen(pattern, seen_targets, sub, mode=mode, gauge=gauge, distance=distance, angle=angle)
    changes = np.count_nonzero(np.diff(pattern.yarn, axis=1), axis=1)
    row = {
        "rank": rc.rank,
        "default": rc.rank == pick,
        "score": None,
        "score_rank": None,
        "bank": None,
        "method": rc.label,
        **_measure_fields(meas),
        "legibility": _legibility_json(rc),
        "diagnostics": diagnostics,
        "fills_a": [],
        "fills_b": [],
        "error_repainted": None,
        "error_repainted_interior": None,
        "color_changes_per_course_max": int(changes.max()) if changes.size else 0,
        "overlaps": None,
        "folder": sub.name,
    }
    return row, []


def write_edits(edits: list[Any], folder: Path, *, scale: int) -> None:
    """``suggestions/``: each edit as before | after pictures, and ``suggestions.json``."""
    from illuknit.core.files import atomic_write_text
    from illuknit.outputs.previews import save_png, upscale

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


def _legibility_json(rc: Any) -> dict[str, Any] | None:
    """The reader's verdict on a candidate's sides (None when it was not read)."""
    verdict = getattr(rc, "legibility", None)
    return None if verdict is None else dict(verdict.to_json())


def _measure_fields(m: Any) -> dict[str, Any]:
    """A candidate's perceptual measures as summary-table fields (see tiles.perception)."""
    j = m.to_json()
    return {
        "perceptual_score": j["perceptual_score"],
        "readability": j["readability"],
        "contrast": j["contrast"],
        "ghosting": j["ghosting"],
        "visible_ghosting": j["visible_ghosting"],
        "knit_minutes": j["knit_minutes"],
        "machine_passes": j["machine_passes"],
        "hand": j.get("hand"),
    }


def _write_diagnostics(
    pattern: Any, pictures: list[np.ndarray], sub: Path, *, mode: str, scale: int
) -> dict[str, dict[str, float]]:
    """``diagnostic_<view>.png`` per view: where it shows the wrong shade, where the other
    picture ghosts through. Returns the fractions of units marked, per view."""
    from illuknit.design.tiles.perception import diagnostic_rgb
    from illuknit.outputs.previews import save_png, upscale

    views = ("A", "B") if mode == "double" else ("headon", "A")
    out = {}
    for k, (letter, view) in enumerate(zip(("a", "b"), views, strict=True)):
        other = pictures[1 - k] if mode == "double" else None
        img, stats = diagnostic_rgb(pattern, pictures[k], other, view=view)
        save_png(upscale(img, scale), sub / f"diagnostic_{letter}.png")
        out[letter.upper()] = {key: round(v, 4) for key, v in stats.items()}
    return out


def write_seen(
    pattern: Any,
    pictures: list[np.ndarray],
    sub: Path,
    *,
    mode: str,
    gauge: Any,
    distance: float,
    angle: float = 30.0,
) -> Path:
    """``seen.png``: per view, what it should show, the render up close at ``angle`` and the
    same render as a 20/20 eye resolves it from ``distance`` metres (the app's far view,
    :func:`~illuknit.design.tiles.perception.seen_from`), side by side.

    The views are side A and side B (double view: picture A then B; single view: picture A
    from both sides), or head-on then side A and B (head-on: the front picture head-on, the
    side picture or a plain field at an angle)."""
    from illuknit.core.gauge import CM_PER_INCH
    from illuknit.design.render.raycast import render_image
    from illuknit.design.tiles.perception import eye_blur_units, seen_from
    from illuknit.outputs.previews import contact_sheet, save_png, unit_scale, upscale

    if gauge is None:
        from illuknit.core.machine import resolve_machine

        gauge = resolve_machine(None).fabric_gauge
    s = min(8, max(2, unit_scale(pattern.shape, target=320)))  # the renderer's finest
    per_inch = gauge.stitches_per_10cm * CM_PER_INCH / 10.0
    sigma = eye_blur_units(distance, gauge=per_inch) * s  # in pixels: s per unit across
    if mode in ("double", "single"):
        views = [("side A", angle, pictures[0]), ("side B", -angle, pictures[-1])]
    else:
        views = [("head-on", 90.0, pictures[0])]
        views += [("side A", angle, pictures[1]), ("side B", -angle, pictures[1])]
    aspect = gauge.unit_aspect
    panels = []
    for name, elevation, picture in views:  # a signed elevation: + side A, - side B
        # in the fabric's proportions, as the picture it should show: the render's
        # foreshortening at a low angle undone (sin of the elevation), so the two compare
        sine = float(np.sin(np.radians(abs(elevation))))
        near = render_image(pattern, elevation, scale=s, unit_aspect=aspect / sine)
        want = np.asarray(picture, dtype=np.uint8)
        if want.size and not np.ptp(want.reshape(-1, 3), axis=0).any():
            # a head-on design without a side picture: any plain field will do, whatever
            # colour stands for it in the measures
            panels.append((f"{name}: a plain field", np.full_like(near, 235)))
        else:
            panels.append((f"{name} should show", upscale(want, s, s * aspect)))
        panels += [
            (f"{name} up close" + ("" if sine == 1.0 else " (unforeshortened)"), near),
            (f"{name} from {distance:g} m", seen_from(near, sigma)),
        ]
    return save_png(contact_sheet(panels, columns=3), sub / "seen.png")


def _bank_line(summary: dict[str, Any]) -> str:
    """The default design's bank and the tile solver, or the method of a design without tiles."""
    bank = summary["bank"]
    if bank is None:
        return f"{summary.get('method', 'no tile bank')}, solver cpsat"
    return f"bank {bank['name']} ({bank['tiles']} tiles), solver {summary['solver']}"


def _hand_model_lines(summary: dict[str, Any]) -> list[str]:
    """Made for hands: the constraint model's solve and where its design ranked."""
    hm = summary.get("hand_model")
    if not hm:
        return []
    where = (
        f"its design ranks {hm['rank']}"
        if hm.get("rank")
        else f"its design is not among the {len(summary['candidates'])} shown"
    )
    return [
        f"constraint model made for hands: {hm['status']} after {hm['wall_time']:.1f} s "
        f"(up to {hm['seconds']:g} s), {hm['objective']} view cells off target; {where}"
    ]


def summary_text(summary: dict[str, Any], overlap_lines: list[str]) -> str:
    lines = [
        f"{summary['mode']}-view tile design, {summary['size']['rows']} x {summary['size']['cols']} units, "
        f"yarns: {', '.join(y['name'] + ' ' + y['rgb'] for y in summary['yarns'])}",
        _bank_line(summary),
        *_hand_model_lines(summary),
        "",
        *verdict_lines(summary),
        *alternative_lines(summary),
        *order_lines(summary),
        f"best {len(summary['candidates'])} of {summary['searched']} tile designs searched, "
        f"ranked by {summary.get('ranked_by', 'score')}; correlation / contrast per view; worst ghosting "
        "and how much of it shows (visible ghosting); whether the reader reads each side",
        "rank  default  percept  corr A  corr B  contr A  contr B  ghost  shows  reads A  reads B  minutes  cost ΔE  fills of input A | fills of input B",
    ]
    for r in summary["candidates"]:
        mark = "  *    " if r["default"] else "       "
        rd, ct = r["readability"], r["contrast"]
        ghost = max((abs(g) for g in r["ghosting"] if g is not None), default=None)
        shows = max((g for g in r["visible_ghosting"] if g is not None), default=None)
        ra, rb = reads_cells(r)
        lines.append(
            f"{r['rank']:>4}  {mark}  {fmt_number(r['perceptual_score']):>7}  {fmt_number(rd[0]):>6}  "
            f"{fmt_number(rd[1]):>6}  {fmt_number(ct[0]):>7}  {fmt_number(ct[1]):>7}  {fmt_number(ghost):>5}  {fmt_number(shows):>5}  "
            f"{ra:>7}  {rb:>7}  {fmt_number(r['knit_minutes'], 1):>7}  {fmt_number(r['score'], 2):>7}  "
            + (
                f"{'; '.join(r['fills_a'])} | {'; '.join(r['fills_b'])}"
                if r.get("bank") is not None or "method" not in r
                else f"({r['method']}: no tiles)"
            )
        )
    lines.append("")
    lines.append(
        "* = default candidate (its pattern is also ./pattern.json); each is in candidate_K/"
    )
    lines += _COLUMN_NOTES
    lines += hand_table(summary)
    if overlap_lines:
        lines += ["", f"default candidate: {overlap_lines[0]}", *overlap_lines[1:]]
    return "\n".join(lines) + "\n"


def by_hand(summary: dict[str, Any]) -> bool:
    """Whether the summary's designs were made for hands or ranked by hand-time: its tables
    then say what each costs by hand."""
    return summary.get("made_for") == "hands" or summary.get("ranked_by") == "hand-time"


#: The columns of :func:`hand_table`.
HAND_TABLE_HEADS = (
    "rank",
    "default",
    "knittable rows",
    "colour rows",
    "changes a row (mean / max)",
    "longest float",
    "catches",
    "hours",
)


def hand_table(summary: dict[str, Any]) -> list[str]:
    """Made for hands (:func:`by_hand`): each candidate's rows as a hand knitter works them, a
    table for summary.txt (none otherwise, or when not measured)."""
    rows = [r for r in summary["candidates"] if r.get("hand")]
    if not by_hand(summary) or not rows:
        return []
    from illuknit.design.hand_cost import (
        COLOUR_STITCHES_PER_MINUTE,
        MINUTES_PER_CHANGE,
        PLAIN_STITCHES_PER_MINUTE,
    )

    out = [
        "",
        "by hand: the rows of each candidate as a hand knitter works them (2 a unit row, "
        "2 stitches a unit)",
        "  ".join(HAND_TABLE_HEADS),
    ]
    for r in rows:
        h = r["hand"]
        cells = (
            str(r["rank"]),
            "*" if r["default"] else "",
            f"{h['knittable_rows']} of {h['rows']}",
            f"{h['colour_rows']} of {h['rows']}",
            f"{h['mean_changes']:.1f} / {h['max_changes']}",
            f"{h['longest_float']} sts",
            str(h["catches"]),
            f"{h['hours']:.1f}",
        )
        out.append(
            "  ".join(c.rjust(len(head)) for c, head in zip(cells, HAND_TABLE_HEADS, strict=True))
        )
    out += [
        "knittable: 2 yarns with floats of at most 7 stitches, or at most 6 intarsia blocks; "
        "longest float: of the rows not worked in intarsia;",
        f"hours: estimated at {PLAIN_STITCHES_PER_MINUTE:g} stitches a minute in one yarn, "
        f"{COLOUR_STITCHES_PER_MINUTE:g} in colour work and {MINUTES_PER_CHANGE:g} min a colour "
        "change (rules of thumb, not measured; --rank-by hand-time ranks by them)",
    ]
    return out


def order_lines(summary: dict[str, Any]) -> list[str]:
    """The order the candidates were ranked in and why, a line (none for an old summary)."""
    order = summary.get("order")
    if not order:
        return []
    chosen = " [--rank-by auto, the default]" if order["asked"] == "auto" else ""
    return [f"order: {order['sentence']}{chosen}"]


def reads_cells(row: dict[str, Any]) -> tuple[str, str]:
    """``("yes", "no")``: whether each side reads (``"yes*"``: a picture, by its shapes);
    ``"-"`` when not read."""
    verdict = row.get("legibility")
    if not verdict:
        return ("-", "-")
    cells = []
    for side in verdict["sides"]:
        word = "yes" if side["reads"] else "no"
        cells.append(word + ("*" if side["judge"] != "reader" else ""))
    return (cells[0], cells[1])


def alternative_lines(summary: dict[str, Any]) -> list[str]:
    """The candidates shown that a user may prefer to the default and why
    (:func:`~illuknit.pipeline.alternatives.alternatives`), each with the switch that picks it."""
    from illuknit.pipeline.alternatives import alternative_sentences

    said = alternative_sentences(summary)
    out = [f"{text}: --pick {rank} to make it the default" for rank, text in said]
    return [*out, ""] if out else []


def verdict_lines(summary: dict[str, Any]) -> list[str]:
    """The reader's verdict on the default candidate, first thing in summary.txt."""
    default = next((r for r in summary["candidates"] if r["default"]), None)
    verdict = None if default is None else default.get("legibility")
    if summary["mode"] != "double":
        return []
    if not verdict:
        return [
            "not read: whether each side reads was not judged (the reader, tesseract, was not "
            "asked or is not installed); the correlations below are not a legibility scale",
            "",
        ]
    words = any(side["judge"] == "reader" for side in verdict["sides"])
    by = f"read by {verdict['reader']}" if words else "judged by its shapes"
    head = (
        f"default candidate, {by} from {verdict['distance_m']:g} m at "
        f"{verdict['angle']:g} degrees: {verdict['sentence']}"
    )
    out = [head]
    if not verdict["all_read"]:
        out.append(_elsewhere(summary))
    step = summary.get("next_step")
    if step:
        out += [
            f"  {step['why']}: a wider piece may read. Next, find the smallest width at which "
            "both sides read (a small search per width, not run here):",
            f"    {step['command']}",
            "  then design at that width: illuknit double ... --width N",
        ]
    return [*out, ""]


def _elsewhere(summary: dict[str, Any]) -> str:
    """Which candidates shown read on both sides, when the default does not."""
    both = [r["rank"] for r in summary["candidates"] if (r.get("legibility") or {}).get("all_read")]
    # ranked by the reader alone, the first design has the most sides that read of all searched
    by_reader = summary.get("ranked_by") == "legibility" and summary.get("made_for") != "hands"
    if both:
        rank_first = "" if by_reader else ", or --rank-by legibility to rank them first"
        return (
            f"  it does not read on every side; read on both: candidate(s) "
            f"{', '.join(map(str, both))} (--pick one{rank_first})"
        )
    if by_reader:
        return "  it does not read on every side, nor does any design searched"
    return (
        "  it does not read on every side, nor does any candidate shown: try --rank-by "
        "legibility, a wider --width, or `illuknit legible` for the smallest width that reads"
    )


#: What the columns of summary.txt mean, written under the table.
_COLUMN_NOTES = [
    "percept: the perceptual score the default order sorts by (higher first): the worse view's",
    "  correlation, less its contrast's shortfall below the floor (docs/tiles.md);",
    "corr: per view, the Pearson correlation (-1 to 1) of the blurred render's luminance with its",
    "  picture's: how much of the light/dark pattern is there. It is not a legibility scale:",
    "  word sides at 0.92-0.95 can be unreadable (docs/legibility.md); below 0, the view shows",
    "  its picture in negative (light and dark swapped);",
    "contr: per view, how much of its light/dark difference survives (1 = all, 0 = a flat field);",
    "ghost, shows: how much of the other picture shows through (0 = none), and the share of",
    "  the view's light/dark variation it makes; minutes: machine knitting time (--knit-time);",
    "reads: whether the reader (tesseract OCR) reads the side's words from the viewing distance;",
    "  yes* / no* on a picture side is an estimate from its light/dark shapes, not a reader's;",
    "cost ΔE: the tile search's own cost (colour distance of the fills to the picture colours",
    "  in CIELAB ΔE, plus stripe and yarn penalties; lower is closer). It never looks at the",
    "  knitted result, so it is not the order of the ranking.",
]


def fmt_number(x: float | None, digits: int = 3) -> str:
    return "-" if x is None else f"{x:.{digits}f}"
