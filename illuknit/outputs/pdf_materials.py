"""The pattern PDF's opening pages: the cover with the views and the verdict, then materials
and gauge (yarn lengths, needles, the swatch), abbreviations, how to read the chart, the
technique advice, finishing and the key.
"""

from __future__ import annotations

import itertools
from typing import Any

import numpy as np

from illuknit.core.colors import luminance
from illuknit.core.gauge import SWATCH_MARGIN_CM, SWATCH_MEASURE_CM, swatch_size
from illuknit.outputs.hand_pattern import hand_verdict, yarn_estimate
from illuknit.outputs.pdf_chart import SECTION_ROWS
from illuknit.outputs.pdf_document import CELL_MM, FONTS_ENV, MARGIN_MM, _Document, _png

__all__ = ["ABBREVIATIONS", "needles_for_gauge"]

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


def _cover(doc: _Document, angle: float | None) -> None:
    """Title, finished size, the head-on and both angled previews in the fabric's proportions."""
    from illuknit.design.render import RenderParams, render_views
    from illuknit.outputs.captions import headon_likeness
    from illuknit.outputs.previews import chart_rgb, rows_per_unit, unit_scale, upscale

    pdf, pattern, gauge = doc.pdf, doc.pattern, doc.gauge
    pdf.add_page()
    doc.heading(doc.title, 20)
    doc.para(_cover_size(doc))
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
    "stripes": "Easy: knit, purl and a change of yarn every {rows}; the care is in counting.",
    "intarsia": "Experienced: intarsia with a bobbin a colour block, on top of the ridges.",
    "stranded": "Experienced: stranded colour work with floats caught, on top of the ridges.",
    "not-sensible": "Machine: no hand technique fits the colour rows (see Working it).",
}


def _stripe_rows(pattern: Any) -> str:
    """How many hand rows a stripe of one yarn runs between changes ("2 rows", "2 to 4 rows"),
    for a design knitted one yarn a row: the runs of hand rows in one yarn, leaving out the
    first and the last run (cut by the edges) when there are more than two."""
    n = pattern.shape[0]
    yarns = [
        int((pattern.yarn if k % 2 == 0 else pattern.upper_yarn)[n - 1 - k // 2][0])
        for k in range(2 * n)
    ]
    runs = [len(list(g)) for _, g in itertools.groupby(yarns)]
    inner = runs[1:-1] if len(runs) > 2 else runs
    lo, hi = min(inner), max(inner)
    return f"{lo} rows" if lo == hi else f"{lo} to {hi} rows"


def _finishing(doc: _Document) -> None:
    """Skill level, blocking and finishing, and how to hang and view the piece."""
    doc.heading("Skill level")
    doc.para(_SKILL[doc.advice.technique].format(rows=_stripe_rows(doc.pattern)))
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


def _cover_size(doc: _Document) -> str:
    """The cover's finished size: the one the schematic draws (by hand, at the estimated row gauge
    when the design's gauge was not measured), with the design's gauge beside it."""
    n, m = doc.pattern.shape
    counts = f"{doc.W} stitches x {doc.H} rows ({m} x {n} units of 2 stitches x 2 rows)"
    if not doc.gauge.estimate:
        return f"Finished size: {doc.size.describe()}  -  {counts}, at {doc.gauge.describe()}."
    if doc.drawn_for_hands:
        return (
            f"Finished size by hand: about {doc.hand_size.describe()}  -  {counts}, at "
            f"{doc.hand_gauge.describe()} (an estimate until your swatch says otherwise)."
        )
    return (
        f"Finished size by hand: about {doc.hand_size.describe()}  -  {counts}, at "
        f"{doc.hand_gauge.describe()} (an estimate until your swatch says otherwise; the design "
        f"is drawn for {doc.size.describe()} at {doc.gauge.describe()})."
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
    elif doc.drawn_for_hands:
        hand = gauge
        doc.para(
            f"The design is drawn for hand-knitted illusion fabric: about {s:.1f} stitches and "
            f"{r:.1f} rows = 10 cm (4 in), an estimate from published illusion patterns "
            "(1.75-1.92 rows a stitch), not measured. Expect about "
            f"{doc.size.describe()}, until your swatch says otherwise."
        )
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
