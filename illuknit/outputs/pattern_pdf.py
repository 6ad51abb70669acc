"""A print-ready hand-knitting pattern: ``pattern.pdf`` (and its chart as ``chart.svg``).

What a knitter buying an illusion pattern expects, in this order:

1. **Cover**: the title, the head-on view and the picture seen from either end (drawn in the
   fabric's proportions, angled views foreshortened), the finished size in cm and inches.
2. **Materials and gauge**: each yarn with its length and weight (stitch counts x loop length at
   the gauge, floats, 20 % margin: :func:`illuknit.outputs.hand_pattern.yarn_estimate`), needles for the
   gauge, the gauge swatch; abbreviations; how to read the chart; the technique advice
   (:func:`illuknit.outputs.hand_pattern.hand_advice`); the key.
3. **Schematic**: the piece to scale, its width and height in cm and inches, the cast-on and
   bind-off edges, and from where each picture is seen (:mod:`illuknit.outputs.pdf_schematic`).
4. **Chart**, tiled over A4 or Letter pages at a printable cell size (:data:`CELL_MM`): each page
   repeats one stitch column and one row of its neighbours (shaded), stitch numbers along the top
   and bottom counted from the right edge, row numbers on both sides (RS rows at the right, WS
   rows at the left), bold lines every 10 stitches and rows, a section marker every
   :data:`SECTION_ROWS` rows, and a page map.
5. **Written rows**, each with its stitch count and its colourwork note.

Written with fpdf2: a maintained, pure-Python PDF writer (on top of Pillow, already a
dependency) that places text, lines, rectangles and PNGs at exact millimetre positions, which a
tiled chart needs; reportlab does the same but is a larger dependency with C parts, and
matplotlib's PDF backend lays out figures, not pages of text. Text is set in the core Helvetica
when it fits Latin-1, else in DejaVu Sans, bundled with its licence, which covers Latin, Greek,
Cyrillic and more; characters it lacks (Chinese yarn names, say) come from a system font when one
is found (:func:`pdf_fonts`), and are otherwise written as their code points, with a note in the
materials saying which and how to add a font.

The pages are drawn by :mod:`illuknit.outputs.pdf_materials` (cover, materials, gauge, key),
:mod:`illuknit.outputs.pdf_chart` (the chart, and ``chart.svg``) and this module (the written
rows), on the page furniture of :mod:`illuknit.outputs.pdf_document`; every public name of
those is importable from here.
"""

from __future__ import annotations

import os
from pathlib import Path

from illuknit.core.errors import OptionError
from illuknit.core.files import atomic_write_bytes, atomic_write_text
from illuknit.core.gauge import Gauge
from illuknit.core.pattern import LogicalPattern
from illuknit.outputs.hand_pattern import with_border, written_row
from illuknit.outputs.pdf_chart import SECTION_ROWS, ChartTile, _chart_pages, chart_svg, chart_tiles
from illuknit.outputs.pdf_document import (
    CELL_MM,
    FALLBACK_FONTS,
    FONT,
    FONTS_ENV,
    LABEL_MM,
    MARGIN_MM,
    PAGE_SIZES,
    PdfFonts,
    _Document,
    pdf_fonts,
)
from illuknit.outputs.pdf_materials import ABBREVIATIONS, _cover, _materials, needles_for_gauge
from illuknit.outputs.pdf_schematic import _schematic

__all__ = [
    "ABBREVIATIONS",
    "CELL_MM",
    "CHART_KINDS",
    "FALLBACK_FONTS",
    "FONT",
    "FONTS_ENV",
    "LABEL_MM",
    "MARGIN_MM",
    "PAGE_SIZES",
    "SECTION_ROWS",
    "ChartTile",
    "PdfFonts",
    "chart_svg",
    "chart_tiles",
    "needles_for_gauge",
    "pattern_pdf",
    "pdf_fonts",
    "write_pattern_pdf",
]

#: What one chart square is: ``"units"`` (one square a ridge: a unit of 2 stitches x 2 rows, the
#: default, as bought illusion charts draw it) or ``"stitches"`` (one square a stitch).
CHART_KINDS = ("units", "stitches")


def pattern_pdf(
    pattern: LogicalPattern,
    *,
    gauge: Gauge,
    title: str = "illuknit illusion pattern",
    page: str = "A4",
    angle: float | None = None,
    chart: str = "units",
    border: int = 0,
) -> bytes:
    """The pattern as a print-ready PDF (see the module docstring for its pages). ``chart`` is
    one of :data:`CHART_KINDS`: a square a unit (default) or a square a stitch. ``border`` > 0
    frames it in garter stitch that many ridge units wide
    (:func:`~illuknit.outputs.hand_pattern.with_border`: 4 stitches and 4 rows more a unit);
    the sizes, chart and written rows all include it."""
    if page not in PAGE_SIZES:
        raise ValueError(f"`page` must be one of {', '.join(PAGE_SIZES)}, got {page!r}")
    if chart not in CHART_KINDS:
        raise OptionError(f"`chart` must be one of {', '.join(CHART_KINDS)}, got {chart!r}")
    doc = _Document(with_border(pattern, border), gauge, title, page, chart)
    doc.border = border
    _cover(doc, angle)
    _materials(doc)
    _schematic(doc)
    _chart_pages(doc)
    _written_rows(doc)
    return bytes(doc.pdf.output())


def _written_rows(doc: _Document) -> None:
    """Every row written out, with its stitch count and colourwork note."""
    doc.pdf.add_page()
    doc.heading("Written rows")
    doc.para(f"CO {doc.W} sts with {doc.cast_on_yarn}.", 9)
    colourwork = {r.number: r for r in doc.advice.rows}
    doc.font(8.5)
    for row in doc.rows:
        note = colourwork[row.number].note()
        text = f"Row {row.number} ({row.side}): {written_row(row.worked(), doc.names)}"
        if note:
            text += f" [{note}]"
        doc.pdf.multi_cell(0, 3.9, doc.fonts.text(text), new_x="LMARGIN", new_y="NEXT")
    doc.para(f"BO all {doc.W} sts knitwise. Weave in the ends; wash and dry flat.", 9)


def write_pattern_pdf(
    pattern: LogicalPattern,
    outdir: str | os.PathLike[str],
    *,
    gauge: Gauge,
    title: str = "illuknit illusion pattern",
    page: str = "A4",
    chart: str = "units",
    border: int = 0,
) -> dict[str, Path]:
    """Write ``pattern.pdf`` and ``chart.svg``, their chart a square a unit or a stitch
    (:data:`CHART_KINDS`), both with the garter ``border`` (ridge units) when one is asked
    for, into ``outdir``; name -> path."""
    out = Path(outdir)
    pdf = pattern_pdf(pattern, gauge=gauge, title=title, page=page, chart=chart, border=border)
    svg = chart_svg(with_border(pattern, border), unit_aspect=gauge.unit_aspect, chart=chart)
    return {
        "pattern_pdf": atomic_write_bytes(out / "pattern.pdf", pdf),
        "chart_svg": atomic_write_text(out / "chart.svg", svg),
    }
