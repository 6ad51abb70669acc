"""pattern.pdf and chart.svg: what a knitter prints, read back as text and rendered to pictures."""

from __future__ import annotations

import io
import re
import shutil
import subprocess
import xml.etree.ElementTree as ET
from itertools import pairwise
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from PIL import Image

from illuknit.core.errors import IlluknitError
from illuknit.core.gauge import parse_gauge
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.outputs import pattern_pdf as pdf_module
from illuknit.outputs import pdf_document
from illuknit.outputs.captions import headon_likeness
from illuknit.outputs.pattern_pdf import CELL_MM, chart_svg, chart_tiles, pattern_pdf, pdf_fonts

pypdf = pytest.importorskip("pypdf", reason="the test extra (pypdf) is not installed")


def pdf_pages(data: bytes) -> list[str]:
    return [page.extract_text() for page in pypdf.PdfReader(io.BytesIO(data)).pages]


def assert_is_a_pattern(pages: list[str], pattern: LogicalPattern, gauge_text: str) -> None:
    text = "\n".join(pages)
    n, m = pattern.shape
    for needed in (
        "Finished size",
        "Materials",
        "Gauge",
        "Abbreviations",
        "How to read the chart",
        "Key",
        "Written rows",
        "Skill level",
        "Finishing",
        "Wet-block",
        "To hang and view it",
        "By hand: ",
        gauge_text,
    ):
        assert needed in " ".join(text.split()), needed
    assert re.search(r"\d+\.\d x \d+\.\d cm \(\d+\.\d x \d+\.\d in\)", text)
    # materials: every used yarn with a length
    for y in pattern.yarns:
        if (pattern.yarn == pattern.yarns.index(y)).any():
            assert re.search(rf"{re.escape(y.name)} \({y.hex}\): \d+ sts, about \d+ m", text), y
    # every row, with its stitch count
    rows = re.findall(r"Row (\d+) \((RS|WS)\): .*?\((\d+) sts\)", text)
    assert [int(r[0]) for r in rows] == list(range(1, 2 * n + 1))
    assert {int(r[2]) for r in rows} == {2 * m}


def small_pattern(shape=(6, 10), k=2, seed=1) -> LogicalPattern:
    rng = np.random.default_rng(seed)
    yarns = parse_yarns("black,firebrick,linen")[:k]
    return LogicalPattern(rng.integers(0, k, shape), rng.random(shape) < 0.3, yarns)


def test_single_view_design_writes_a_pattern_pdf(tmp_path: Path, run_cli=None) -> None:
    from illuknit.cli import main

    img = np.full((30, 40, 3), 240, np.uint8)
    img[8:22, 10:30] = 20
    Image.fromarray(img).save(tmp_path / "pic.png")
    out = tmp_path / "out"
    main(["single", str(tmp_path / "pic.png"), "--width", "20", "-o", str(out)])
    from illuknit.core.pattern import load_pattern

    pattern = load_pattern(out / "pattern.json")
    pages = pdf_pages((out / "pattern.pdf").read_bytes())
    assert_is_a_pattern(pages, pattern, "27.6 sts x 39.4 rows per 10 cm")
    assert (out / "chart.svg").read_text().startswith("<svg")
    # a single view is stripes head-on, measured (issue 33): the cover says so
    assert "Head-on: stripes (no picture)" in pages[0]
    # issue 37: by default a chart square is a ridge unit
    assert "A square is 2 stitches x 2 rows" in " ".join("\n".join(pages).split())


def test_three_colour_double_view_writes_a_pattern_pdf(tmp_path: Path) -> None:
    from illuknit.cli import main
    from illuknit.core.pattern import load_pattern

    a = np.full((40, 40, 3), (244, 240, 232), np.uint8)
    a[5:35, 5:35] = (27, 27, 27)
    a[15:25, 15:25] = (179, 32, 42)
    b = np.full((40, 40, 3), (244, 240, 232), np.uint8)
    b[10:30, :] = (179, 32, 42)
    b[:, 18:22] = (27, 27, 27)
    Image.fromarray(a).save(tmp_path / "a.png")
    Image.fromarray(b).save(tmp_path / "b.png")
    out = tmp_path / "out"
    main(
        [
            "double",
            str(tmp_path / "a.png"),
            str(tmp_path / "b.png"),
            "--yarns",
            "#1b1b1b,#b3202a,#f4f0e8",
            "--width",
            "16",
            "--candidates",
            "1",
            "--fabric-gauge",
            "22x30/10cm",
            "--chart",
            "stitches",
            "-o",
            str(out),
        ]
    )
    pattern = load_pattern(out / "pattern.json")
    assert len(pattern.yarns) == 3
    pages = pdf_pages((out / "pattern.pdf").read_bytes())
    assert_is_a_pattern(pages, pattern, "22 sts x 30 rows per 10 cm")
    assert "--fabric-gauge: 22x30/10cm" in "\n".join(pages)
    flat = " ".join("\n".join(pages).split())  # --chart stitches: a square a stitch
    assert "Dot: purl on RS, knit on WS" in flat and "A square is 2 stitches" not in flat
    # head-on a double view shows both its pictures, mixed: the cover once said "stripes"
    cover = " ".join(pages[0].split())
    assert "stripes" not in cover, cover
    likeness = headon_likeness(pattern)
    assert likeness.shows == "both" and likeness.caption() in cover


