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
matplotlib's PDF backend lays out figures, not pages of text. Text is set in the core Helvetica
when it fits Latin-1, else in DejaVu Sans, bundled with its licence, which covers Latin, Greek,
Cyrillic and more; characters it lacks (Chinese yarn names, say) come from a system font when one
is found (:func:`pdf_fonts`), and are otherwise written as their code points, with a note in the
materials saying which and how to add a font.
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

from illuknit.core.colors import luminance
from illuknit.core.errors import OptionError
from illuknit.core.files import atomic_write_bytes, atomic_write_text
from illuknit.core.gauge import (
    SWATCH_MARGIN_CM,
    SWATCH_MEASURE_CM,
    Gauge,
    finished_size,
    hand_illusion_gauge,
    swatch_size,
)
from illuknit.core.pattern import LogicalPattern
from illuknit.outputs.chart import hand_rows, ink_on
from illuknit.outputs.hand_pattern import hand_advice, hand_verdict, written_row, yarn_estimate

__all__ = [
    "CELL_MM",
    "CHART_KINDS",
    "FONT",
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

#: Page sizes in mm (width, height), portrait.
PAGE_SIZES = {"A4": (210.0, 297.0), "Letter": (215.9, 279.4)}
#: Chart cell width in mm: a printed chart cell of about 4.5 mm reads at arm's length (its height
#: is the fabric's: 4.5 mm times the gauge's unit_aspect).
CELL_MM = 4.5
#: What one chart square is: ``"units"`` (one square a ridge: a unit of 2 stitches x 2 rows, the
#: default, as bought illusion charts draw it) or ``"stitches"`` (one square a stitch).
CHART_KINDS = ("units", "stitches")
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
    chart: str = "units",
) -> bytes:
    """The pattern as a print-ready PDF (see the module docstring for its pages). ``chart`` is
    one of :data:`CHART_KINDS`: a square a unit (default) or a square a stitch."""
    if page not in PAGE_SIZES:
        raise ValueError(f"`page` must be one of {', '.join(PAGE_SIZES)}, got {page!r}")
    if chart not in CHART_KINDS:
        raise OptionError(f"`chart` must be one of {', '.join(CHART_KINDS)}, got {chart!r}")
    doc = _Document(pattern, gauge, title, page, chart)
    _cover(doc, angle)
    _materials(doc)
    _chart_pages(doc)
    _written_rows(doc)
    return bytes(doc.pdf.output())


class _Document:
    """The PDF being written, its fonts and the facts every page draws on."""

    def __init__(
        self, pattern: LogicalPattern, gauge: Gauge, title: str, page: str, chart: str
    ) -> None:
        from fpdf import FPDF

        self.pattern, self.gauge, self.title, self.page = pattern, gauge, title, page
        self.chart = chart
        #: stitches (and rows) per chart square
        self.per = 2 if chart == "units" else 1
        n, m = pattern.shape
        self.W, self.H = 2 * m, 2 * n
        #: a chart row's height: a cell in the fabric's proportions (a stitch unit_aspect as
        #: tall as wide), so a round motif is round on paper
        self.row_mm = CELL_MM * gauge.unit_aspect
        self.size = finished_size(pattern.shape, gauge)
        #: the gauge a hand knitter is told to expect: the estimate when ``gauge`` is one
        self.hand_gauge = (
            hand_illusion_gauge(round(gauge.stitches_per_10cm, 1)) if gauge.estimate else gauge
        )
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


