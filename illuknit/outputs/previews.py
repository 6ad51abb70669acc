"""Preview pictures of a pattern: the head-on chart, the side views, and a contact sheet.

Two kinds of side view: the boolean model (:mod:`illuknit.core.views`, ``view_a.png``/``view_b.png``:
each cell shows the yarn of the unit a viewer sees) and the angled renders of the ray-casting
renderer (:mod:`illuknit.design.render`, ``render_a.png``/``render_b.png``: what a person sees at the
render angle, stripes blending where several units share a pixel). Every picture is upscaled with
nearest-neighbour, one unit drawn in the fabric's proportions (``unit_aspect``: a unit of 2
stitches x 2 rows is about 0.7 as tall as wide), angled renders foreshortened by the sine of
their elevation.
"""

from __future__ import annotations

import io
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.arguments import (
    check_array,
    check_instance,
    check_int,
    check_mapping,
    check_number,
    check_path,
)
from illuknit.core.colors import luminance
from illuknit.core.files import atomic_write_bytes
from illuknit.core.pattern import LogicalPattern, check_pattern
from illuknit.core.views import View, can_see

__all__ = [
    "chart_rgb",
    "contact_sheet",
    "png_bytes",
    "rows_per_unit",
    "save_png",
    "stretch_rows",
    "unit_scale",
    "upscale",
    "view_rgb",
    "write_previews",
]


def view_rgb(pattern: LogicalPattern, view: View) -> NDArray[np.uint8]:
    """ndarray of shape (N, M, 3): colours seen from ``view`` ("A", "B", "headon"), one per unit."""
    return pattern.palette[can_see(pattern, view)]


