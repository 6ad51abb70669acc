"""One proportion: every picture a person sees is drawn in the fabric's proportions (issue 33,
item 8).

A unit is 2 stitches x 2 rows, about 0.7 as tall as wide in stocking stitch; a picture drawn one
square pixel a unit is 1.43x too tall and a round ring becomes an oval. Each test knits a disc
(round in the fabric) and measures its width over its height in each output; angled views,
labelled with their angle, are foreshortened by the sine of it.
"""

from __future__ import annotations

import math
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from scipy import ndimage

from illuknit.cli import main
from illuknit.core.machine import DEFAULT_MACHINE
from illuknit.core.pattern import LogicalPattern, Yarn, load_pattern, save_pattern

ASPECT = DEFAULT_MACHINE.fabric_gauge.unit_aspect
YARNS = (Yarn("Dark", (27, 27, 27)), Yarn("Light", (244, 240, 232)))
TOL = 0.12  # a disc 30 units across, drawn on whole units and pixels


def disc_shapes(img: np.ndarray) -> list[float]:
    """Width over height of each dark blob at least a fifth the size of the largest (titles,
    numbers and key swatches are smaller)."""
    dark = np.asarray(img)[..., :3].max(axis=-1) < 90
    labels, count = ndimage.label(dark)
    boxes = ndimage.find_objects(labels)
    areas = ndimage.sum(dark, labels, range(1, count + 1))
    keep = [b for b, a in zip(boxes, areas, strict=True) if a >= 0.2 * areas.max()]
    return [(b[1].stop - b[1].start) / (b[0].stop - b[0].start) for b in keep]


def disc_pattern(width: int = 40, radius: float = 15.0) -> LogicalPattern:
    """A flat pattern (every view shows its yarn) holding a disc round in the fabric."""
    rows = round(width / ASPECT)
    y = (np.arange(rows)[:, None] + 0.5) * ASPECT - rows * ASPECT / 2
    x = np.arange(width)[None, :] + 0.5 - width / 2
    yarn = np.where(x**2 + y**2 <= radius**2, 0, 1).astype(np.int16)
    return LogicalPattern(yarn, np.zeros(yarn.shape, dtype=bool), YARNS)


def _round(shapes: list[float], *, also: float | None = None) -> None:
    assert shapes
    for s in shapes:
        assert abs(s - 1) <= TOL or (also is not None and abs(s - also) <= TOL * also), shapes


