"""The pattern PDF's page furniture: page sizes and margins, the fonts its text is set in
(:func:`pdf_fonts`), the footer every page carries, and the document every section draws on.

The sections are :mod:`illuknit.outputs.pdf_materials` (cover, materials, gauge, key) and
:mod:`illuknit.outputs.pdf_chart` (the chart pages); :mod:`illuknit.outputs.pattern_pdf`
assembles them.
"""

from __future__ import annotations

import io
import os
from dataclasses import dataclass
from datetime import UTC, datetime
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from illuknit.core.gauge import Gauge, finished_size, hand_gauge
from illuknit.core.pattern import LogicalPattern
from illuknit.outputs.chart import hand_rows
from illuknit.outputs.hand_pattern import hand_advice

__all__ = ["CELL_MM", "FONT", "PAGE_SIZES", "PdfFonts", "pdf_fonts"]

#: Page sizes in mm (width, height), portrait.
PAGE_SIZES = {"A4": (210.0, 297.0), "Letter": (215.9, 279.4)}
#: Chart cell width in mm: a printed chart cell of about 4.5 mm reads at arm's length (its height
#: is the fabric's: 4.5 mm times the gauge's unit_aspect).
CELL_MM = 4.5
MARGIN_MM = 12.0
#: room for the row numbers / stitch numbers around the chart grid
LABEL_MM = 9.0


#: Family name the PDF's text is set in: DejaVu Sans, bundled (``illuknit/data``, its licence
#: beside it), which covers Latin, Greek, Cyrillic and more.
FONT = "DejaVu"
_DATA = Path(__file__).resolve().parents[1] / "data"
_FONT_FILES = {"": _DATA / "DejaVuSans.ttf", "B": _DATA / "DejaVuSans-Bold.ttf"}
#: Environment variable: more font files (TrueType/OpenType, path-separated) for characters
#: DejaVu lacks, tried before the system fonts of :data:`FALLBACK_FONTS`.
FONTS_ENV = "ILLUKNIT_PDF_FONTS"
#: System fonts tried, in order, for characters DejaVu lacks (Chinese, Japanese, Korean ...):
#: Debian's fonts-droid-fallback, fonts-noto-cjk, fonts-wqy-microhei / -zenhei.
FALLBACK_FONTS = (
    "/usr/share/fonts/truetype/droid/DroidSansFallbackFull.ttf",
    "/usr/share/fonts/opentype/noto/NotoSansCJK-Regular.ttc",
    "/usr/share/fonts/truetype/wqy/wqy-microhei.ttc",
    "/usr/share/fonts/truetype/wqy/wqy-zenhei.ttc",
)


@dataclass(frozen=True)
class PdfFonts:
    """The fonts a pattern is written in.

    ``family`` is Helvetica (the PDF's core font, nothing embedded) when every character fits
    Latin-1, else :data:`FONT` (DejaVu Sans, embedded) with ``fallbacks`` for what it lacks.
    :meth:`text` keeps every character some font has, and writes any other as its code point
    (``<U+6DF1>``) rather than a blank or a wrong glyph; :meth:`missing` lists those.
    """

    family: str
    fallbacks: tuple[Path, ...]
    covered: frozenset[int]

    def install(self, pdf: Any) -> None:
        if self.family != FONT:
            return
        for style, path in _FONT_FILES.items():
            pdf.add_font(FONT, style, str(path))
        names = []
        for k, path in enumerate(self.fallbacks):
            pdf.add_font(f"fallback{k}", "", str(path))
            names.append(f"fallback{k}")
        if names:
            pdf.set_fallback_fonts(names, exact_match=False)

    def text(self, text: str) -> str:
        if self.family != FONT:
            text = text.replace("\u2013", "-").replace("\u2014", "-")
        return "".join(ch if ord(ch) in self.covered else f"<U+{ord(ch):04X}>" for ch in text)

    def missing(self, text: str) -> list[str]:
        return sorted({f"U+{ord(ch):04X}" for ch in text if ord(ch) not in self.covered})


@lru_cache(maxsize=4)
def _cmap(path: str) -> frozenset[int]:
    from fontTools.ttLib import TTFont

    with TTFont(path, fontNumber=0, lazy=True) as font:
        return frozenset(font.getBestCmap() or {})