def test_a_240_stitch_chart_is_tiled_over_printable_pages(tmp_path: Path) -> None:
    tiles = chart_tiles(240, 340, page="A4")
    assert len({t.across for t in tiles}) >= 6 and len({t.down for t in tiles}) >= 6
    # every stitch and row is on a page, neighbours share exactly one column / row
    across = sorted({(t.c0, t.c1) for t in tiles})
    assert across[0][0] == 1 and across[-1][1] == 240
    assert all(a[1] == b[0] for a, b in pairwise(across))
    letter = chart_tiles(240, 340, page="Letter")
    assert letter and all(t.c1 - t.c0 + 1 <= 40 for t in letter)

    pattern = small_pattern((20, 120))
    data = pattern_pdf(pattern, gauge=parse_gauge("22x30/10cm"), chart="stitches")
    pages = pdf_pages(data)
    chart_pages = [p for p in pages if re.search(r"Chart page \d+ of \d+", p)]
    assert len(chart_pages) == len(chart_tiles(240, 40)) >= 6
    for p in chart_pages:
        flat = " ".join(p.split())
        assert "Row 1 at the bottom" in flat and "Hatched: shared with page" in flat
        numbers = [int(w) for w in re.findall(r"\d+", p.split("\n", 1)[1])]
        # every row number 1..40 once (RS at the right, WS at the left), stitch numbers twice
        assert all(numbers.count(r) >= 1 for r in range(1, 41)), numbers
        first, last = map(int, re.search(r"stitches (\d+)-(\d+)", p).groups())
        assert numbers.count(first) >= 2
        assert numbers.count(last) >= 2
    if shutil.which("pdftoppm") is None:
        pytest.skip("pdftoppm (poppler-utils) is not installed")
    first_chart = next(i for i, p in enumerate(pages) if re.search(r"Chart page 1 of", p)) + 1
    pdf = tmp_path / "p.pdf"
    pdf.write_bytes(data)
    subprocess.run(
        [
            "pdftoppm",
            "-r",
            "72",
            "-f",
            str(first_chart),
            "-l",
            str(first_chart),
            "-png",
            "-singlefile",
            str(pdf),
            str(tmp_path / "page"),
        ],
        check=True,
    )
    img = np.asarray(Image.open(tmp_path / "page.png").convert("L"))
    # A4 at 72 dpi; a chart cell of 4.5 mm is about 13 pixels: the grid is drawn, not blank
    assert abs(img.shape[0] - 842) <= 1 and abs(img.shape[1] - 595) <= 1
    assert (img < 128).mean() > 0.05
    assert CELL_MM >= 4


def test_chart_svg_has_every_stitch() -> None:
    pattern = small_pattern((3, 7), k=3)
    ns = "{http://www.w3.org/2000/svg}"
    for chart, squares, dotted in (
        ("stitches", 6 * 14, 2 * int(pattern.raised.sum())),  # a raised unit: 2 purls on RS
        ("units", 3 * 7, int(pattern.raised.sum())),  # the default: a square a ridge
    ):
        root = ET.fromstring(chart_svg(pattern, cell=10, chart=chart))
        rects = [r for r in root.iter(f"{ns}rect") if r.get("width") != "100%"]
        rects = [r for r in rects if r.get("class") != "ws"]
        assert sum(float(r.get("width")) for r in rects) == pytest.approx(squares * 10), chart
        assert len(list(root.iter(f"{ns}circle"))) == dotted, chart
    assert chart_svg(pattern) == chart_svg(pattern, chart="units")


