"""The pattern PDF's chart: tiled over pages (:func:`chart_tiles`) with a page map, each page
with its overlap, numbers and section markers; and the whole chart as one SVG
(:func:`chart_svg`, a square a unit or a stitch, as the PDF's).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from illuknit.core.pattern import LogicalPattern
from illuknit.outputs.chart import hand_rows, ink_on
from illuknit.outputs.pdf_document import CELL_MM, LABEL_MM, MARGIN_MM, PAGE_SIZES, _Document

__all__ = ["SECTION_ROWS", "ChartTile", "chart_svg", "chart_tiles"]

#: A section marker every this many rows on the chart.
SECTION_ROWS = 20


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
    stitches: int,
    rows: int,
    *,
    page: str = "A4",
    cell_mm: float = CELL_MM,
    row_mm: float | None = None,
) -> list[ChartTile]:
    """The chart's pages: stitches from the right edge, rows from the bottom, page by page from
    the bottom right (where knitting starts), across then up. A cell is ``cell_mm`` wide and
    ``row_mm`` tall (default ``cell_mm``; the chart uses ``cell_mm`` times the gauge's
    ``unit_aspect``, the fabric's proportions)."""
    pw, ph = PAGE_SIZES[page]
    cols = int((pw - 2 * MARGIN_MM - 2 * LABEL_MM) // cell_mm)
    nrows = int((ph - 2 * MARGIN_MM - 2 * LABEL_MM - 14) // (row_mm or cell_mm))
    tiles: list[ChartTile] = []
    for down, (r0, r1) in enumerate(_spans(rows, nrows)):
        for across, (c0, c1) in enumerate(_spans(stitches, cols)):
            tiles.append(ChartTile(len(tiles) + 1, across, down, c0, c1, r0, r1))
    return tiles


def _grids(
    pattern: LogicalPattern, kind: str = "stitches"
) -> tuple[NDArray[np.int16], NDArray[np.int16], NDArray[np.bool_]]:
    """(yarn of the RS row, yarn of the WS row, dotted) per chart square, indexed [row - 1,
    column - 1] (column 1 at the right edge, row 1 at the bottom). ``kind`` "stitches": a
    square a stitch, dotted where it shows as a purl on the RS; "units": a square a unit (2
    stitches x 2 rows), dotted where it is a ridge."""
    if kind == "units":
        flip = (slice(None, None, -1), slice(None, None, -1))
        return (
            pattern.yarn[flip].astype(np.int16),
            pattern.upper_yarn[flip].astype(np.int16),
            pattern.raised[flip].astype(bool),
        )
    rows = hand_rows(pattern)
    yarn = np.stack([r.yarn[::-1] for r in rows])
    purl = np.stack([r.purl_on_rs[::-1] for r in rows])
    return yarn, yarn, purl


def _chart_pages(doc: _Document) -> None:
    """The page map, then the chart tiled over pages."""
    yarn, upper, dots = _grids(doc.pattern, doc.chart)
    tiles = chart_tiles(yarn.shape[1], yarn.shape[0], page=doc.page, row_mm=doc.row_mm)
    down = max(t.down for t in tiles) + 1
    needed = 30 + min(14.0, 150.0 / max(max(t.across for t in tiles) + 1, down)) * down + 4 * down
    if doc.pdf.get_y() + needed > doc.pdf.page_break_trigger:
        doc.pdf.add_page()  # else the page map shares the key's page
    else:
        doc.pdf.ln(4)
    doc.heading(f"Chart: {len(tiles)} page{'s' if len(tiles) > 1 else ''}")
    doc.para(
        "Page map (the chart as knitted: row 1 at the bottom, stitch 1 at the right; knitting "
        "starts on the bottom right page):"
    )
    _page_map(doc, tiles)
    for t in tiles:
        doc.pdf.add_page()
        _chart_page(doc, t, tiles, (yarn, upper, dots))


def _page_map(doc: _Document, tiles: list[ChartTile]) -> None:
    pdf = doc.pdf
    across = max(t.across for t in tiles) + 1
    down = max(t.down for t in tiles) + 1
    box = min(14.0, 150.0 / max(across, down))
    x0 = pdf.l_margin + 10
    y0 = pdf.get_y() + 2
    doc.font(8)
    for t in tiles:
        # the chart as knitted: page across 0 at the right, down 0 at the bottom
        x = x0 + (across - 1 - t.across) * box
        y = y0 + (down - 1 - t.down) * box
        pdf.rect(x, y, box, box)
        pdf.set_xy(x, y + box / 2 - 2)
        pdf.cell(box, 4, f"p.{t.page}", align="C")
    pdf.set_xy(pdf.l_margin, y0 + down * box + 4)
    for d in range(down):
        row = [t for t in tiles if t.down == d]
        r0, r1 = doc.span(row[0].r0, row[0].r1)
        text = f"Rows {r0}-{r1}: " + "; ".join(
            "page {} sts {}-{}".format(t.page, *doc.span(t.c0, t.c1)) for t in row
        )
        pdf.multi_cell(0, 3.6, text, new_x="LMARGIN", new_y="NEXT")


@dataclass(frozen=True)
class _Grid:
    """Where one chart page's grid sits (mm): stitch ``t.c0`` at the right, row ``t.r0`` at the
    bottom."""

    t: ChartTile
    left: float
    top: float
    row_mm: float = CELL_MM

    @property
    def right(self) -> float:
        return self.left + (self.t.c1 - self.t.c0 + 1) * CELL_MM

    @property
    def bottom(self) -> float:
        return self.top + (self.t.r1 - self.t.r0 + 1) * self.row_mm

    def x(self, stitch: int) -> float:
        """Left edge of ``stitch``'s cell."""
        return self.right - (stitch - self.t.c0 + 1) * CELL_MM

    def y(self, row: int) -> float:
        """Top edge of ``row``'s cell."""
        return self.bottom - (row - self.t.r0 + 1) * self.row_mm


_Grids = tuple[NDArray[np.int16], NDArray[np.int16], NDArray[np.bool_]]


def _chart_page(doc: _Document, t: ChartTile, tiles: list[ChartTile], grids: _Grids) -> None:
    """One page of the chart: title, cells, grid lines, numbers, and what the hatching means."""
    pdf = doc.pdf
    doc.font(11, "B")
    s0, s1 = doc.span(t.c0, t.c1)
    r0, r1 = doc.span(t.r0, t.r1)
    pdf.cell(
        0,
        5,
        f"Chart page {t.page} of {len(tiles)}: stitches {s0}-{s1} (from the right), rows {r0}-{r1}",
        new_x="LMARGIN",
        new_y="NEXT",
    )
    ncols = t.c1 - t.c0 + 1
    free = doc.pw - 2 * MARGIN_MM - 2 * LABEL_MM
    left = MARGIN_MM + LABEL_MM + (free - ncols * CELL_MM) / 2
    g = _Grid(t, left, pdf.get_y() + LABEL_MM + 2, doc.row_mm)
    _chart_cells(doc, g, grids)
    _chart_lines(doc, g)
    _chart_numbers(doc, g)
    doc.font(7)
    pdf.set_xy(g.left, g.bottom + 5)
    neighbours = []
    for dx, dy, word in ((1, 0, "left"), (-1, 0, "right"), (0, 1, "above"), (0, -1, "below")):
        other = next((o for o in tiles if (o.across, o.down) == (t.across + dx, t.down + dy)), None)
        if other is not None:
            neighbours.append(f"page {other.page} {word}")
    square = (
        "A square is 2 stitches x 2 rows: RS row (number at right) knit, WS row (number at "
        "left) purl, or knit where dotted (a ridge)."
        if doc.per == 2
        else "RS rows right to left (number at right), WS rows left to right (number at "
        "left). Dot: purl on RS, knit on WS."
    )
    pdf.multi_cell(
        max(ncols * CELL_MM, 120.0),
        3.2,
        f"Row 1 at the bottom. {square} Hatched: shared with "
        + (", ".join(neighbours) if neighbours else "no other page")
        + ".",
    )


def _chart_cells(doc: _Document, g: _Grid, grids: _Grids) -> None:
    """The squares in their yarns' colours (one rectangle per run; a square whose WS row is in
    another yarn has its top half in that yarn), each run outlined in the ink that contrasts
    with its yarn (:func:`~illuknit.outputs.chart.ink_on`), the overlap with the neighbouring
    pages hatched and the dots, all in that ink."""
    pdf, t, c = doc.pdf, g.t, CELL_MM
    yarn, upper, dots = grids
    rgbs = [tuple(int(v) for v in y.rgb) for y in doc.pattern.yarns]
    inks = [ink_on(rgb) for rgb in rgbs]
    shared_cols = ({t.c0} if t.c0 > 1 else set()) | ({t.c1} if t.c1 < yarn.shape[1] else set())
    shared_rows = ({t.r0} if t.r0 > 1 else set()) | ({t.r1} if t.r1 < yarn.shape[0] else set())
    pdf.set_line_width(0.12)
    for r in range(t.r0, t.r1 + 1):
        y, s = g.y(r), t.c0
        while s <= t.c1:
            key = (int(yarn[r - 1, s - 1]), int(upper[r - 1, s - 1]))
            e = s
            while e < t.c1 and (int(yarn[r - 1, e]), int(upper[r - 1, e])) == key:
                e += 1
            x, w = g.x(e), (e - s + 1) * c
            pdf.set_fill_color(*rgbs[key[0]])
            pdf.rect(x, y, w, g.row_mm, style="F")
            if key[1] != key[0]:  # the WS row in another yarn: the top half
                pdf.set_fill_color(*rgbs[key[1]])
                pdf.rect(x, y, w, g.row_mm / 2, style="F")
            pdf.set_draw_color(*inks[key[0]])
            pdf.rect(x, y, w, g.row_mm, style="D")
            for k in range(1, e - s + 1):
                pdf.line(x + k * c, y, x + k * c, y + g.row_mm)
            s = e + 1
        for col in range(t.c0, t.c1 + 1):
            ink = inks[int(yarn[r - 1, col - 1])]
            if col in shared_cols or r in shared_rows:  # the overlap: hatched
                pdf.set_draw_color(*ink)
                x = g.x(col)
                pdf.line(x, y + g.row_mm, x + c / 2, y)
                pdf.line(x + c / 2, y + g.row_mm, x + c, y)
            if dots[r - 1, col - 1]:
                pdf.set_fill_color(*ink)
                pdf.ellipse(g.x(col) + c / 2 - 0.8, y + g.row_mm / 2 - 0.8, 1.6, 1.6, style="F")


def _chart_lines(doc: _Document, g: _Grid) -> None:
    """Bold lines every 10 stitches and rows (counted from stitch 1 / row 1) and the frame, each
    black on a white halo so it shows on every yarn (the thin lines are :func:`_chart_cells`')."""
    pdf, t = doc.pdf, g.t
    every = 10 // doc.per
    lines = [(g.x(s), g.top, g.x(s), g.bottom) for s in range(t.c0 - 1, t.c1 + 1) if s % every == 0]
    lines += [
        (g.left, g.y(r), g.right, g.y(r)) for r in range(t.r0 - 1, t.r1 + 1) if r % every == 0
    ]
    for width, grey in ((0.9, 255), (0.4, 0)):
        pdf.set_line_width(width)
        pdf.set_draw_color(grey, grey, grey)
        for x0, y0, x1, y1 in lines:
            pdf.line(x0, y0, x1, y1)
        pdf.rect(g.left, g.top, g.right - g.left, g.bottom - g.top)


def _chart_numbers(doc: _Document, g: _Grid) -> None:
    """Stitch numbers along top and bottom (stitch 1, every 10th or 5th and the page's ends);
    row numbers, RS (odd) at the right and WS (even) at the left (a unit square has both);
    section markers at the left."""
    pdf, t, c, per = doc.pdf, g.t, CELL_MM, doc.per
    doc.font(6)
    for s in range(t.c0, t.c1 + 1):
        if s == 1 or s % 5 == 0 or s in (t.c0, t.c1):
            label = per * (s - 1) + 1 if s == t.c0 else per * s
            x = g.x(s)
            pdf.set_xy(x - 1, g.top - 4)
            pdf.cell(c + 2, 3.5, str(label), align="C")
            pdf.set_xy(x - 1, g.bottom + 0.5)
            pdf.cell(c + 2, 3.5, str(label), align="C")
    for r in range(t.r0, t.r1 + 1):
        y = g.y(r) + (g.row_mm - 3.5) / 2
        for row in range(per * (r - 1) + 1, per * r + 1):
            doc.font(6.5, "B" if row % 10 == 0 else "")
            if row % 2 == 1:
                pdf.set_xy(g.right + 0.5, y)
                pdf.cell(LABEL_MM - 1, 3.5, str(row))
            else:
                pdf.set_xy(g.left - LABEL_MM + 0.5, y)
                pdf.cell(LABEL_MM - 1, 3.5, str(row), align="R")
            if (row - 1) % SECTION_ROWS == 0:
                doc.font(7, "B")
                pdf.set_xy(g.left - LABEL_MM - 7, y)
                pdf.cell(6.5, 3.5, f"S{(row - 1) // SECTION_ROWS + 1}", align="R")


def chart_svg(
    pattern: LogicalPattern,
    *,
    cell: float = 10.0,
    unit_aspect: float | None = None,
    chart: str = "units",
) -> str:
    """The whole chart as SVG, as the PDF draws it: ``chart`` "units" (default) a square a unit
    (2 stitches x 2 rows, dotted where it is a ridge; a square whose WS row is in another yarn
    has its top half in that yarn) or "stitches" a square a stitch (dotted where it shows as a
    purl on the RS). Runs of one yarn merged; the thin grid, each run's outline and the dots in
    the ink that contrasts with the run's yarn (:func:`~illuknit.outputs.chart.ink_on`); bold
    lines every 10 stitches and rows, black on a white halo; stitch numbers from the right along
    the top and bottom, row numbers (RS right, WS left). Squares are ``cell`` wide and
    ``unit_aspect`` as tall (the fabric's proportions; default the default machine's gauge)."""
    if unit_aspect is None:
        from illuknit.core.machine import DEFAULT_MACHINE

        unit_aspect = DEFAULT_MACHINE.fabric_gauge.unit_aspect
    yarn, upper, dots = _grids(pattern, chart)
    H, W = yarn.shape
    g = _SvgGrid(W, H, cell, cell * unit_aspect, 2 if chart == "units" else 1)
    width, height = W * cell + 2 * g.pad, H * g.rh + 2 * g.pad
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:g}" height="{height:g}" '
        f'viewBox="0 0 {width:g} {height:g}" font-family="Helvetica, Arial, sans-serif" '
        f'font-size="{cell * 0.6:g}">',
        '<rect width="100%" height="100%" fill="white"/>',
    ]
    rgbs = [tuple(int(v) for v in y.rgb) for y in pattern.yarns]
    inks = ["#000" if ink_on(rgb) == (0, 0, 0) else "#fff" for rgb in rgbs]
    for r in range(1, H + 1):
        out += _svg_row(pattern, g, r, (yarn[r - 1], upper[r - 1], dots[r - 1]), inks)
    out += _svg_lines_and_numbers(g)
    out.append("</svg>")
    return "\n".join(out) + "\n"


@dataclass(frozen=True)
class _SvgGrid:
    """chart.svg's geometry: ``W`` x ``H`` squares of ``cell`` x ``rh``, ``per`` stitches (and
    rows) a square, stitch 1 at the right and row 1 at the bottom."""

    W: int
    H: int
    cell: float
    rh: float
    per: int

    @property
    def pad(self) -> float:
        return 3 * self.cell

    def x(self, s: int) -> float:  # left edge of square s (1 = right edge)
        return self.pad + (self.W - s) * self.cell

    def y(self, r: int) -> float:  # top edge of row r (1 = bottom)
        return self.pad + (self.H - r) * self.rh


def _svg_row(
    pattern: LogicalPattern,
    g: _SvgGrid,
    r: int,
    row: tuple[NDArray[np.int16], NDArray[np.int16], NDArray[np.bool_]],
    inks: list[str],
) -> list[str]:
    """One chart row: its runs filled and outlined (thin lines between squares) in their ink,
    then its dots."""
    yarn, upper, dots = row
    out, s, y = [], 1, g.y(r)
    while s <= g.W:
        key = (int(yarn[s - 1]), int(upper[s - 1]))
        e = s
        while e < g.W and (int(yarn[e]), int(upper[e])) == key:
            e += 1
        x, w = g.x(e), (e - s + 1) * g.cell
        out.append(
            f'<rect x="{x:g}" y="{y:g}" width="{w:g}" height="{g.rh:g}" '
            f'fill="{pattern.yarns[key[0]].hex}"/>'
        )
        if key[1] != key[0]:  # the WS row in another yarn: the top half
            out.append(
                f'<rect class="ws" x="{x:g}" y="{y:g}" width="{w:g}" height="{g.rh / 2:g}" '
                f'fill="{pattern.yarns[key[1]].hex}"/>'
            )
        ink = inks[key[0]]
        path = f"M{x:g} {y:g}h{w:g}v{g.rh:g}h{-w:g}z" + "".join(
            f"M{x + k * g.cell:g} {y:g}v{g.rh:g}" for k in range(1, e - s + 1)
        )
        out.append(f'<path d="{path}" fill="none" stroke="{ink}" stroke-width="0.3"/>')
        s = e + 1
    for dot in (np.flatnonzero(dots) + 1).tolist():
        out.append(
            f'<circle cx="{g.x(dot) + g.cell / 2:g}" cy="{y + g.rh / 2:g}" '
            f'r="{min(g.cell, g.rh) * 0.18:g}" fill="{inks[int(yarn[dot - 1])]}"/>'
        )
    return out


def _svg_lines_and_numbers(g: _SvgGrid) -> list[str]:
    """Bold lines every 10 stitches and rows and the frame, black on a white halo; stitch
    numbers along the top and bottom and row numbers (RS at the right, WS at the left)."""
    every = 10 // g.per
    left, right, top, bottom = g.pad, g.pad + g.W * g.cell, g.pad, g.pad + g.H * g.rh
    d = "".join(f"M{g.x(s) + g.cell:g} {top:g}V{bottom:g}" for s in range(every, g.W, every))
    d += "".join(f"M{left:g} {g.y(r):g}H{right:g}" for r in range(every, g.H, every))
    d += f"M{left:g} {top:g}H{right:g}V{bottom:g}H{left:g}z"
    out = [
        f'<path d="{d}" fill="none" stroke="{colour}" stroke-width="{width}"/>'
        for colour, width in (("#fff", 2.5), ("#000", 1.2))
    ]
    for s in range(1, g.W + 1):
        if s == 1 or s % 5 == 0:
            label, x = g.per * (s - 1) + 1 if s == 1 else g.per * s, g.x(s) + g.cell / 2
            for y in (top - g.cell * 0.4, bottom + g.cell):
                out.append(f'<text x="{x:g}" y="{y:g}" text-anchor="middle">{label}</text>')
    for r in range(1, g.H + 1):
        for row in range(g.per * (r - 1) + 1, g.per * r + 1):
            y = g.y(r) + g.rh * (0.8 if g.per == 1 else (0.55 if row % 2 else 0.95))
            if row % 2:
                out.append(f'<text x="{right + g.cell * 0.3:g}" y="{y:g}">{row}</text>')
            else:
                out.append(
                    f'<text x="{left - g.cell * 0.3:g}" y="{y:g}" text-anchor="end">{row}</text>'
                )
    return out