def pdf_fonts(text: str = "") -> PdfFonts:
    """The fonts for a pattern whose free text (title, yarn names; all else is ASCII) is
    ``text``: the core Helvetica when it fits Latin-1 (the quickest, smallest file), else DejaVu
    Sans and, for characters it lacks, the fallback fonts found that have some
    (:data:`FONTS_ENV`, then :data:`FALLBACK_FONTS`)."""
    if all(ord(ch) < 256 for ch in text):
        return PdfFonts("Helvetica", (), frozenset(range(256)))
    # characters every style can draw from DejaVu, plus any a fallback has
    covered = _cmap(str(_FONT_FILES[""])) & _cmap(str(_FONT_FILES["B"])) | {0x0A, 0x0D}
    lacking = {ord(ch) for ch in text} - covered
    extra = [p for p in os.environ.get(FONTS_ENV, "").split(os.pathsep) if p.strip()]
    used: list[Path] = []
    for path in (Path(p) for p in (*extra, *FALLBACK_FONTS)):
        if not lacking or not path.is_file():
            continue
        has = _cmap(str(path))
        if lacking & has:
            used.append(path)
            covered |= has
            lacking -= has
    return PdfFonts(FONT, tuple(used), frozenset(covered))


def _png(rgb: NDArray[np.uint8]) -> io.BytesIO:
    from illuknit.outputs.previews import png_bytes

    return io.BytesIO(png_bytes(rgb))


class _Document:
    """The PDF being written, its fonts and the facts every page draws on."""

    def __init__(
        self, pattern: LogicalPattern, gauge: Gauge, title: str, page: str, chart: str
    ) -> None:
        from fpdf import FPDF

        self.pattern, self.gauge, self.title, self.page = pattern, gauge, title, page
        self.chart = chart
        #: the garter border's width in ridge units (0: none), already in ``pattern``
        self.border = 0
        #: stitches (and rows) per chart square
        self.per = 2 if chart == "units" else 1
        n, m = pattern.shape
        self.W, self.H = 2 * m, 2 * n
        #: a chart row's height: a cell in the fabric's proportions (a stitch unit_aspect as
        #: tall as wide), so a round motif is round on paper
        self.row_mm = CELL_MM * gauge.unit_aspect
        self.size = finished_size(pattern.shape, gauge)
        #: the gauge a hand knitter is told to expect: the estimate when ``gauge`` is one
        self.hand_gauge = hand_gauge(gauge)
        #: ``gauge`` is the hand estimate itself: the grid was sized for hand knitting
        self.drawn_for_hands = gauge.estimate and self.hand_gauge == gauge
        self.hand_size = finished_size(pattern.shape, self.hand_gauge)
        self.names = [y.name for y in pattern.yarns]
        self.rows = hand_rows(pattern)
        self.advice = hand_advice(pattern)
        self.pw, self.ph = PAGE_SIZES[page]
        self.usable = self.pw - 2 * MARGIN_MM
        pdf = FPDF(orientation="P", unit="mm", format=PAGE_SIZES[page])
        pdf.set_auto_page_break(auto=True, margin=MARGIN_MM)
        pdf.set_margins(MARGIN_MM, MARGIN_MM, MARGIN_MM)
        self.fonts = pdf_fonts(title + "".join(self.names))
        self.fonts.install(pdf)
        pdf.set_title(self.fonts.text(title))
        pdf.set_creator("illuknit")
        # no time stamp: the same pattern gives the same file (a folder holds one whole design)
        pdf.set_creation_date(datetime(2000, 1, 1, tzinfo=UTC))
        pdf.footer = self._footer  # type: ignore[method-assign]  # fpdf2 calls it per page
        self.pdf = pdf

    def _footer(self) -> None:
        """Every page: the design's name and "page N of M" (a loose page finds its place)."""
        pdf = self.pdf
        pdf.set_y(-9)
        pdf.set_text_color(60, 60, 60)
        self.font(8)
        pdf.cell(0, 4, self.fonts.text(self.title), align="L")
        pdf.set_x(MARGIN_MM)
        pdf.cell(0, 4, f"page {pdf.page_no()} of {{nb}}", align="R")
        pdf.set_text_color(0, 0, 0)

    def span(self, first: int, last: int) -> tuple[int, int]:
        """Chart squares ``first..last`` (columns or rows) as stitches or rows, 1-based."""
        return self.per * (first - 1) + 1, self.per * last

    def font(self, size_pt: float, style: str = "") -> None:
        self.pdf.set_font(self.fonts.family, style, size_pt)

    def heading(self, text: str, size_pt: float = 14) -> None:
        self.font(size_pt, "B")
        self.pdf.multi_cell(0, size_pt * 0.5, self.fonts.text(text), new_x="LMARGIN", new_y="NEXT")
        self.pdf.ln(1.5)

    def para(self, text: str, size_pt: float = 10) -> None:
        self.font(size_pt)
        self.pdf.multi_cell(0, size_pt * 0.45, self.fonts.text(text), new_x="LMARGIN", new_y="NEXT")
        self.pdf.ln(1)

    @property
    def cast_on_yarn(self) -> str:
        return self.names[int(self.rows[0].yarn[-1])]
