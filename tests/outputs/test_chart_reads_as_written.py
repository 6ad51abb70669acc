"""The hand chart says what the written rows say, stitch by stitch.

Each chart a knitter may follow -- ``chart.png`` (:func:`~illuknit.outputs.chart.chart_png_rgb`),
``chart.svg`` and the chart pages of ``pattern.pdf`` (a square a stitch or a square a unit) -- is
read back as a picture and compared with the written instructions read back as text: row 1 at
the bottom, stitch 1 at the right edge (RS rows are worked right to left, WS rows left to
right), every square in the colour of the yarn its written row names for that stitch, and a dot
exactly where the stitch shows as a purl on the right side. The patterns are asymmetric both
ways (a flip or a mirror of the chart would show) and have three yarns and split bumps (a WS row
in another yarn than its RS row).
"""

from __future__ import annotations

import io
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from PIL import Image

from illuknit.core.errors import IlluknitError
from illuknit.core.gauge import parse_gauge
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.outputs.chart import chart_png_rgb, written_instructions
from illuknit.outputs.hand_pattern import with_border
from illuknit.outputs.pattern_pdf import chart_svg, pattern_pdf

YARNS = parse_yarns("Red=#d7191c,Teal=#2b83ba,Gold=#fdae61")
#: Neither rows nor columns are symmetric: a chart drawn upside down or mirrored reads wrong.
ASYMMETRIC = LogicalPattern(
    np.array([[0, 1, 2, 2], [1, 1, 0, 2], [2, 0, 0, 0]], np.int16),
    np.array([[1, 0, 0, 0], [0, 1, 1, 0], [0, 0, 0, 1]], bool),
    YARNS,
)
#: Split bumps: the WS row of a raised unit in another yarn than its RS row.
SPLIT = LogicalPattern(
    np.array([[0, 1, 0], [1, 1, 2]], np.int16),
    np.array([[1, 0, 0], [0, 1, 1]], bool),
    YARNS,
    upper=np.array([[1, 1, 0], [1, 2, 0]], np.int16),
)
PATTERNS = {"asymmetric": ASYMMETRIC, "split": SPLIT}

#: (row, stitch) -> (yarn index, shows as a purl on the RS); row 1 is the cast-on row, stitch 1
#: the right edge of the chart.
Stitches = dict[tuple[int, int], tuple[int, bool]]


def _expand(text: str, yarn: str | None) -> list[tuple[str, str]]:
    """'k2, p1' (all in ``yarn``) or 'k2 Red, p1 Teal' as (stitch, yarn name) in working order."""
    out: list[tuple[str, str]] = []
    for token in text.split(", "):
        op_count, _, name = token.partition(" ")
        out += [(op_count[0], name or yarn or "")] * int(op_count[1:])
    return out


def _worked(body: str) -> list[tuple[str, str]]:
    """One written row ('with Red, *k2, p4; rep from * to last 2 sts, k2 (8 sts).') expanded."""
    body = re.sub(r" \[[^]]*\]$", "", body).rstrip(".")
    match = re.fullmatch(r"(.*) \((\d+) sts\)", body)
    assert match is not None, body
    body, total = match[1], int(match[2])
    yarn = None
    if body.startswith("with "):
        yarn, _, body = body[5:].partition(", ")
        if body in ("knit across", "purl across"):
            return [(body[0], yarn)] * total
    rep = re.fullmatch(r"(?:(.*?), )?\*(.*?); rep from \*(?: to end| to last \d+ sts?, (.*))", body)
    if rep is None:
        out = _expand(body, yarn)
    else:
        head = _expand(rep[1], yarn) if rep[1] else []
        unit, tail = _expand(rep[2], yarn), _expand(rep[3], yarn) if rep[3] else []
        times, left = divmod(total - len(head) - len(tail), len(unit))
        assert left == 0 and times >= 2, body
        out = head + unit * times + tail
    assert len(out) == total, body
    return out


def written_stitches(pattern: LogicalPattern, text: str | None = None) -> Stitches:
    """Every stitch as the written instructions (``text``, default
    :func:`~illuknit.outputs.chart.written_instructions`) give it, read back from their text."""
    names = [y.name for y in pattern.yarns]
    found: Stitches = {}
    for line in (text or written_instructions(pattern)).splitlines():
        row = re.match(r"Row (\d+) \((RS|WS)\): (.*)", line)
        if row is None:
            continue
        number, side = int(row[1]), row[2]
        assert side == ("RS" if number % 2 else "WS"), line
        worked = _worked(row[3])
        width = len(worked)
        for k, (op, name) in enumerate(worked):
            # RS rows start at the right edge (stitch 1), WS rows at the left (the last stitch)
            stitch = k + 1 if side == "RS" else width - k
            purl_on_rs = op == "p" if side == "RS" else op == "k"
            found[number, stitch] = (names.index(name), purl_on_rs)
    n, m = pattern.shape
    assert set(found) == {(r, s) for r in range(1, 2 * n + 1) for s in range(1, 2 * m + 1)}
    return found