def test_chart_svg_inks_contrast_with_every_yarn() -> None:
    """Issue 37 item 3 for chart.svg: no grey grid lines; a run's grid and dots are black on a
    light or mid-grey yarn and white on a dark one, the bold lines black on a white halo."""
    shape = (4, 6)
    rng = np.random.default_rng(0)
    yarns = parse_yarns("#808080,#1b1b1b")
    pattern = LogicalPattern(rng.integers(0, 2, shape), np.ones(shape, bool), yarns)
    svg = chart_svg(pattern)
    assert "#888" not in svg
    for fill, ink in (("#808080", "#000"), ("#1b1b1b", "#fff")):
        runs = re.findall(rf'fill="{fill}"/>\n<path d="[^"]+" fill="none" stroke="([^"]+)"', svg)
        assert runs and set(runs) == {ink}, fill
    assert re.search(
        r'stroke="#fff" stroke-width="2.5"/>\n<path d="[^"]+" fill="none" '
        r'stroke="#000" stroke-width="1.2"',
        svg,
    )


def test_yarn_names_outside_latin1_are_written_as_they_are() -> None:
    """Greek from the bundled DejaVu Sans; Chinese from a system font when one is found (CI
    installs Debian's fonts-droid-fallback), else as code points with a note saying so."""
    yarns = parse_yarns("Ø深蓝=#1e2a5a,Ελληνικά=#f4f0e8")
    pattern = LogicalPattern(np.array([[0, 1], [1, 0]]), np.array([[True, False]] * 2), yarns)
    text = "\n".join(pdf_pages(pattern_pdf(pattern, gauge=parse_gauge("22x30/10cm"))))
    assert re.search(r"Ελληνικά \(#f4f0e8\): \d+ sts", text)
    if pdf_fonts("深蓝").fallbacks:
        assert re.search(r"Ø深蓝 \(#1e2a5a\): \d+ sts", text)
        assert "?" not in text.split("Materials")[1].split("Gauge")[0]
    else:
        assert "Ø<U+6DF1><U+84DD> (#1e2a5a)" in text
        assert "U+6DF1, U+84DD" in " ".join(text.split())


def test_characters_no_font_has_become_code_points(monkeypatch: pytest.MonkeyPatch) -> None:
    # the fonts live in pdf_document; pattern_pdf only re-exports them
    monkeypatch.setattr(pdf_document, "FALLBACK_FONTS", ())
    monkeypatch.delenv(pdf_module.FONTS_ENV, raising=False)
    fonts = pdf_fonts("Ø深蓝 Ελληνικά")
    assert fonts.fallbacks == ()
    assert fonts.text("Ø深蓝 Ελληνικά – x") == "Ø<U+6DF1><U+84DD> Ελληνικά – x"
    assert fonts.missing("深蓝ØA") == ["U+6DF1", "U+84DD"]


def test_every_page_has_its_number_and_the_design_name() -> None:
    """Issue 37: a loose page finds its place: "page N of M" and the design's name on each."""
    pages = pdf_pages(
        pattern_pdf(small_pattern((30, 50)), gauge=parse_gauge("22x30/10cm"), title="Owl")
    )
    assert len(pages) >= 4
    for k, text in enumerate(pages, 1):
        assert f"page {k} of {len(pages)}" in text and "Owl" in text, (k, text[-200:])


def test_the_default_chart_is_a_square_a_ridge_and_takes_fewer_pages() -> None:
    """Issue 37: one square a unit (2 stitches x 2 rows) by default, the stitch chart an option;
    a 96 x 138 stitch design's chart: 2 pages instead of 6, 200 x 286: 6 instead of 24 (A4)."""
    row = CELL_MM * 0.7  # a row 0.7 of a stitch tall (the default machine's 5:7 gauge)
    pages = {size: len(chart_tiles(*size, row_mm=row)) for size in ((48, 69), (96, 138))}
    assert pages == {(48, 69): 2, (96, 138): 6}
    pages = {size: len(chart_tiles(*size, row_mm=row)) for size in ((100, 143), (200, 286))}
    assert pages == {(100, 143): 6, (200, 286): 24}
    pattern = small_pattern((20, 60))
    gauge = parse_gauge("22x30/10cm")
    units, stitches = (
        pdf_pages(pattern_pdf(pattern, gauge=gauge, chart=c)) for c in ("units", "stitches")
    )
    count = lambda pages: sum(bool(re.search(r"Chart page \d+ of", p)) for p in pages)  # noqa: E731
    assert count(units) == len(chart_tiles(60, 20)) < count(stitches) == len(chart_tiles(120, 40))
    first = next(p for p in units if "Chart page 1 of" in p)
    # the page's stitches and every row (a square's RS row at the right, its WS row at the left)
    assert re.search(r"stitches 1-(\d+) \(from the right\), rows 1-40", first)
    for j in range(1, 21):  # a square's two rows share a line: "3" at the right, "4" at the left
        assert re.search(rf"^{2 * j - 1}(S\d+)? ?{2 * j}$", first, re.MULTILINE), j
    assert "A square is 2 stitches x 2 rows" in " ".join(first.split())
    with pytest.raises(IlluknitError, match="`chart`"):
        pattern_pdf(pattern, gauge=gauge, chart="rows")