def _cover(doc: _Document, angle: float | None) -> None:
    """Title, finished size, the head-on and both angled previews in the fabric's proportions."""
    from illuknit.design.render import RenderParams, render_views
    from illuknit.outputs.captions import headon_likeness
    from illuknit.outputs.previews import chart_rgb, rows_per_unit, unit_scale, upscale

    pdf, pattern, gauge = doc.pdf, doc.pattern, doc.gauge
    n, m = pattern.shape
    pdf.add_page()
    doc.heading(doc.title, 20)
    doc.para(
        f"Finished size: {doc.size.describe()}  -  {doc.W} stitches x {doc.H} rows ({m} x {n} "
        f"units of 2 stitches x 2 rows), at {gauge.describe()}."
    )
    doc.para(hand_verdict(pattern).text, 9.5)
    s = max(2, unit_scale(pattern.shape, target=400))
    theta = angle if angle is not None else RenderParams().theta
    headon = chart_rgb(pattern, scale=s, unit_aspect=gauge.unit_aspect)
    renders = render_views(pattern, angle=angle)
    sy = rows_per_unit(s, gauge.unit_aspect, angle=theta)
    likeness = headon_likeness(pattern)
    views = [
        (likeness.caption(), headon),
        (f"Seen from above (top edge) at {theta:g} deg", upscale(renders["A"], s, sy)),
        (f"Seen from below (cast-on edge) at {theta:g} deg", upscale(renders["B"], s, sy)),
    ]
    y = pdf.get_y() + 2
    big_w = doc.usable * 0.62
    img_h = big_w * headon.shape[0] / headon.shape[1]
    max_h = doc.ph - y - MARGIN_MM - 10
    if img_h > max_h:
        big_w, img_h = big_w * max_h / img_h, max_h
    doc.font(9)
    pdf.set_xy(MARGIN_MM, y)
    pdf.cell(big_w, 5, views[0][0])
    pdf.image(_png(views[0][1]), x=MARGIN_MM, y=y + 5, w=big_w, h=img_h)
    small_w = doc.usable - big_w - 6
    yy = y
    for label, img in views[1:]:
        h = small_w * img.shape[0] / img.shape[1]
        pdf.set_xy(MARGIN_MM + big_w + 6, yy)
        pdf.multi_cell(small_w, 4, label)
        pdf.image(_png(img), x=MARGIN_MM + big_w + 6, y=yy + 9, w=small_w, h=h)
        yy += h + 16
    pdf.set_y(max(y + 5 + img_h, yy) + 4)
    doc.para(
        _HEADON_WORDS[likeness.shows] + " Look along it from the top or the bottom edge and the "
        "raised purl ridges hide the rows behind them, and each side's picture appears. The "
        "previews are drawn in the fabric's proportions; angled views are foreshortened as they "
        "are seen.",
        9,
    )


#: What the cover says head-on shows, measured (:func:`~illuknit.outputs.captions.headon_likeness`).
_HEADON_WORDS = {
    "stripes": "Head-on the piece shows stripes.",
    "same": "Head-on the piece shows the same picture as from either edge.",
    "both": "Head-on the piece shows both pictures, mixed (the caption gives how alike each is).",
    "A": "Head-on the piece shows mostly the picture seen from the top edge.",
    "B": "Head-on the piece shows mostly the picture seen from the cast-on edge.",
    "own": "Head-on the piece shows a picture of its own.",
}


def _materials(doc: _Document) -> None:
    """Materials, gauge, abbreviations, how to read the chart, the advice and the key."""
    pdf, gauge = doc.pdf, doc.gauge
    yclass, needles, metres_per_100g = needles_for_gauge(gauge.stitches_per_10cm)
    pdf.add_page()
    doc.heading("Materials")
    for e in yarn_estimate(doc.pattern, gauge, metres_per_100g=metres_per_100g):
        doc.para(f"- Yarn {e.describe()}")
    doc.para(
        f"Lengths are estimates: each stitch takes about 3.8 stitch widths of yarn at this gauge, "
        f"plus the floats of stranded rows and a 20 % margin for the cast-on, bind-off and ends; "
        f"weights assume {yclass} yarn of about {metres_per_100g:.0f} m per 100 g. Check the "
        "meterage on your ball band."
    )
    doc.para(
        f"- Needles: {needles} for {yclass} yarn, or the size that gives the gauge below. "
        "A tapestry needle to weave in ends."
    )
    missing = doc.fonts.missing(" ".join(doc.names))
    if missing:
        doc.para(
            "Some characters of the yarn names have no glyph in the fonts found, so they are "
            f"written as their code points ({', '.join(missing)}); install a font that covers "
            "them (e.g. Debian's fonts-noto-cjk or fonts-droid-fallback) or name one in "
            f"{FONTS_ENV}.",
            8,
        )
    _gauge_section(doc)
    doc.heading("Abbreviations")
    for abbr, meaning in ABBREVIATIONS:
        doc.font(10, "B")
        pdf.cell(38, 5, abbr)
        doc.font(10)
        pdf.cell(0, 5, meaning, new_x="LMARGIN", new_y="NEXT")
    pdf.ln(2)
    doc.heading("How to read the chart")
    doc.para(_how_to_read(doc))
    doc.heading("Working it")
    for line in doc.advice.lines:
        doc.para(line)
    doc.para(
        f"Cast on {doc.W} stitches with {doc.cast_on_yarn} and follow the chart (or the written "
        f"rows) from row 1 to row {doc.H}; bind off all stitches knitwise."
    )
    _finishing(doc)
    doc.heading("Key")
    _key(doc)


#: Skill level by technique (Craft Yarn Council's skill levels: Easy, Intermediate, Experienced).
_SKILL = {
    "stripes": "Easy: knit, purl and a change of yarn every 2 rows; the care is in counting.",
    "intarsia": "Experienced: intarsia with a bobbin a colour block, on top of the ridges.",
    "stranded": "Experienced: stranded colour work with floats caught, on top of the ridges.",
    "not-sensible": "Machine: no hand technique fits the colour rows (see Working it).",
}