def _nearest_yarn(pattern: LogicalPattern, rgb: np.ndarray, tolerance: float = 40.0) -> int:
    distance = np.abs(pattern.palette.astype(float) - rgb.astype(float)).sum(axis=1)
    assert distance.min() <= tolerance, f"{rgb} is no yarn's colour"
    return int(np.argmin(distance))


def _is_dot(pattern: LogicalPattern, rgb: np.ndarray, yarn: int) -> bool:
    return float(np.abs(pattern.palette[yarn].astype(float) - rgb).sum()) > 60


# -- chart.png -------------------------------------------------------------------------------


def png_stitches(
    pattern: LogicalPattern, *, cell: int, unit_aspect: float, img: np.ndarray | None = None
) -> Stitches:
    """Every stitch as chart.png (``img``, default drawn here) draws it: the colour of a corner
    of its square (clear of the grid line and the dot), and whether its centre is dotted."""
    if img is None:
        img = chart_png_rgb(pattern, cell=cell, unit_aspect=unit_aspect)
    n, m = pattern.shape
    rows, width, margin = 2 * n, 2 * m, 40
    ch = max(2, round(cell * unit_aspect))
    found: Stitches = {}
    for r in range(1, rows + 1):
        for s in range(1, width + 1):
            top, left = margin + (rows - r) * ch, margin + (width - s) * cell
            yarn = _nearest_yarn(pattern, img[top + ch - 2, left + cell - 2], tolerance=0)
            centre = img[top + ch // 2, left + cell // 2].astype(float)
            found[r, s] = (yarn, _is_dot(pattern, centre, yarn))
    return found


@pytest.mark.parametrize("unit_aspect", [1.0, 0.75])
@pytest.mark.parametrize("name", sorted(PATTERNS))
def test_chart_png_shows_every_stitch_as_written(name, unit_aspect):
    pattern = PATTERNS[name]
    assert png_stitches(pattern, cell=12, unit_aspect=unit_aspect) == written_stitches(pattern)


@st.composite
def patterns(draw):
    n, m = draw(st.integers(1, 5)), draw(st.integers(1, 5))
    yarn = draw(arrays(np.int16, (n, m), elements=st.integers(0, 2)))
    raised = draw(arrays(np.bool_, (n, m)))
    upper = np.where(raised, draw(arrays(np.int16, (n, m), elements=st.integers(0, 2))), yarn)
    return LogicalPattern(yarn, raised, YARNS, upper=upper)


@settings(max_examples=30, deadline=None)
@given(patterns())
def test_chart_png_and_written_rows_agree_on_any_pattern(pattern):
    assert png_stitches(pattern, cell=10, unit_aspect=1.0) == written_stitches(pattern)


def test_a_flipped_or_mirrored_chart_would_be_caught():
    """The comparison sees orientation: the asymmetric pattern turned upside down or mirrored
    has other written rows."""
    p = ASYMMETRIC
    written = written_stitches(p)
    for flip in (np.flipud, np.fliplr):
        turned = LogicalPattern(flip(p.yarn), flip(p.raised), p.yarns)
        assert png_stitches(turned, cell=12, unit_aspect=1.0) != written


def test_the_pattern_folder_s_chart_and_instructions_agree(tmp_path):
    """What export_pattern writes (chart.png, instructions.txt, chart.svg), read from the files."""
    from illuknit.core.machine import DEFAULT_MACHINE
    from illuknit.outputs.export import export_pattern

    pattern = ASYMMETRIC
    export_pattern(pattern, tmp_path)
    written = written_stitches(pattern, (tmp_path / "instructions.txt").read_text())
    assert written == written_stitches(pattern)
    aspect = DEFAULT_MACHINE.fabric_gauge.unit_aspect
    img = np.asarray(Image.open(tmp_path / "chart.png").convert("RGB"))
    # a chart this small is drawn 14 pixels a stitch (chart_png_rgb's default cell)
    assert np.array_equal(img, chart_png_rgb(pattern, cell=14, unit_aspect=aspect))
    assert png_stitches(pattern, cell=14, unit_aspect=aspect, img=img) == written
    assert (tmp_path / "chart.svg").read_text() == chart_svg(pattern, unit_aspect=aspect)


# -- chart.svg -------------------------------------------------------------------------------


def svg_stitches(pattern: LogicalPattern, *, cell: float = 10.0) -> Stitches:
    """Every stitch as chart.svg draws it: the run rectangle over it and the dots on it."""
    svg = chart_svg(pattern, cell=cell, unit_aspect=1.0, chart="stitches")
    n, m = pattern.shape
    rows, width, pad = 2 * n, 2 * m, 3 * cell
    hexes = [y.hex.lower() for y in pattern.yarns]
    found: Stitches = {}
    for x, y, w, fill in re.findall(
        r'<rect x="([\d.]+)" y="([\d.]+)" width="([\d.]+)" height="[\d.]+" fill="(#\w+)"/>', svg
    ):
        r = rows - round((float(y) - pad) / cell)
        last = width - round((float(x) - pad) / cell)  # a run's left edge is its last stitch
        for s in range(last - round(float(w) / cell) + 1, last + 1):
            found[r, s] = (hexes.index(fill.lower()), False)
    for cx, cy in re.findall(r'<circle cx="([\d.]+)" cy="([\d.]+)"', svg):
        r = rows - int((float(cy) - pad) // cell)
        s = width - int((float(cx) - pad) // cell)
        found[r, s] = (found[r, s][0], True)
    return found


@pytest.mark.parametrize("name", sorted(PATTERNS))
def test_chart_svg_shows_every_stitch_as_written(name):
    pattern = PATTERNS[name]
    assert svg_stitches(pattern) == written_stitches(pattern)


@pytest.mark.parametrize("name", sorted(PATTERNS))
def test_the_default_chart_svg_shows_every_unit_as_written(name):
    """chart.svg's default, a square a unit as the PDF draws it: the square in the yarn of its
    RS row, its top half (class "ws") in the yarn of its WS row when that differs, dotted
    where the WS row is knit (a ridge); read back against the written rows."""
    pattern, cell = PATTERNS[name], 10.0
    svg = chart_svg(pattern, cell=cell, unit_aspect=1.0)
    written = written_stitches(pattern)
    n, m = pattern.shape
    hexes = [y.hex.lower() for y in pattern.yarns]
    rs: dict[tuple[int, int], int] = {}
    ws: dict[tuple[int, int], int] = {}
    for cls, x, y, w, fill in re.findall(
        r'<rect (class="ws" )?x="([\d.]+)" y="([\d.]+)" width="([\d.]+)" height="[\d.]+" '
        r'fill="(#\w+)"/>',
        svg,
    ):
        u = n - int((float(y) - 3 * cell) // cell)
        last = m - round((float(x) - 3 * cell) / cell)
        for v in range(last - round(float(w) / cell) + 1, last + 1):
            (ws if cls else rs)[u, v] = hexes.index(fill.lower())
    dotted = {
        (n - int((float(cy) - 3 * cell) // cell), m - int((float(cx) - 3 * cell) // cell))
        for cx, cy in re.findall(r'<circle cx="([\d.]+)" cy="([\d.]+)"', svg)
    }
    for u in range(1, n + 1):
        for v in range(1, m + 1):
            (rs_yarn, _), (ws_yarn, ridge) = written[2 * u - 1, 2 * v], written[2 * u, 2 * v]
            assert rs[u, v] == rs_yarn and ws.get((u, v), rs_yarn) == ws_yarn, (u, v)
            assert ((u, v) in dotted) == ridge, (u, v)


# -- the chart pages of pattern.pdf ----------------------------------------------------------


def _chart_page_picture(
    pattern: LogicalPattern, chart: str, tmp_path: Path, border: int = 0
) -> np.ndarray:
    """The first chart page of pattern.pdf, rendered at 150 dpi."""
    pypdf = pytest.importorskip("pypdf", reason="the test extra (pypdf) is not installed")
    if shutil.which("pdftoppm") is None:
        pytest.skip("pdftoppm (poppler-utils) is not installed")
    data = pattern_pdf(pattern, gauge=parse_gauge("20x20/10cm"), chart=chart, border=border)
    pages = [p.extract_text() for p in pypdf.PdfReader(io.BytesIO(data)).pages]
    number = next(i for i, text in enumerate(pages) if "Chart page 1 of 1" in text) + 1
    (tmp_path / "p.pdf").write_bytes(data)
    page = ["-f", str(number), "-l", str(number)]
    out = [str(tmp_path / "p.pdf"), str(tmp_path / "page")]
    subprocess.run(["pdftoppm", "-r", "150", *page, "-png", "-singlefile", *out], check=True)
    return np.asarray(Image.open(tmp_path / "page.png").convert("RGB")).astype(float)


def _squares(img: np.ndarray, pattern: LogicalPattern, rows: int, cols: int):
    """A function (row, column, (down, across) within the square) -> the pixel there; the grid
    is the box of the page's pixels in a yarn's colour."""
    near = np.stack([np.abs(img - c).sum(axis=2) < 12 for c in pattern.palette.astype(float)])
    ys, xs = np.nonzero(near.any(axis=0))
    top, bottom, left, right = ys.min(), ys.max() + 1, xs.min(), xs.max() + 1
    h, w = (bottom - top) / rows, (right - left) / cols

    def at(row: int, col: int, where: tuple[float, float]) -> np.ndarray:
        y = top + (rows - row + where[0]) * h  # row 1 at the bottom
        x = left + (cols - col + where[1]) * w  # column 1 at the right
        return img[int(y), int(x)]

    return at


def pdf_stitches(pattern: LogicalPattern, tmp_path: Path, border: int = 0) -> Stitches:
    """Every stitch as the PDF's chart (a square a stitch) draws it."""
    img = _chart_page_picture(pattern, "stitches", tmp_path, border)
    n, m = with_border(pattern, border).shape
    at = _squares(img, pattern, 2 * n, 2 * m)
    found: Stitches = {}
    for r in range(1, 2 * n + 1):
        for s in range(1, 2 * m + 1):
            yarn = _nearest_yarn(pattern, at(r, s, (0.8, 0.2)))
            found[r, s] = (yarn, _is_dot(pattern, at(r, s, (0.5, 0.5)), yarn))
    return found


@pytest.mark.parametrize("name", sorted(PATTERNS))
def test_the_pdf_chart_of_stitches_shows_every_stitch_as_written(name, tmp_path):
    pattern = PATTERNS[name]
    assert pdf_stitches(pattern, tmp_path) == written_stitches(pattern)


@pytest.mark.parametrize("name", sorted(PATTERNS))
def test_the_pdf_chart_of_units_shows_every_unit_as_written(name, tmp_path):
    """A square a unit (2 stitches x 2 rows): its lower half in the yarn of its RS row, its
    upper half in the yarn of its WS row, dotted where the WS row is knit (a ridge)."""
    pattern = PATTERNS[name]
    written = written_stitches(pattern)
    n, m = pattern.shape
    at = _squares(_chart_page_picture(pattern, "units", tmp_path), pattern, n, m)
    for u in range(1, n + 1):
        for v in range(1, m + 1):
            rs = {written[2 * u - 1, s] for s in (2 * v - 1, 2 * v)}
            ws = {written[2 * u, s] for s in (2 * v - 1, 2 * v)}
            assert len(rs) == len(ws) == 1, "a unit is one yarn and one stitch per row"
            (rs_yarn, rs_purl), (ws_yarn, ridge) = rs.pop(), ws.pop()
            assert not rs_purl, "RS rows are knit"
            assert _nearest_yarn(pattern, at(u, v, (0.85, 0.15))) == rs_yarn, (u, v)
            assert _nearest_yarn(pattern, at(u, v, (0.15, 0.15))) == ws_yarn, (u, v)
            assert _is_dot(pattern, at(u, v, (0.5, 0.5)), rs_yarn) == ridge, (u, v)


# -- the garter border (pattern_pdf(border=...)) ---------------------------------------------


@pytest.mark.parametrize("name", sorted(PATTERNS))
def test_the_border_is_written_and_charted_alike(name, tmp_path):
    """With a border of 1 ridge unit the PDF's written rows, read back from its text, are the
    design's stitches framed by 2 garter stitches at each side and 2 garter rows at the cast-on
    and bind-off edges (4 stitches and 4 rows more), and its chart shows exactly those."""
    pypdf = pytest.importorskip("pypdf", reason="the test extra (pypdf) is not installed")
    pattern = PATTERNS[name]
    n, m = pattern.shape
    data = pattern_pdf(pattern, gauge=parse_gauge("20x20/10cm"), chart="stitches", border=1)
    text = "\n".join(p.extract_text() for p in pypdf.PdfReader(io.BytesIO(data)).pages)
    framed = with_border(pattern, 1)
    assert framed.shape == (n + 2, m + 2)
    written = written_stitches(framed, text)
    assert written == written_stitches(framed)  # as instructions.txt writes the framed rows
    for (r, s), stitch in written_stitches(pattern).items():
        assert written[r + 2, s + 2] == stitch, (r, s)  # the design, untouched, inside
    for (r, s), (_, purl_on_rs) in written.items():
        if not (2 < r <= 2 * n + 2 and 2 < s <= 2 * m + 2):  # the border: knit every row
            assert purl_on_rs == (r % 2 == 0), (r, s)
    flat = " ".join(text.split())
    assert f"CO {2 * m + 4} sts" in flat and "It adds 4 stitches and 4 rows" in flat
    assert pdf_stitches(pattern, tmp_path, border=1) == written


def test_no_border_leaves_the_written_rows_as_they_were():
    pattern = PATTERNS["asymmetric"]
    assert with_border(pattern, 0) is pattern
    with pytest.raises(IlluknitError, match="`border`"):
        with_border(pattern, -1)