def test_grid_lines_show_on_a_mid_grey_yarn(tmp_path: Path) -> None:
    """Issue 37: the thin grid lines vanished on a mid-grey yarn (grey on grey); now each is
    drawn in the ink that contrasts with its yarn."""
    if shutil.which("pdftoppm") is None:
        pytest.skip("pdftoppm (poppler-utils) is not installed")
    grey = LogicalPattern(
        np.zeros((4, 4), np.int16), np.zeros((4, 4), bool), parse_yarns("#808080")
    )
    data = pattern_pdf(grey, gauge=parse_gauge("22x22/10cm"), chart="stitches")
    pages = pdf_pages(data)
    at = next(i for i, p in enumerate(pages) if "Chart page 1 of" in p) + 1
    (tmp_path / "p.pdf").write_bytes(data)
    subprocess.run(
        [
            "pdftoppm",
            "-r",
            "200",
            "-f",
            str(at),
            "-l",
            str(at),
            "-gray",
            "-singlefile",
            str(tmp_path / "p.pdf"),
            str(tmp_path / "g"),
        ],
        check=True,
    )
    img = np.asarray(Image.open(tmp_path / "g.pgm")).astype(int)
    grey_px = np.abs(img - 128) < 10  # the grey cells (not the anti-aliased text)
    ys = np.flatnonzero(grey_px.sum(axis=1) > 100)
    xs = np.flatnonzero(grey_px.sum(axis=0) > 100)
    inside = img[ys.min() + 6 : ys.max() - 6, xs.min() + 6 : xs.max() - 6]
    # 8 x 8 stitches of 4.5 mm: 7 inner lines each way, each at least a pixel of near-black
    dark_cols = (inside < 50).mean(axis=0) > 0.5
    dark_rows = (inside < 50).mean(axis=1) > 0.5
    runs = lambda a: int((np.diff(a.astype(int)) == 1).sum())  # noqa: E731
    assert runs(dark_cols) >= 6 and runs(dark_rows) >= 6


def test_hand_gauge_swatch_and_no_machine_words() -> None:
    """Issue 37 item 4: an unmeasured (machine) gauge gives the hand illusion-fabric estimate,
    a swatch big enough to measure 10 cm in its middle and how to feed it back; no machine
    words in a hand pattern."""
    from illuknit.core.machine import DEFAULT_MACHINE

    pages = pdf_pages(pattern_pdf(small_pattern(), gauge=DEFAULT_MACHINE.fabric_gauge))
    text = " ".join("\n".join(pages).split())
    for machine_word in ("needle at gauge", "SWG", "V-bed", "540"):
        assert machine_word not in text, machine_word
    assert "Hand-knitted illusion fabric" in text and "1.75-1.92" in text
    m = re.search(r"Gauge swatch \(about 15 x 15 cm\): cast on (\d+) stitches", text)
    assert m and int(m[1]) * 10 / 27.6 >= 15
    assert "--fabric-gauge" in text and "By hand:" in pages[0]


@given(st.floats(5, 60), st.floats(5, 90))
def test_a_swatch_measures_10cm_in_its_middle(sts: float, rows: float) -> None:
    from illuknit.core.gauge import Gauge, swatch_size

    g = Gauge(sts, rows)
    n, r = swatch_size(g)
    assert n * g.stitch_cm >= 15 - 1e-9 and r * g.row_cm >= 15 - 1e-9
    assert n % 2 == 0 and r % 4 == 0


@pytest.mark.parametrize(
    "stripe, says",
    [([0, 1], "every 2 rows"), ([0, 0, 1, 1], "every 4 rows"), ([0, 1, 1], "every 2 to 4 rows")],
)
def test_the_skill_level_names_the_stripes_the_design_has(stripe, says) -> None:
    # one yarn a row, unit rows cycling through `stripe` (2 hand rows each)
    n, m = 13, 6
    yarn = np.array([[stripe[r % len(stripe)]] * m for r in range(n)])
    pattern = LogicalPattern(yarn, np.zeros((n, m), bool), parse_yarns("navy,linen"))
    text = " ".join(
        " ".join(pdf_pages(pattern_pdf(pattern, gauge=parse_gauge("22x30/10cm")))).split()
    )
    assert f"Easy: knit, purl and a change of yarn {says};" in text
