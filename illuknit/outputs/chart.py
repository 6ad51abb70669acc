"""Hand-knitting output: a stitch chart (PNG) and row-by-row written instructions.

Hand knitters are the traditional makers of single-view ("shadow") illusions, worked flat in garter
ridges on a stockinette ground. Each logical unit is 2 stitches wide and 2 rows tall:

* the first row of a unit (a right-side row) is knit;
* the second (a wrong-side row) is purled where the unit is flat (stockinette on the right side)
  and knit where it is raised, which shows a purl ridge on the right side — the bump.

Rows are numbered from the cast-on edge, which is the **bottom** of the picture (pattern row N-1).
Odd rows are right-side (RS) rows, worked from the right edge of the chart to the left; even rows
are wrong-side (WS) rows, worked from the left edge to the right. On the chart a dot marks a
stitch that shows as a purl on the right side.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from illuknit.core.arguments import check_instance, check_number, check_str
from illuknit.core.colors import luminance
from illuknit.core.gauge import Gauge, finished_size
from illuknit.core.pattern import LogicalPattern, check_pattern
from illuknit.outputs.hand_pattern import hand_advice, written_row

__all__ = [
    "HandRow",
    "chart_key",
    "chart_png_rgb",
    "chart_row_labels",
    "contrast_ratio",
    "hand_rows",
    "ink_on",
    "written_instructions",
]


def contrast_ratio(a: Sequence[int], b: Sequence[int]) -> float:
    """WCAG 2 contrast ratio of two sRGB colours: 1 (the same) to 21 (black on white).

    >>> round(contrast_ratio((0, 0, 0), (255, 255, 255)), 1)
    21.0
    """
    la, lb = (float(luminance(np.array(c, dtype=float))) for c in (a, b))
    return (max(la, lb) + 0.05) / (min(la, lb) + 0.05)


def ink_on(rgb: Sequence[int]) -> tuple[int, int, int]:
    """Black or white, whichever contrasts more with a yarn of colour ``rgb``: the colour the
    chart's grid lines, hatching and dots are drawn in on that yarn. Its contrast ratio is at
    least 4.58 on any colour (mid-grey #808080 gets black, 5.3), where a fixed grey line
    vanishes on a grey yarn.

    >>> ink_on((128, 128, 128)), ink_on((40, 40, 40))
    ((0, 0, 0), (255, 255, 255))
    """
    black, white = (0, 0, 0), (255, 255, 255)
    return black if contrast_ratio(rgb, black) >= contrast_ratio(rgb, white) else white


@dataclass(frozen=True)
class HandRow:
    """One hand-knitting row.

    Attributes
    ----------
    number : int
        1-based row number from the cast-on edge.
    side : {"RS", "WS"}
    purl_on_rs : ndarray of shape (2M,), bool
        Stitches that show as purls on the right side, in chart order (left to right on the RS).
    yarn : ndarray of shape (2M,), int
        Yarn index per stitch, chart order.
    """

    number: int
    side: str
    purl_on_rs: NDArray[np.bool_]
    yarn: NDArray[np.int16]

    def worked(self) -> list[tuple[str, int]]:
        """(stitch as worked, yarn) in working order: RS rows right-to-left, WS rows left-to-right."""
        if self.side == "RS":
            ops = np.where(self.purl_on_rs, "p", "k")[::-1]
            ys = self.yarn[::-1]
        else:  # a purl seen on the RS is knit from the WS, and vice versa
            ops = np.where(self.purl_on_rs, "k", "p")
            ys = self.yarn
        return list(zip(ops.tolist(), ys.tolist(), strict=True))


def hand_rows(pattern: LogicalPattern) -> list[HandRow]:
    """The 2N hand-knitting rows of a pattern, from the cast-on edge up."""
    n, _ = pattern.shape
    rows: list[HandRow] = []
    for k in range(2 * n):
        unit_row = n - 1 - k // 2
        # a unit's second row takes its second course's yarn (split bumps: LogicalPattern.upper)
        yarn = np.repeat((pattern.yarn if k % 2 == 0 else pattern.upper_yarn)[unit_row], 2)
        if k % 2 == 0:
            purl = np.zeros(yarn.shape, dtype=bool)
        else:
            purl = np.repeat(pattern.raised[unit_row], 2)
        rows.append(HandRow(k + 1, "RS" if k % 2 == 0 else "WS", purl, yarn))
    return rows


def written_instructions(
    pattern: LogicalPattern, *, title: str | None = None, gauge: Gauge | None = None
) -> str:
    """Row-by-row written instructions for knitting the pattern by hand.

    Examples
    --------
    >>> from illuknit.core.pattern import parse_yarns
    >>> p = LogicalPattern(np.array([[0, 0], [1, 1]]), np.array([[1, 0], [0, 0]]), parse_yarns("black,white"))
    >>> for line in written_instructions(p).splitlines()[-3:]:
    ...     print(line)
    Row 3 (RS): with black, knit across (4 sts).
    Row 4 (WS): with black, k2, p2 (4 sts).
    Bind off all 4 sts knitwise.
    """
    check_pattern(pattern)
    if title is not None:
        check_str(title, "title")
    if gauge is not None:
        check_instance(gauge, Gauge, "gauge")
    n, m = pattern.shape
    names = [y.name for y in pattern.yarns]
    lines = [
        title or "illuknit illusion pattern",
        f"Size: {n} x {m} units = {2 * m} stitches x {2 * n} rows.",
        *(
            [
                f"Finished size: {finished_size(pattern.shape, gauge).describe()} at "
                f"{gauge.describe()} ({gauge.source})."
            ]
            if gauge is not None
            else []
        ),
        "Yarns: " + ", ".join(f"{y.name} ({y.hex})" for y in pattern.yarns) + ".",
        "RS rows are worked from the right edge of the chart, WS rows from the left. A purl ridge on",
        "the right side (made by knitting on a WS row) is a raised unit: it hides the row above or",
        "below it when the fabric is seen at an angle.",
    ]
    advice = hand_advice(pattern)
    lines += ["", *advice.lines]
    colourwork = {r.number: r for r in advice.rows}
    first = hand_rows(pattern)[0]
    lines.append("")
    lines.append(f"Cast on {2 * m} sts with {names[int(first.yarn[-1])]}.")
    for row in hand_rows(pattern):
        note = colourwork[row.number].note()
        note = f" [{note}]" if note else ""
        lines.append(f"Row {row.number} ({row.side}): {written_row(row.worked(), names)}{note}")
    lines.append(f"Bind off all {2 * m} sts knitwise.")
    return "\n".join(lines) + "\n"


def chart_key(pattern: LogicalPattern) -> list[str]:
    """The chart's key, one entry per line: each yarn's square, then what a dot means."""
    lines = [f"square = a stitch in {y.name} ({y.hex})" for y in pattern.yarns]
    lines.append("dot = purl on the right side (knit on the wrong side): a raised ridge")
    lines.append("row 1 (RS) at the bottom; RS rows are read right to left, WS rows left to right")
    return lines


def chart_png_rgb(
    pattern: LogicalPattern, *, cell: int | None = None, unit_aspect: float | None = None
) -> NDArray[np.uint8]:
    """A stitch chart as an image: one cell per stitch, purls on the RS dotted, rows numbered.

    Row 1 is at the bottom; RS row numbers are written on the right, WS on the left. Below the
    chart a key shows each yarn's colour and what a dot means (:func:`chart_key`). A cell is
    ``cell`` pixels wide and ``unit_aspect`` as tall (a stitch's height over its width in the
    fabric, :attr:`illuknit.core.gauge.Gauge.unit_aspect`; default the default machine's gauge),
    so the chart has the fabric's proportions: a round motif is round on it.
    """
    if unit_aspect is None:
        from illuknit.core.machine import DEFAULT_MACHINE

        unit_aspect = DEFAULT_MACHINE.fabric_gauge.unit_aspect
    aspect = check_number(unit_aspect, "unit_aspect", min=0.05, max=20)
    chart = _chart_body(pattern, cell=cell, aspect=aspect)
    return _with_key(chart, pattern)


def _with_key(chart: NDArray[np.uint8], pattern: LogicalPattern) -> NDArray[np.uint8]:
    from PIL import Image, ImageDraw, ImageFont

    try:
        font = ImageFont.load_default(size=13)
    except TypeError:
        font = ImageFont.load_default()
    lines = chart_key(pattern)
    line_h, sw = 20, 14
    key_w = 40 + max(int(font.getlength(t)) for t in lines)
    width = max(chart.shape[1], key_w)
    img = Image.new("RGB", (width, chart.shape[0] + 10 + line_h * len(lines)), (255, 255, 255))
    img.paste(Image.fromarray(chart), (0, 0))
    draw = ImageDraw.Draw(img)
    y0 = chart.shape[0] + 8
    for i, text in enumerate(lines):
        y = y0 + i * line_h
        box = (8, y, 8 + sw, y + sw)
        if i < len(pattern.yarns):
            draw.rectangle(
                box, fill=tuple(int(v) for v in pattern.yarns[i].rgb), outline=(90, 90, 90)
            )
        elif i == len(pattern.yarns):  # the dot, on the lightest yarn as in the chart
            light = pattern.palette[int(np.argmax(luminance(pattern.palette)))]
            draw.rectangle(box, fill=tuple(int(v) for v in light), outline=(90, 90, 90))
            draw.ellipse((8 + 4, y + 4, 8 + sw - 4, y + sw - 4), fill=(20, 20, 20))
        draw.text((8 + sw + 8, y), text, fill=(40, 40, 40), font=font)
    return np.asarray(img)


def _chart_body(pattern: LogicalPattern, *, cell: int | None, aspect: float) -> NDArray[np.uint8]:
    from PIL import Image, ImageDraw

    n, m = pattern.shape
    rows = hand_rows(pattern)
    w, h = 2 * m, 2 * n
    c = cell or int(max(4, min(14, 2400 // max(w, h))))
    ch = max(2, round(c * aspect))  # cell height: the fabric's proportions
    margin = 40
    img = Image.new("RGB", (w * c + 2 * margin, h * ch + 2 * margin), (255, 255, 255))
    pal = pattern.palette
    yarn = np.zeros((h, w), dtype=np.int16)
    purl = np.zeros((h, w), dtype=bool)
    for r in rows:
        y = h - r.number  # row 1 at the bottom
        yarn[y] = r.yarn
        purl[y] = r.purl_on_rs
    big = np.repeat(np.repeat(pal[yarn], ch, 0), c, 1)
    # grid lines, purl dots: in the ink (black or white) that contrasts with each cell's yarn
    ink = np.array([ink_on(tuple(int(v) for v in rgb)) for rgb in pal], dtype=np.uint8)
    inked = np.repeat(np.repeat(ink[yarn], ch, 0), c, 1)
    if c >= 6:
        big[::ch] = inked[::ch]
        big[:, ::c] = inked[:, ::c]
    # Purl dots: one disc rasterised once by Pillow, stamped into every purl cell in the stitch's
    # contrasting tone (a per-stitch ellipse call was the slowest part of writing a chart).
    rad = max(1, min(c, ch) // 5)
    stamp = Image.new("1", (c, ch), 0)
    ImageDraw.Draw(stamp).ellipse(
        (c // 2 - rad, ch // 2 - rad, c // 2 + rad, ch // 2 + rad), fill=1
    )
    disc = np.asarray(stamp, dtype=bool)
    dots = np.repeat(np.repeat(purl, ch, 0), c, 1) & np.tile(disc, (h, w))
    big[dots] = inked[dots]
    img.paste(Image.fromarray(big), (margin, margin))
    _number_chart(ImageDraw.Draw(img), w, h, c, ch, margin)
    return np.asarray(img)


def chart_row_labels(rows: int, row_px: int) -> list[tuple[int, str]]:
    """Which rows ``chart.png`` numbers, and on which side: ``(row, "right")`` for RS (odd)
    rows, ``(row, "left")`` for WS (even) rows, as hand charts do; every row when rows are 16
    pixels or taller, else every ``step``-th pair (both of its rows), and the last row.

    >>> chart_row_labels(6, 20)
    [(1, 'right'), (2, 'left'), (3, 'right'), (4, 'left'), (5, 'right'), (6, 'left')]
    >>> chart_row_labels(10, 5)[:4]
    [(1, 'right'), (2, 'left'), (7, 'right'), (8, 'left')]
    """
    step = max(1, 16 // row_px) * 2
    out = []
    for r in range(1, rows + 1):
        pair_start = r if r % 2 else r - 1
        if (pair_start - 1) % step == 0 or r == rows:
            out.append((r, "right" if r % 2 else "left"))
    return out


def _number_chart(draw: Any, w: int, h: int, c: int, ch: int, margin: int) -> None:
    """Stitch numbers (from the right edge) along the top and bottom, row numbers at the sides."""
    from PIL import ImageFont

    try:
        font = ImageFont.load_default(size=max(9, min(14, 2 * ch, c + 4)))
    except TypeError:
        font = ImageFont.load_default()
    grey = (60, 60, 60)
    for r, side in chart_row_labels(h, ch):
        y = margin + (h - r) * ch + ch // 2
        if side == "right":
            draw.text((margin + w * c + 4, y), str(r), fill=grey, font=font, anchor="lm")
        else:
            draw.text((margin - 4, y), str(r), fill=grey, font=font, anchor="rm")
    every = 5 if c >= 12 else 10
    for s in range(1, w + 1):
        if s == 1 or s % every == 0:
            x = margin + (w - s) * c + c // 2
            draw.text((x, margin - 4), str(s), fill=grey, font=font, anchor="ms")
            draw.text((x, margin + h * ch + 4), str(s), fill=grey, font=font, anchor="mt")
