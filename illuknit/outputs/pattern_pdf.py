"""A print-ready hand-knitting pattern: ``pattern.pdf`` (and the chart as ``chart.svg``).

What a knitter buying an illusion pattern expects, in this order:

1. **Cover**: the title, the head-on view and the picture seen from either end (drawn in the
   fabric's proportions, angled views foreshortened), the finished size in cm and inches.
2. **Materials and gauge**: each yarn with its length and weight (stitch counts x loop length at
   the gauge, floats, 20 % margin: :func:`illuknit.outputs.hand_pattern.yarn_estimate`), needles for the
   gauge, the gauge swatch; abbreviations; how to read the chart; the technique advice
   (:func:`illuknit.outputs.hand_pattern.hand_advice`); the key.
3. **Chart**, tiled over A4 or Letter pages at a printable cell size (:data:`CELL_MM`): each page
   repeats one stitch column and one row of its neighbours (shaded), stitch numbers along the top
   and bottom counted from the right edge, row numbers on both sides (RS rows at the right, WS
   rows at the left), bold lines every 10 stitches and rows, a section marker every
   :data:`SECTION_ROWS` rows, and a page map.
4. **Written rows**, each with its stitch count and its colourwork note.

Written with fpdf2: a maintained, pure-Python PDF writer (on top of Pillow, already a
dependency) that places text, lines, rectangles and PNGs at exact millimetre positions, which a
tiled chart needs; reportlab does the same but is a larger dependency with C parts, and
matplotlib's PDF backend lays out figures, not pages of text. The core fonts cover Latin-1, so
text outside it (yarn names in other scripts) is written with replacement characters.
"""

from __future__ import annotations

import io
import os
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from illuknit.core.colors import luminance
from illuknit.core.files import atomic_write_bytes, atomic_write_text
from illuknit.core.gauge import Gauge, finished_size
from illuknit.core.pattern import LogicalPattern
from illuknit.outputs.chart import hand_rows
from illuknit.outputs.hand_pattern import hand_advice, written_row, yarn_estimate

__all__ = [
    "CELL_MM",
    "PAGE_SIZES",
    "SECTION_ROWS",
    "ChartTile",
    "chart_svg",
    "chart_tiles",
    "needles_for_gauge",
    "pattern_pdf",
    "write_pattern_pdf",
]

#: Page sizes in mm (width, height), portrait.
PAGE_SIZES = {"A4": (210.0, 297.0), "Letter": (215.9, 279.4)}
#: Chart cell size in mm: a printed chart square of about 4.5 mm reads at arm's length.
CELL_MM = 4.5
#: A section marker every this many rows on the chart.
SECTION_ROWS = 20
MARGIN_MM = 12.0
#: room for the row numbers / stitch numbers around the chart grid
LABEL_MM = 9.0

ABBREVIATIONS = (
    ("k", "knit"),
    ("p", "purl"),
    ("k2", "knit 2 stitches (any number: that many)"),
    ("st(s)", "stitch(es)"),
    ("RS", "right side (the side the picture is seen on)"),
    ("WS", "wrong side"),
    ("CO", "cast on"),
    ("BO", "bind off"),
    ("*...; rep from *", "work the stitches after * and repeat them as told"),
    ("to last N sts", "repeat until N stitches are left, then work what follows"),
)

#: Craft Yarn Council standard yarn weights: stitches per 10 cm, needle sizes, metres per 100 g
#: (typical lengths of each class).
_YARN_CLASSES = (
    (33.0, "lace", "1.5-2.25 mm (US 000-1)", 600.0),
    (27.0, "fingering (super fine)", "2.25-3.25 mm (US 1-3)", 400.0),
    (23.0, "sport (fine)", "3.25-3.75 mm (US 3-5)", 300.0),
    (21.0, "DK (light)", "3.75-4.5 mm (US 5-7)", 225.0),
    (16.0, "worsted (medium)", "4.5-5.5 mm (US 7-9)", 180.0),
    (12.0, "bulky", "5.5-8 mm (US 9-11)", 120.0),
    (0.0, "super bulky", "8-12.75 mm (US 11-17)", 80.0),
)