def _finishing(doc: _Document) -> None:
    """Skill level, blocking and finishing, and how to hang and view the piece."""
    doc.heading("Skill level")
    doc.para(_SKILL[doc.advice.technique])
    doc.heading("Finishing")
    doc.para(
        "Weave in the ends along the same-coloured stripes on the wrong side. Wet-block: soak "
        f"the piece, press the water out in a towel and pin it flat to about "
        f"{doc.hand_size.describe()} (or the size your swatch gives); let it dry. Do not press or steam the right side: the purl "
        "ridges must stand up for the pictures to show."
    )
    doc.para(
        "To hang and view it: hang it with the cast-on edge at the bottom (a rod through a "
        "sleeve sewn at the top), in light from one side. Walk past it looking along the "
        "fabric from above, then from below, to see each picture; head-on it shows stripes "
        "or the mix the cover describes."
    )


def _gauge_section(doc: _Document) -> None:
    """The gauge the design is sized for, the hand estimate when that gauge was not measured,
    the swatch (big enough to measure 10 cm in its middle) and how to feed a swatch back."""
    gauge = doc.gauge
    doc.heading("Gauge")
    s, r = gauge.stitches_per_10cm, gauge.rows_per_10cm
    if not gauge.estimate:
        doc.para(
            f"{s:.1f} stitches and {r:.1f} rows = 10 cm (4 in) in the pattern stitch "
            f"({gauge.describe()}; {gauge.source})."
        )
        doc.para(f"Finished size at this gauge: {doc.size.describe()}.")
        hand = gauge
    else:
        hand, size = doc.hand_gauge, doc.hand_size
        doc.para(
            f"The design is drawn for {s:.1f} stitches and {r:.1f} rows = 10 cm (4 in): "
            f"{doc.size.describe()}. That row gauge was not measured. Hand-knitted illusion "
            f"fabric has more rows to the stitch: about {hand.rows_per_10cm:.1f} rows = 10 cm "
            "at this stitch gauge (an estimate from published illusion patterns, 1.75-1.92 "
            f"rows a stitch), so by hand expect about {size.describe()}, the pictures "
            f"{size.height_cm / doc.size.height_cm:.0%} as tall as drawn, until your swatch "
            "says otherwise."
        )
    sts, rows = swatch_size(hand)
    span = SWATCH_MEASURE_CM + 2 * SWATCH_MARGIN_CM
    doc.para(
        f"Gauge swatch (about {span:g} x {span:g} cm): cast on {sts} stitches and knit 6 rows. "
        "Then repeat 2 rows stocking stitch (knit on the RS, purl on the WS) and 2 rows garter "
        "(knit both), knitting the first and last 3 stitches of every row (a garter border "
        f"against curling), until the swatch has {rows - 6} rows; knit 6 rows and bind off. "
        f"Wash it and dry it flat. Count the stitches across and the rows up "
        f"{SWATCH_MEASURE_CM:g} cm in the middle, away from the border. More stitches than "
        f"{hand.stitches_per_10cm:.1f}: use larger needles; fewer: smaller. Then give your "
        "counts to illuknit, which sizes the design to them (more rows keep the pictures in "
        "proportion): --fabric-gauge STSxROWS/10cm, e.g. --fabric-gauge "
        f"{hand.stitches_per_10cm:.0f}x{hand.rows_per_10cm:.0f}/10cm."
    )


def _how_to_read(doc: _Document) -> str:
    """The paragraph that explains the chart's squares, numbers and pages."""
    pages = (
        "Bold lines mark every 10 stitches and 10 rows, and a section marker (S1, S2, ...) "
        f"starts every {SECTION_ROWS} rows. The chart is split over pages as the page map "
        "shows; neighbouring pages repeat one column and one row (hatched) so you can line "
        "them up. Every page has its number and the design's name at the foot."
    )
    if doc.per == 2:
        return (
            "Each square is one ridge unit: 2 stitches wide and 2 rows tall, drawn in the "
            f"fabric's proportions ({CELL_MM:g} x {doc.row_mm:.1f} mm). Row 1 is at the bottom "
            "(the cast-on edge). A row of squares is two rows of knitting: the right-side row "
            "(RS, odd, its number at the right) is read from right to left and knitted, 2 "
            "stitches a square in the square's colour; the wrong-side row (WS, even, its "
            "number at the left) is read from left to right: purl the 2 stitches of a plain "
            "square, knit the 2 stitches of a dotted square (they show as a purl ridge on the "
            "right side). A square split in two colours has its WS row in the top half's "
            "yarn. Stitches are numbered from the right edge along the top and bottom. " + pages
        )
    return (
        "Each cell is one stitch, in the colour of its yarn, as wide and tall as a stitch of "
        f"the fabric ({CELL_MM:g} x {doc.row_mm:.1f} mm), so motifs keep their shape. Row 1 is "
        "at the bottom (the cast-on edge). Right-side (RS, odd) rows are read from right to "
        "left and have their number at the right; wrong-side (WS, even) rows are read from "
        "left to right and have their number at the left. A dot is a stitch that shows as a "
        "purl on the right side: purl it on a RS row, knit it on a WS row. Stitches are "
        "numbered from the right edge along the top and bottom. " + pages
    )


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