def unit_scale(shape: tuple[int, int], *, target: int = 640, max_px: int = 2400) -> int:
    """Pixels per unit so that the longer side is about ``target`` pixels (at least 1)."""
    longest = max(shape)
    return int(max(1, min(max_px // max(longest, 1), round(target / max(longest, 1)))))


def upscale(rgb: ArrayLike, scale: int, scale_y: float | None = None) -> NDArray[np.uint8]:
    """Nearest-neighbour upscaling of an (N, M, 3) image by an integer factor; ``scale_y``
    pixel rows per unit (any positive number: ``round(N * scale_y)`` rows) for units that are
    not square."""
    a = np.asarray(rgb, dtype=np.uint8)
    wide = np.repeat(a, scale, axis=1)
    if scale_y is None:
        return np.repeat(wide, scale, axis=0)
    return stretch_rows(wide, round(a.shape[0] * scale_y))


def stretch_rows(img: ArrayLike, height: int) -> NDArray[np.uint8]:
    """``img`` resampled (nearest neighbour) to ``height`` rows, columns unchanged."""
    a = np.asarray(img, dtype=np.uint8)
    h = max(1, int(height))
    return a[(np.arange(h) * a.shape[0]) // h]


def rows_per_unit(scale: int, unit_aspect: float, *, angle: float = 90.0) -> float:
    """Pixel rows for one unit ``scale`` pixels wide, as the fabric is seen: ``unit_aspect``
    (height over width, :attr:`illuknit.core.gauge.Gauge.unit_aspect`) head-on, foreshortened by
    ``sin(angle)`` at an elevation of ``angle`` degrees."""
    return float(scale * unit_aspect * np.sin(np.radians(angle)))


def chart_rgb(
    pattern: LogicalPattern, *, scale: int | None = None, unit_aspect: float = 1.0
) -> NDArray[np.uint8]:
    """The head-on chart: yarn colours, each raised unit marked with a centred square.

    The mark is drawn in a contrasting tone of the unit's own colour so raised units read at a
    glance without hiding the colour. Units are ``unit_aspect`` as tall as wide (the fabric's
    proportions, :attr:`illuknit.core.gauge.Gauge.unit_aspect`).
    """
    n, m = pattern.shape
    s = scale or max(4, unit_scale((n, m)))
    img = upscale(pattern.rgb(), s).astype(np.int16)
    pal = pattern.palette.astype(np.int16)
    dark = luminance(pattern.palette) > 0.35
    mark = np.where(dark[:, None], pal * 0.45, pal + (255 - pal) * 0.55).astype(np.int16)
    lo, hi = s // 4, s - s // 4
    if hi > lo:
        ii, jj = np.nonzero(pattern.raised)
        block = mark[pattern.yarn[ii, jj]]
        for dy in range(lo, hi):
            for dx in range(lo, hi):
                img[ii * s + dy, jj * s + dx] = block
    square = img.clip(0, 255).astype(np.uint8)
    return square if unit_aspect == 1.0 else stretch_rows(square, round(n * s * unit_aspect))


def png_bytes(rgb: ArrayLike, *, compress_level: int = 6) -> bytes:
    """Encode an (H, W, 3) uint8 image as PNG (zlib ``compress_level`` 0-9; 1 for live previews)."""
    from PIL import Image

    buf = io.BytesIO()
    image = Image.fromarray(np.ascontiguousarray(rgb, dtype=np.uint8))
    image.save(buf, format="PNG", compress_level=compress_level)
    return buf.getvalue()


def save_png(rgb: ArrayLike, path: str | os.PathLike[str]) -> Path:
    """Write an image as PNG atomically."""
    return atomic_write_bytes(path, png_bytes(rgb))


def contact_sheet(
    panels: Sequence[tuple[str, ArrayLike]], *, columns: int | None = None, pad: int = 12
) -> NDArray[np.uint8]:
    """Lay titled images side by side on white (``columns`` per row; default all in one row)."""
    from PIL import Image, ImageDraw, ImageFont

    if not panels:
        raise ValueError("contact_sheet needs at least one panel")
    ims = [np.asarray(p, dtype=np.uint8) for _, p in panels]
    cols = columns or len(ims)
    rows = (len(ims) + cols - 1) // cols
    try:
        font = ImageFont.load_default(size=16)
    except TypeError:  # Pillow < 10.1
        font = ImageFont.load_default()
    # a column is as wide as its widest picture or title, so titles never run into each other
    cell_w = max(max(i.shape[1] for i in ims), *(int(font.getlength(t)) + 4 for t, _ in panels))
    cell_h = max(i.shape[0] for i in ims)
    title_h = 24
    W = cols * cell_w + (cols + 1) * pad
    H = rows * (cell_h + title_h) + (rows + 1) * pad
    sheet = Image.new("RGB", (W, H), (255, 255, 255))
    draw = ImageDraw.Draw(sheet)
    for k, ((title, _), im) in enumerate(zip(panels, ims, strict=True)):
        r, c = divmod(k, cols)
        x = pad + c * (cell_w + pad)
        y = pad + r * (cell_h + title_h + pad)
        draw.text((x, y), title, fill=(30, 30, 30), font=font)
        sheet.paste(Image.fromarray(im), (x, y + title_h))
    return np.asarray(sheet)


def write_previews(
    pattern: LogicalPattern,
    outdir: str | os.PathLike[str],
    *,
    targets: Mapping[str, ArrayLike] | None = None,
    scale: int | None = None,
    params: Any = None,
    angle: float | None = None,
    unit_aspect: float = 1.0,
) -> dict[str, Path]:
    """Write ``headon.png`` (chart), ``view_a.png``, ``view_b.png`` (boolean views),
    ``render_a.png``, ``render_b.png`` (angled renders) and ``contact.png``.

    Parameters
    ----------
    targets : mapping of title -> (N, M, 3) uint8, optional
        Input pictures to show first on the contact sheet (e.g. the quantised picture).
    params : illuknit.design.render.RenderParams, optional
        Renderer parameters (default: the calibrated defaults).
    angle : float, optional
        Viewing elevation in degrees for the renders (default: ``params.theta``).
    unit_aspect : float
        Height over width of a unit in the fabric (:attr:`illuknit.core.gauge.Gauge.unit_aspect`):
        the head-on chart and the side views are drawn at it, the renders foreshortened by
        ``sin(angle)`` as seen at that elevation; the input pictures keep their own proportions.

    Returns
    -------
    dict of name -> path
    """
    from illuknit.design.render import RenderParams, render_views

    check_pattern(pattern)
    check_path(outdir, "outdir")
    if targets is not None:
        for key, picture in check_mapping(targets, "targets").items():
            check_array(picture, f"targets[{key!r}]", ndim=(2, 3))
    if scale is not None:
        check_int(scale, "scale", min=1, max=64)
    if params is not None:
        check_instance(params, RenderParams, "params")
    if angle is not None:
        check_number(angle, "angle", min=0, max=90, min_open=True)
    check_number(unit_aspect, "unit_aspect", min=0.05, max=20)

    out = Path(outdir)
    s = scale or max(2, unit_scale(pattern.shape))
    theta = angle if angle is not None else (params or RenderParams()).theta
    sy, sy_angled = rows_per_unit(s, unit_aspect), rows_per_unit(s, unit_aspect, angle=theta)
    chart = chart_rgb(pattern, scale=max(s, 4), unit_aspect=unit_aspect)
    va = upscale(view_rgb(pattern, "A"), s, sy)
    vb = upscale(view_rgb(pattern, "B"), s, sy)
    renders = render_views(pattern, params=params, angle=angle)
    ra, rb = upscale(renders["A"], s, sy_angled), upscale(renders["B"], s, sy_angled)
    paths = {
        "headon": save_png(chart, out / "headon.png"),
        "view_a": save_png(va, out / "view_a.png"),
        "view_b": save_png(vb, out / "view_b.png"),
        "render_a": save_png(ra, out / "render_a.png"),
        "render_b": save_png(rb, out / "render_b.png"),
    }
    deg = f" at {theta:g} deg"
    panels: list[tuple[str, ArrayLike]] = []
    for title, img in (targets or {}).items():
        # a target on the unit grid has the grid's rows: drawn at the fabric's proportions too
        panels.append((title, upscale(np.asarray(img, dtype=np.uint8), s, sy)))
    # At 4+ pixels per unit the chart written above is already at the contact sheet's scale.
    chart_small = chart if s >= 4 else upscale(pattern.rgb(), s, sy)
    panels += [
        ("head-on (raised marked)", chart_small),
        (f"rendered from above{deg}", ra),
        (f"rendered from below{deg}", rb),
    ]
    paths["contact"] = save_png(
        contact_sheet(panels, columns=(len(panels) + 1) // 2 if len(panels) > 4 else None),
        out / "contact.png",
    )
    return paths
