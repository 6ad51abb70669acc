"""The pattern PDF's schematic: the piece drawn to scale as a bought pattern draws it.

One page: the outline of the finished piece in its proportions (at the gauge a hand knitter is
told to expect), its width and height in cm and inches on dimension lines, the stitch and row
counts, which edge is the cast-on and which the bind-off, and from which side each picture is
seen (from above, looking down along the fabric from the bind-off edge; from below, from the
cast-on edge; head-on, the right side facing).
"""

from __future__ import annotations

from illuknit.outputs.pdf_document import MARGIN_MM, _Document

__all__: list[str] = []

#: Room around the outline for the dimension lines and the edge labels, in mm.
_ROOM_MM = 34.0
#: The tallest the outline is drawn, in mm (the page keeps room for the notes below it).
_MAX_H_MM = 150.0


def _schematic(doc: _Document) -> None:
    """The schematic page (see the module docstring)."""
    pdf, size = doc.pdf, doc.hand_size
    pdf.add_page()
    doc.heading("Schematic")
    doc.para(
        f"Finished size: {size.describe()} (width x height) after blocking, {doc.W} stitches x "
        f"{doc.H} rows, at {doc.hand_gauge.describe()}.",
        9.5,
    )
    avail_w = doc.usable - 2 * _ROOM_MM
    scale = min(avail_w / size.width_cm, _MAX_H_MM / size.height_cm)
    w, h = size.width_cm * scale, size.height_cm * scale
    x0 = MARGIN_MM + (doc.usable - w) / 2
    y0 = pdf.get_y() + 22
    pdf.set_fill_color(235, 235, 235)
    pdf.set_draw_color(0, 0, 0)
    pdf.set_line_width(0.6)
    pdf.rect(x0, y0, w, h, style="DF")
    if doc.border:  # the pictures inside the border, a lighter field
        bx, by = w * 2 * doc.border / doc.W, h * 2 * doc.border / doc.H
        pdf.set_fill_color(255, 255, 255)
        pdf.set_line_width(0.2)
        pdf.rect(x0 + bx, y0 + by, w - 2 * bx, h - 2 * by, style="DF")
    _dimensions(doc, (x0, y0, w, h))
    _edges(doc, (x0, y0, w, h))
    pdf.set_y(y0 + h + 22)
    doc.para(
        "Picture A is seen from above: hang the piece, stand close and look down along the "
        "fabric from the bind-off edge. Picture B is seen from below: look up along it from the "
        "cast-on edge. Head-on, with the right side facing you, the piece shows what the cover "
        "says. Block it to the size drawn here; the stitch and row counts stay as charted.",
        9.5,
    )
    doc.para(_edges_text(doc), 9.5)


def _edges_text(doc: _Document) -> str:
    """What the edges are: the garter border and what it adds, or that there is none."""
    hang = "A sleeve for a hanging rod can be sewn along the bind-off edge."
    b = doc.border
    if not b:
        return (
            "Edges: no selvedge stitches or border are added; every stitch on the chart is part "
            "of a picture. The sides of ridged illusion fabric curl little, but pin them "
            f"straight when blocking. {hang}"
        )
    return (
        f"Border (shaded band): {2 * b} garter stitches at each side (knit on both sides, in "
        f"the yarn of the stitch beside them, so they add no colour change) and {b} garter "
        f"ridge{'s' if b > 1 else ''} ({2 * b} rows) at the cast-on and at the bind-off edge, "
        f"against curling. It adds {4 * b} stitches and {4 * b} rows: the pictures are "
        f"{doc.W - 4 * b} stitches x {doc.H - 4 * b} rows inside it. The chart and the written "
        f"rows include it, and the sizes above are with it. {hang}"
    )


def _dimensions(doc: _Document, box: tuple[float, float, float, float]) -> None:
    """The width above the outline and the height to its right, on dimension lines."""
    pdf, size = doc.pdf, doc.hand_size
    x0, y0, w, h = box
    pdf.set_line_width(0.25)
    top, right = y0 - 8, x0 + w + 8
    pdf.line(x0, top, x0 + w, top)
    pdf.line(right, y0, right, y0 + h)
    for x in (x0, x0 + w):  # ticks at the ends
        pdf.line(x, top - 2, x, top + 2)
    for y in (y0, y0 + h):
        pdf.line(right - 2, y, right + 2, y)
    doc.font(9, "B")
    pdf.set_xy(x0, top - 6)
    pdf.cell(w, 4, f"{size.width_cm:.1f} cm ({size.width_in:.1f} in), {doc.W} sts", align="C")
    pdf.set_xy(right + 2, y0 + h / 2 - 6)
    pdf.multi_cell(
        _ROOM_MM - 4, 4, f"{size.height_cm:.1f} cm\n({size.height_in:.1f} in)\n{doc.H} rows"
    )


def _edges(doc: _Document, box: tuple[float, float, float, float]) -> None:
    """Which edge is the cast-on and the bind-off, and from where each picture is seen."""
    pdf = doc.pdf
    x0, y0, w, h = box
    inset = h * 2 * doc.border / doc.H  # the labels inside the border band
    doc.font(9)
    pdf.set_xy(x0, y0 + inset + 1.5)
    pdf.cell(w, 4, f"bind-off edge (top, row {doc.H})", align="C")
    pdf.set_xy(x0, y0 + h - inset - 5.5)
    pdf.cell(w, 4, "cast-on edge (bottom, row 1)", align="C")
    pdf.set_xy(x0, y0 + h / 2 - 4)
    pdf.multi_cell(w, 4, "right side facing:\nseen head-on", align="C")
    doc.font(9, "B")
    pdf.set_xy(x0, y0 - 20)
    pdf.cell(w, 4, "Picture A: seen from above, along the fabric", align="C")
    pdf.set_xy(x0, y0 + h + 12)
    pdf.cell(w, 4, "Picture B: seen from below, along the fabric", align="C")
    pdf.set_line_width(0.4)
    cx = x0 + 5  # beside the width label
    for tip, tail in ((y0 - 1, y0 - 15), (y0 + h + 1, y0 + h + 11)):  # eye -> fabric arrows
        pdf.line(cx, tail, cx, tip)
        d = 1.6 if tip > tail else -1.6
        pdf.line(cx, tip, cx - 1.4, tip - d)
        pdf.line(cx, tip, cx + 1.4, tip - d)