@pytest.fixture(scope="module")
def disc_file(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("disc") / "pattern.json"
    save_pattern(disc_pattern(), path)
    return path


def test_view_draws_the_disc_round_everywhere(disc_file, tmp_path):
    out = tmp_path / "view"
    main(["view", str(disc_file), "-o", str(out)])
    for name in ("headon", "view_a", "view_b", "chart"):
        _round(disc_shapes(np.asarray(Image.open(out / f"{name}.png"))))
    theta = math.radians(30)
    # the contact sheet also holds the renders at 30 degrees, foreshortened as seen
    _round(disc_shapes(np.asarray(Image.open(out / "contact.png"))), also=1 / math.sin(theta))
    if shutil.which("pdftoppm") is None:
        pytest.skip("pdftoppm (poppler-utils) is not installed")
    pdf, cover = str(out / "pattern.pdf"), str(tmp_path / "cover")
    subprocess.run(
        ["pdftoppm", "-r", "100", "-l", "1", "-png", "-singlefile", pdf, cover], check=True
    )
    cover = np.asarray(Image.open(tmp_path / "cover.png").convert("RGB"))
    _round(disc_shapes(cover), also=1 / math.sin(theta))


def test_render_draws_the_disc_round_head_on_and_foreshortened_at_an_angle(disc_file, tmp_path):
    out = tmp_path / "render"
    main(["render", str(disc_file), "--angle", "40", "--frames", "2", "-o", str(out)])
    _round(disc_shapes(np.asarray(Image.open(out / "headon.png"))))
    for name in ("view_a", "view_b"):
        (shape,) = disc_shapes(np.asarray(Image.open(out / f"{name}.png")))
        assert shape == pytest.approx(1 / math.sin(math.radians(40)), rel=TOL)


def test_single_draws_a_round_picture_round(tmp_path):
    """A round picture through sizing, quantising, the previews, the chart and seen.png."""
    yy, xx = np.mgrid[0:240, 0:240]
    picture = np.where(((yy - 120) ** 2 + (xx - 120) ** 2 <= 90**2)[..., None], 20, 240)
    Image.fromarray(np.repeat(picture, 3, axis=2).astype(np.uint8)).save(tmp_path / "disc.png")
    out = tmp_path / "single"
    main(["single", str(tmp_path / "disc.png"), "--width", "40", "-o", str(out)])
    assert load_pattern(out / "pattern.json").shape == (round(40 / ASPECT), 40)
    for name in ("quantised_picture", "view_a", "view_b", "seen"):
        _round(disc_shapes(np.asarray(Image.open(out / f"{name}.png"))))


def _bbox_aspect(mask: np.ndarray, *, min_count: int = 5) -> float:
    """Width over height of the rows and columns holding at least ``min_count`` mask pixels
    (stray anti-aliased text pixels do not count)."""
    rows = np.flatnonzero(mask.sum(axis=1) >= min_count)
    cols = np.flatnonzero(mask.sum(axis=0) >= min_count)
    return (cols[-1] - cols[0] + 1) / (rows[-1] - rows[0] + 1)


def test_the_pdf_chart_and_chart_svg_are_in_the_fabrics_proportions(tmp_path):
    import re

    from illuknit.core.machine import DEFAULT_MACHINE
    from illuknit.outputs.pattern_pdf import chart_svg, pattern_pdf

    pattern = disc_pattern(width=16, radius=6.0)  # 32 stitches, 46 rows: one chart page
    svg = chart_svg(pattern, cell=10)
    rects = [
        (float(x), float(y), float(w), float(h))
        for x, y, w, h, fill in re.findall(
            r'<rect x="([\d.]+)" y="([\d.]+)" width="([\d.]+)" height="([\d.]+)" fill="(#1b1b1b)"',
            svg,
        )
    ]
    x0, x1 = min(r[0] for r in rects), max(r[0] + r[2] for r in rects)
    y0, y1 = min(r[1] for r in rects), max(r[1] + r[3] for r in rects)
    assert (x1 - x0) / (y1 - y0) == pytest.approx(1.0, rel=TOL)
    if shutil.which("pdftoppm") is None:
        pytest.skip("pdftoppm (poppler-utils) is not installed")
    from pypdf import PdfReader

    (tmp_path / "p.pdf").write_bytes(pattern_pdf(pattern, gauge=DEFAULT_MACHINE.fabric_gauge))
    texts = [p.extract_text() for p in PdfReader(tmp_path / "p.pdf").pages]
    n = str(next(i for i, t in enumerate(texts) if "Chart page 1 of 1" in t) + 1)
    pdf, page = str(tmp_path / "p.pdf"), str(tmp_path / "page")
    subprocess.run(
        ["pdftoppm", "-r", "100", "-f", n, "-l", n, "-png", "-singlefile", pdf, page], check=True
    )
    img = np.asarray(Image.open(page + ".png").convert("RGB")).astype(int)
    yarn = (np.abs(img - 27) <= 12).all(axis=-1)  # the dark yarn, not the black grid lines
    # only inside the chart grid (the light yarn's extent): the title, the notes and the
    # footer's anti-aliased text have pixels of that grey too
    light = (np.abs(img - np.array([244, 240, 232])) <= 6).all(axis=-1)
    rows, cols = (np.flatnonzero(light.sum(axis=k) >= 20) for k in (1, 0))
    grid = np.zeros_like(yarn)
    grid[rows[0] : rows[-1] + 1, cols[0] : cols[-1] + 1] = True
    assert _bbox_aspect(yarn & grid) == pytest.approx(1.0, rel=TOL)