def needles_for_gauge(stitches_per_10cm: float) -> tuple[str, str, float]:
    """(yarn class, needle sizes, metres per 100 g) whose standard gauge includes this one
    (Craft Yarn Council, Standard Yarn Weight System)."""
    for low, name, needles, metres in _YARN_CLASSES:
        if stitches_per_10cm >= low:
            return name, needles, metres
    raise AssertionError("unreachable")  # the last class starts at 0


@dataclass(frozen=True)
class ChartTile:
    """One chart page: stitch columns ``c0..c1`` and row numbers ``r0..r1`` (inclusive, stitch 1
    at the right edge, row 1 at the bottom), its place ``(across, down)`` on the page map."""

    page: int
    across: int
    down: int
    c0: int
    c1: int
    r0: int
    r1: int


def _spans(total: int, per_page: int) -> list[tuple[int, int]]:
    """1-based inclusive spans of at most ``per_page``, neighbours sharing one (the overlap)."""
    if total <= per_page:
        return [(1, total)]
    spans, start = [], 1
    while True:
        end = min(total, start + per_page - 1)
        spans.append((start, end))
        if end == total:
            return spans
        start = end  # one shared column / row


def chart_tiles(
    stitches: int, rows: int, *, page: str = "A4", cell_mm: float = CELL_MM
) -> list[ChartTile]:
    """The chart's pages: stitches from the right edge, rows from the bottom, page by page from
    the bottom right (where knitting starts), across then up."""
    pw, ph = PAGE_SIZES[page]
    cols = int((pw - 2 * MARGIN_MM - 2 * LABEL_MM) // cell_mm)
    nrows = int((ph - 2 * MARGIN_MM - 2 * LABEL_MM - 14) // cell_mm)
    tiles: list[ChartTile] = []
    for down, (r0, r1) in enumerate(_spans(rows, nrows)):
        for across, (c0, c1) in enumerate(_spans(stitches, cols)):
            tiles.append(ChartTile(len(tiles) + 1, across, down, c0, c1, r0, r1))
    return tiles


def _latin1(text: str) -> str:
    return (
        text.replace("\u2013", "-")
        .replace("\u2014", "-")
        .replace("\u00d7", "x")
        .encode("latin-1", "replace")
        .decode("latin-1")
    )


def _grids(pattern: LogicalPattern) -> tuple[NDArray[np.int16], NDArray[np.bool_]]:
    """(yarn, purl on RS) per chart cell, indexed [row number - 1, stitch number - 1] (stitch 1
    at the right edge, row 1 at the bottom)."""
    rows = hand_rows(pattern)
    yarn = np.stack([r.yarn[::-1] for r in rows])
    purl = np.stack([r.purl_on_rs[::-1] for r in rows])
    return yarn, purl


def _png(rgb: NDArray[np.uint8]) -> io.BytesIO:
    from illuknit.outputs.previews import png_bytes

    return io.BytesIO(png_bytes(rgb))


def pattern_pdf(
    pattern: LogicalPattern,
    *,
    gauge: Gauge,
    title: str = "illuknit illusion pattern",
    page: str = "A4",
    angle: float | None = None,
) -> bytes:
    """The pattern as a print-ready PDF (see the module docstring for its pages)."""
    from fpdf import FPDF

    from illuknit.design.render import RenderParams, render_views
    from illuknit.outputs.previews import chart_rgb, rows_per_unit, unit_scale, upscale

    if page not in PAGE_SIZES:
        raise ValueError(f"`page` must be one of {', '.join(PAGE_SIZES)}, got {page!r}")
    n, m = pattern.shape
    W, H = 2 * m, 2 * n
    size = finished_size(pattern.shape, gauge)
    advice = hand_advice(pattern)
    names = [y.name for y in pattern.yarns]
    yclass, needles, metres_per_100g = needles_for_gauge(gauge.stitches_per_10cm)
    yarn_need = yarn_estimate(pattern, gauge, metres_per_100g=metres_per_100g)

    pdf = FPDF(orientation="P", unit="mm", format=PAGE_SIZES[page])
    pdf.set_auto_page_break(auto=True, margin=MARGIN_MM)
    pdf.set_margins(MARGIN_MM, MARGIN_MM, MARGIN_MM)
    pdf.set_title(_latin1(title))
    pdf.set_creator("illuknit")
    # no time stamp: the same pattern gives the same file (a folder holds one whole design)
    pdf.set_creation_date(datetime(2000, 1, 1, tzinfo=UTC))
    pw, ph = PAGE_SIZES[page]
    usable = pw - 2 * MARGIN_MM

    def heading(text: str, size_pt: float = 14) -> None:
        pdf.set_font("Helvetica", "B", size_pt)
        pdf.multi_cell(0, size_pt * 0.5, _latin1(text), new_x="LMARGIN", new_y="NEXT")
        pdf.ln(1.5)

    def para(text: str, size_pt: float = 10) -> None:
        pdf.set_font("Helvetica", "", size_pt)
        pdf.multi_cell(0, size_pt * 0.45, _latin1(text), new_x="LMARGIN", new_y="NEXT")
        pdf.ln(1)

    # -- cover -------------------------------------------------------------------------------
    pdf.add_page()
    heading(title, 20)
    para(
        f"Finished size: {size.describe()}  -  {W} stitches x {H} rows ({m} x {n} units of "
        f"2 stitches x 2 rows), at {gauge.describe()}."
    )
    s = max(2, unit_scale(pattern.shape, target=400))
    theta = angle if angle is not None else RenderParams().theta
    headon = chart_rgb(pattern, scale=s, unit_aspect=gauge.unit_aspect)
    renders = render_views(pattern, angle=angle)
    sy = rows_per_unit(s, gauge.unit_aspect, angle=theta)
    views = [
        ("Head-on: stripes", headon),
        (f"Seen from above (top edge) at {theta:g} deg", upscale(renders["A"], s, sy)),
        (f"Seen from below (cast-on edge) at {theta:g} deg", upscale(renders["B"], s, sy)),
    ]
    y = pdf.get_y() + 2
    big_w = usable * 0.62
    img_h = big_w * headon.shape[0] / headon.shape[1]
    max_h = ph - y - MARGIN_MM - 10
    if img_h > max_h:
        big_w, img_h = big_w * max_h / img_h, max_h
    pdf.set_font("Helvetica", "", 9)
    pdf.set_xy(MARGIN_MM, y)
    pdf.cell(big_w, 5, _latin1(views[0][0]))
    pdf.image(_png(views[0][1]), x=MARGIN_MM, y=y + 5, w=big_w, h=img_h)
    small_w = usable - big_w - 6
    yy = y
    for label, img in views[1:]:
        h = small_w * img.shape[0] / img.shape[1]
        pdf.set_xy(MARGIN_MM + big_w + 6, yy)
        pdf.multi_cell(small_w, 4, _latin1(label))
        pdf.image(_png(img), x=MARGIN_MM + big_w + 6, y=yy + 9, w=small_w, h=h)
        yy += h + 16
    pdf.set_y(max(y + 5 + img_h, yy) + 4)
    para(
        "Head-on the piece shows stripes; look along it from the top or the bottom edge and the "
        "raised purl ridges hide the rows behind them, and the picture appears. The previews "
        "are drawn in the fabric's proportions; angled views are foreshortened as they are seen.",
        9,
    )

    # -- materials, gauge, abbreviations, reading the chart, advice, key -----------------------
    pdf.add_page()
    heading("Materials")
    for e in yarn_need:
        para(f"- Yarn {e.describe()}")
    para(
        f"Lengths are estimates: each stitch takes about 3.8 stitch widths of yarn at this gauge, "
        f"plus the floats of stranded rows and a 20 % margin for the cast-on, bind-off and ends; "
        f"weights assume {yclass} yarn of about {metres_per_100g:.0f} m per 100 g. Check the "
        "meterage on your ball band."
    )
    para(
        f"- Needles: {needles} for {yclass} yarn, or the size that gives the gauge below. "
        "A tapestry needle to weave in ends."
    )
    heading("Gauge")
    para(
        f"{gauge.stitches_per_10cm:.1f} stitches and {gauge.rows_per_10cm:.1f} rows = 10 cm "
        f"(4 in) in the pattern stitch ({gauge.describe()}; {gauge.source})."
    )
    para(
        "Gauge swatch: cast on 40 stitches and work 40 rows, every other pair of rows with the "
        "wrong-side row knitted (the purl ridges of the pattern), then wash and dry it flat. "
        "Count the stitches across and the rows up 10 cm in the middle. More stitches than "
        "above: use larger needles; fewer: smaller. illuknit can size the design to your gauge: "
        "--fabric-gauge STSxROWS/10cm."
    )
    para(f"Finished size at this gauge: {size.describe()}.")
    heading("Abbreviations")
    for abbr, meaning in ABBREVIATIONS:
        pdf.set_font("Helvetica", "B", 10)
        pdf.cell(38, 5, _latin1(abbr))
        pdf.set_font("Helvetica", "", 10)
        pdf.cell(0, 5, _latin1(meaning), new_x="LMARGIN", new_y="NEXT")
    pdf.ln(2)
    heading("How to read the chart")
    para(
        "Each square is one stitch, in the colour of its yarn. Row 1 is at the bottom (the "
        "cast-on edge). Right-side (RS, odd) rows are read from right to left and have their "
        "number at the right; wrong-side (WS, even) rows are read from left to right and have "
        "their number at the left. A dot is a stitch that shows as a purl on the right side: "
        "purl it on a RS row, knit it on a WS row. Stitches are numbered from the right edge "
        "along the top and bottom; bold lines mark every 10 stitches and 10 rows, and a "
        f"section marker (S1, S2, ...) starts every {SECTION_ROWS} rows. The chart is split "
        "over pages as the page map shows; neighbouring pages repeat one stitch column and one "
        "row (shaded) so you can line them up."
    )
    heading("Working it")
    for line in advice.lines:
        para(line)
    para(
        f"Cast on {W} stitches with {names[int(hand_rows(pattern)[0].yarn[-1])]} and follow the "
        f"chart (or the written rows) from row 1 to row {H}; bind off all stitches knitwise."
    )
    heading("Key")
    _key(pdf, pattern)

    # -- chart pages -----------------------------------------------------------------------------
    yarn, purl = _grids(pattern)
    tiles = chart_tiles(W, H, page=page)
    pdf.add_page()
    heading(f"Chart: {len(tiles)} page{'s' if len(tiles) > 1 else ''}")
    para(
        "Page map (the chart as knitted: row 1 at the bottom, stitch 1 at the right; knitting "
        "starts on the bottom right page):"
    )
    _page_map(pdf, tiles)
    for t in tiles:
        pdf.add_page()
        _chart_page(pdf, t, tiles, yarn, purl, pattern, pw)

    # -- written rows ---------------------------------------------------------------------------
    pdf.add_page()
    heading("Written rows")
    para(f"CO {W} sts with {names[int(hand_rows(pattern)[0].yarn[-1])]}.", 9)
    colourwork = {r.number: r for r in advice.rows}
    pdf.set_font("Helvetica", "", 8.5)
    for row in hand_rows(pattern):
        note = colourwork[row.number].note()
        text = f"Row {row.number} ({row.side}): {written_row(row.worked(), names)}"
        if note:
            text += f" [{note}]"
        pdf.multi_cell(0, 3.9, _latin1(text), new_x="LMARGIN", new_y="NEXT")
    para(f"BO all {W} sts knitwise. Weave in the ends; wash and dry flat.", 9)
    return bytes(pdf.output())


def _key(pdf: Any, pattern: LogicalPattern) -> None:
    sw = 5.0
    if pdf.get_y() + (len(pattern.yarns) + 1) * (sw + 2) > pdf.page_break_trigger:
        pdf.add_page()  # the key on one page
    for y in pattern.yarns:
        x, yy = pdf.get_x(), pdf.get_y()
        pdf.set_fill_color(*y.rgb)
        pdf.rect(x, yy, sw, sw, style="DF")
        pdf.set_xy(x + sw + 3, yy)
        pdf.set_font("Helvetica", "", 10)
        pdf.cell(0, sw, _latin1(f"{y.name} ({y.hex}): a stitch in this yarn"))
        pdf.set_xy(x, yy + sw + 2)
    x, yy = pdf.get_x(), pdf.get_y()
    light = pattern.palette[int(np.argmax(luminance(pattern.palette)))]
    pdf.set_fill_color(*(int(v) for v in light))
    pdf.rect(x, yy, sw, sw, style="DF")
    pdf.set_fill_color(20, 20, 20)
    pdf.ellipse(x + sw / 2 - 0.9, yy + sw / 2 - 0.9, 1.8, 1.8, style="F")
    pdf.set_xy(x + sw + 3, yy)
    pdf.cell(0, sw, "dot: purl on a RS row, knit on a WS row (a purl ridge on the right side)")
    pdf.set_xy(x, yy + sw + 2)


def _page_map(pdf: Any, tiles: list[ChartTile]) -> None:
    across = max(t.across for t in tiles) + 1
    down = max(t.down for t in tiles) + 1
    box = min(14.0, 150.0 / max(across, down))
    x0 = pdf.l_margin + 10
    y0 = pdf.get_y() + 2
    pdf.set_font("Helvetica", "", 8)
    for t in tiles:
        # the chart as knitted: page across 0 at the right, down 0 at the bottom
        x = x0 + (across - 1 - t.across) * box
        y = y0 + (down - 1 - t.down) * box
        pdf.rect(x, y, box, box)
        pdf.set_xy(x, y + box / 2 - 2)
        pdf.cell(box, 4, f"p.{t.page}", align="C")
    pdf.set_xy(pdf.l_margin, y0 + down * box + 4)
    pdf.set_font("Helvetica", "", 8)
    for d in range(down):
        row = [t for t in tiles if t.down == d]
        text = f"Rows {row[0].r0}-{row[0].r1}: " + "; ".join(
            f"page {t.page} sts {t.c0}-{t.c1}" for t in row
        )
        pdf.multi_cell(0, 3.6, text, new_x="LMARGIN", new_y="NEXT")


def _chart_page(
    pdf: Any,
    t: ChartTile,
    tiles: list[ChartTile],
    yarn: NDArray[np.int16],
    purl: NDArray[np.bool_],
    pattern: LogicalPattern,
    pw: float,
) -> None:
    c = CELL_MM
    ncols, nrows = t.c1 - t.c0 + 1, t.r1 - t.r0 + 1
    pdf.set_font("Helvetica", "B", 11)
    pdf.cell(
        0,
        5,
        f"Chart page {t.page} of {len(tiles)}: stitches {t.c0}-{t.c1} (from the right), "
        f"rows {t.r0}-{t.r1}",
        new_x="LMARGIN",
        new_y="NEXT",
    )
    # grid: stitch c0 at the right edge of the page's grid, row r0 at its bottom
    left = MARGIN_MM + LABEL_MM + ((pw - 2 * MARGIN_MM - 2 * LABEL_MM) - ncols * c) / 2
    top = pdf.get_y() + LABEL_MM + 2
    right = left + ncols * c
    bottom = top + nrows * c
    dark = luminance(pattern.palette) <= 0.35
    shared_cols = {t.c0} if t.c0 > 1 else set()
    shared_cols |= {t.c1} if t.c1 < yarn.shape[1] else set()
    shared_rows = {t.r0} if t.r0 > 1 else set()
    shared_rows |= {t.r1} if t.r1 < yarn.shape[0] else set()
    # fills: one rectangle per run of one colour in a row (the overlap shaded), then the grid
    for r in range(t.r0, t.r1 + 1):
        y = bottom - (r - t.r0 + 1) * c
        s = t.c0
        while s <= t.c1:
            yi = int(yarn[r - 1, s - 1])
            shade = s in shared_cols or r in shared_rows
            e = s
            while (
                e < t.c1
                and int(yarn[r - 1, e]) == yi
                and (e + 1 in shared_cols or r in shared_rows) == shade
            ):
                e += 1
            rgb = np.array(pattern.yarns[yi].rgb, dtype=float)
            if shade:  # the overlap with the neighbouring page
                rgb = rgb * 0.8 + np.array([120.0, 120.0, 120.0]) * 0.2
            pdf.set_fill_color(*(int(v) for v in rgb))
            pdf.rect(right - (e - t.c0 + 1) * c, y, (e - s + 1) * c, c, style="F")
            s = e + 1
        for dot in (np.flatnonzero(purl[r - 1, t.c0 - 1 : t.c1]) + t.c0).tolist():
            g = 235 if dark[int(yarn[r - 1, dot - 1])] else 20
            pdf.set_fill_color(g, g, g)
            x = right - (dot - t.c0 + 1) * c
            pdf.ellipse(x + c / 2 - 0.8, y + c / 2 - 0.8, 1.6, 1.6, style="F")
    pdf.set_line_width(0.1)
    pdf.set_draw_color(120, 120, 120)
    for k in range(ncols + 1):
        pdf.line(left + k * c, top, left + k * c, bottom)
    for k in range(nrows + 1):
        pdf.line(left, top + k * c, right, top + k * c)
    # bold lines every 10 stitches and rows (counted from stitch 1 / row 1)
    pdf.set_draw_color(0, 0, 0)
    pdf.set_line_width(0.45)
    for s in range(t.c0 - 1, t.c1 + 1):
        if s % 10 == 0:
            x = right - (s - t.c0 + 1) * c
            pdf.line(x, top, x, bottom)
    for r in range(t.r0 - 1, t.r1 + 1):
        if r % 10 == 0:
            y = bottom - (r - t.r0 + 1) * c
            pdf.line(left, y, right, y)
    pdf.set_line_width(0.3)
    pdf.rect(left, top, ncols * c, nrows * c)
    # stitch numbers along top and bottom (every stitch when it fits, else every 5th and 1)
    pdf.set_font("Helvetica", "", 6)
    for s in range(t.c0, t.c1 + 1):
        if s == 1 or s % 5 == 0 or s in (t.c0, t.c1):
            x = right - (s - t.c0 + 1) * c
            pdf.set_xy(x - 1, top - 4)
            pdf.cell(c + 2, 3.5, str(s), align="C")
            pdf.set_xy(x - 1, bottom + 0.5)
            pdf.cell(c + 2, 3.5, str(s), align="C")
    # row numbers: RS (odd) at the right, WS (even) at the left; section markers at the left
    for r in range(t.r0, t.r1 + 1):
        y = bottom - (r - t.r0 + 1) * c
        pdf.set_font("Helvetica", "B" if r % 10 == 0 else "", 6.5)
        if r % 2 == 1:
            pdf.set_xy(right + 0.5, y + (c - 3.5) / 2)
            pdf.cell(LABEL_MM - 1, 3.5, str(r))
        else:
            pdf.set_xy(left - LABEL_MM + 0.5, y + (c - 3.5) / 2)
            pdf.cell(LABEL_MM - 1, 3.5, str(r), align="R")
        if (r - 1) % SECTION_ROWS == 0:
            pdf.set_font("Helvetica", "B", 7)
            pdf.set_xy(left - LABEL_MM - 7, y + (c - 3.5) / 2)
            pdf.cell(6.5, 3.5, f"S{(r - 1) // SECTION_ROWS + 1}", align="R")
    pdf.set_font("Helvetica", "", 7)
    pdf.set_xy(left, bottom + 5)
    neighbours = []
    for dx, dy, word in ((1, 0, "left"), (-1, 0, "right"), (0, 1, "above"), (0, -1, "below")):
        other = next((o for o in tiles if (o.across, o.down) == (t.across + dx, t.down + dy)), None)
        if other is not None:
            neighbours.append(f"page {other.page} {word}")
    pdf.multi_cell(
        ncols * c,
        3.2,
        _latin1(
            "Row 1 at the bottom; RS rows right to left (number at right), WS rows left to "
            "right (number at left). Dot: purl on RS, knit on WS. Shaded: shared with "
            + (", ".join(neighbours) if neighbours else "no other page")
            + "."
        ),
    )


def chart_svg(pattern: LogicalPattern, *, cell: float = 10.0) -> str:
    """The whole chart as SVG: a square per stitch (runs of one yarn merged), purl dots, stitch
    numbers from the right along the top and bottom, row numbers (RS right, WS left), bold lines
    every 10 stitches and rows."""
    yarn, purl = _grids(pattern)
    H, W = yarn.shape
    pad = 3 * cell
    width, height = W * cell + 2 * pad, H * cell + 2 * pad
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:g}" height="{height:g}" '
        f'viewBox="0 0 {width:g} {height:g}" font-family="Helvetica, Arial, sans-serif" '
        f'font-size="{cell * 0.6:g}">',
        '<rect width="100%" height="100%" fill="white"/>',
    ]
    dark = luminance(pattern.palette) <= 0.35

    def x_of(s: int) -> float:  # left edge of stitch s (1 = right edge)
        return pad + (W - s) * cell

    def y_of(r: int) -> float:  # top edge of row r (1 = bottom)
        return pad + (H - r) * cell

    for r in range(1, H + 1):
        s = 1
        row = yarn[r - 1]
        while s <= W:
            e = s
            while e < W and row[e] == row[s - 1]:
                e += 1
            fill = pattern.yarns[int(row[s - 1])].hex
            out.append(
                f'<rect x="{x_of(e):g}" y="{y_of(r):g}" width="{(e - s + 1) * cell:g}" '
                f'height="{cell:g}" fill="{fill}"/>'
            )
            s = e + 1
        for dot in (np.flatnonzero(purl[r - 1]) + 1).tolist():
            col = "#ebebeb" if dark[int(row[dot - 1])] else "#141414"
            out.append(
                f'<circle cx="{x_of(dot) + cell / 2:g}" cy="{y_of(r) + cell / 2:g}" '
                f'r="{cell * 0.18:g}" fill="{col}"/>'
            )
    for s in range(0, W + 1):
        x = pad + (W - s) * cell
        wide = s % 10 == 0
        out.append(
            f'<line x1="{x:g}" y1="{pad:g}" x2="{x:g}" y2="{pad + H * cell:g}" '
            f'stroke="{"#000" if wide else "#888"}" stroke-width="{1.5 if wide else 0.3}"/>'
        )
    for r in range(0, H + 1):
        y = pad + (H - r) * cell
        wide = r % 10 == 0
        out.append(
            f'<line x1="{pad:g}" y1="{y:g}" x2="{pad + W * cell:g}" y2="{y:g}" '
            f'stroke="{"#000" if wide else "#888"}" stroke-width="{1.5 if wide else 0.3}"/>'
        )
    for s in range(1, W + 1):
        if s == 1 or s % 5 == 0:
            x = x_of(s) + cell / 2
            out.append(f'<text x="{x:g}" y="{pad - cell * 0.4:g}" text-anchor="middle">{s}</text>')
            out.append(
                f'<text x="{x:g}" y="{pad + H * cell + cell:g}" text-anchor="middle">{s}</text>'
            )
    for r in range(1, H + 1):
        y = y_of(r) + cell * 0.8
        if r % 2:
            out.append(f'<text x="{pad + W * cell + cell * 0.3:g}" y="{y:g}">{r}</text>')
        else:
            out.append(f'<text x="{pad - cell * 0.3:g}" y="{y:g}" text-anchor="end">{r}</text>')
    out.append("</svg>")
    return "\n".join(out) + "\n"


def write_pattern_pdf(
    pattern: LogicalPattern,
    outdir: str | os.PathLike[str],
    *,
    gauge: Gauge,
    title: str = "illuknit illusion pattern",
    page: str = "A4",
) -> dict[str, Path]:
    """Write ``pattern.pdf`` and ``chart.svg`` into ``outdir``; name -> path."""
    out = Path(outdir)
    pdf = pattern_pdf(pattern, gauge=gauge, title=title, page=page)
    return {
        "pattern_pdf": atomic_write_bytes(out / "pattern.pdf", pdf),
        "chart_svg": atomic_write_text(out / "chart.svg", chart_svg(pattern)),
    }