def _key(doc: _Document) -> None:
    pdf, pattern = doc.pdf, doc.pattern
    sw = 5.0
    if pdf.get_y() + (len(pattern.yarns) + 1) * (sw + 2) > pdf.page_break_trigger:
        pdf.add_page()  # the key on one page
    for y in pattern.yarns:
        x, yy = pdf.get_x(), pdf.get_y()
        pdf.set_fill_color(*y.rgb)
        pdf.rect(x, yy, sw, sw, style="DF")
        pdf.set_xy(x + sw + 3, yy)
        doc.font(10)
        what = "2 stitches x 2 rows" if doc.per == 2 else "a stitch"
        pdf.cell(0, sw, doc.fonts.text(f"{y.name} ({y.hex}): {what} in this yarn"))
        pdf.set_xy(x, yy + sw + 2)
    x, yy = pdf.get_x(), pdf.get_y()
    light = pattern.palette[int(np.argmax(luminance(pattern.palette)))]
    pdf.set_fill_color(*(int(v) for v in light))
    pdf.rect(x, yy, sw, sw, style="DF")
    pdf.set_fill_color(20, 20, 20)
    pdf.ellipse(x + sw / 2 - 0.9, yy + sw / 2 - 0.9, 1.8, 1.8, style="F")
    pdf.set_xy(x + sw + 3, yy)
    pdf.cell(
        0,
        sw,
        "dot: knit both stitches on the WS row (a purl ridge on the right side)"
        if doc.per == 2
        else "dot: purl on a RS row, knit on a WS row (a purl ridge on the right side)",
    )
    pdf.set_xy(x, yy + sw + 2)


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
    pattern: LogicalPattern, *, cell: float = 10.0, unit_aspect: float | None = None
) -> str:
    """The whole chart as SVG: a cell per stitch (runs of one yarn merged), purl dots, stitch
    numbers from the right along the top and bottom, row numbers (RS right, WS left), bold lines
    every 10 stitches and rows. Cells are ``cell`` wide and ``unit_aspect`` as tall (the fabric's
    proportions; default the default machine's gauge)."""
    if unit_aspect is None:
        from illuknit.core.machine import DEFAULT_MACHINE

        unit_aspect = DEFAULT_MACHINE.fabric_gauge.unit_aspect
    yarn, _, purl = _grids(pattern)
    H, W = yarn.shape
    pad, rh = 3 * cell, cell * unit_aspect
    width, height = W * cell + 2 * pad, H * rh + 2 * pad
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
        return pad + (H - r) * rh

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
                f'height="{rh:g}" fill="{fill}"/>'
            )
            s = e + 1
        for dot in (np.flatnonzero(purl[r - 1]) + 1).tolist():
            col = "#ebebeb" if dark[int(row[dot - 1])] else "#141414"
            out.append(
                f'<circle cx="{x_of(dot) + cell / 2:g}" cy="{y_of(r) + rh / 2:g}" '
                f'r="{min(cell, rh) * 0.18:g}" fill="{col}"/>'
            )
    for s in range(0, W + 1):
        x = pad + (W - s) * cell
        wide = s % 10 == 0
        out.append(
            f'<line x1="{x:g}" y1="{pad:g}" x2="{x:g}" y2="{pad + H * rh:g}" '
            f'stroke="{"#000" if wide else "#888"}" stroke-width="{1.5 if wide else 0.3}"/>'
        )
    for r in range(0, H + 1):
        y = pad + (H - r) * rh
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
                f'<text x="{x:g}" y="{pad + H * rh + cell:g}" text-anchor="middle">{s}</text>'
            )
    for r in range(1, H + 1):
        y = y_of(r) + rh * 0.8
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
    chart: str = "units",
) -> dict[str, Path]:
    """Write ``pattern.pdf`` (its chart a square a unit or a stitch, :data:`CHART_KINDS`) and
    ``chart.svg`` (a square a stitch) into ``outdir``; name -> path."""
    out = Path(outdir)
    pdf = pattern_pdf(pattern, gauge=gauge, title=title, page=page, chart=chart)
    return {
        "pattern_pdf": atomic_write_bytes(out / "pattern.pdf", pdf),
        "chart_svg": atomic_write_text(
            out / "chart.svg", chart_svg(pattern, unit_aspect=gauge.unit_aspect)
        ),
    }
