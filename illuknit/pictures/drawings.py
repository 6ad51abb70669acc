"""Inputs drawn by code: text, simple shapes, and scikit-image's bundled pictures.

Benchmarks, demonstrations and tests need target images that are reproducible and need no network
or stored picture files. Everything here is a pure function of its arguments:

* masks (``bool`` ndarray of shape (rows, cols), ``True`` = ink): :func:`draw_text`,
  :func:`draw_heart`, :func:`draw_ecg`, :func:`draw_plus`, :func:`draw_circle`;
* pictures (``float`` RGB ndarray of shape (rows, cols, 3) in [0, 1]): :func:`skimage_image`,
  restricted to the images shipped *inside* the scikit-image wheel (``skimage.data`` downloads
  others on demand with pooch, which a benchmark must never do);
* index images (``int`` ndarray of shape (rows, cols), a colour index per unit):
  :func:`to_index_image` and :func:`layer_masks`, the form the illusion models take as targets.

Shapes are always ``(rows, cols)`` in picture order (row 0 at the top). Masks are drawn
supersampled and thresholded at half coverage, so thin strokes survive down to about 30 units.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.arguments import check_bool, check_number, check_str
from illuknit.core.errors import ImageInputError, UnknownNameError

__all__ = [
    "BUNDLED_IMAGES",
    "DRAWINGS",
    "draw_circle",
    "draw_ecg",
    "draw_heart",
    "draw_plus",
    "draw_shape",
    "draw_text",
    "layer_masks",
    "skimage_image",
    "to_index_image",
]

#: scikit-image data images that ship inside the wheel (no pooch download), name -> file name.
BUNDLED_IMAGES: dict[str, str] = {
    "astronaut": "astronaut.png",
    "brick": "brick.png",
    "camera": "camera.png",
    "cell": "cell.png",
    "chelsea": "chelsea.png",
    "coffee": "coffee.png",
    "coins": "coins.png",
    "grass": "grass.png",
    "gravel": "gravel.png",
    "horse": "horse.png",
    "hubble_deep_field": "hubble_deep_field.jpg",
    "ihc": "ihc.png",
    "logo": "logo.png",
    "microaneurysms": "microaneurysms.png",
    "moon": "moon.png",
    "page": "page.png",
    "phantom": "phantom.png",
    "retina": "retina.jpg",
    "rocket": "rocket.jpg",
    "text": "text.png",
}

#: Supersampling factor for drawn masks: shapes are drawn this much larger, then box-averaged.
_SUPERSAMPLE = 8


def _check_shape(shape: Sequence[int], *, minimum: int = 2) -> tuple[int, int]:
    try:
        rows, cols = (int(v) for v in shape)
    except (TypeError, ValueError):
        raise ImageInputError(f"`shape` must be (rows, cols), got {shape!r}") from None
    if rows < minimum or cols < minimum or rows > 4000 or cols > 4000:
        raise ImageInputError(
            f"`shape` must be (rows, cols) with both in {minimum}..4000, got {(rows, cols)}"
        )
    return rows, cols


def _downsample(big: NDArray[np.floating], shape: tuple[int, int]) -> NDArray[np.bool_]:
    """Box-average a supersampled coverage image to ``shape`` and keep cells at least half inked."""
    rows, cols = shape
    s = big.shape[0] // rows
    cover = big[: rows * s, : cols * s].reshape(rows, s, cols, s).mean(axis=(1, 3))
    return cover >= 0.5


def _grid(shape: tuple[int, int]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Supersampled sample centres: x in [-1, 1] left to right, y in [-1, 1] bottom to top."""
    rows, cols = shape
    s = _SUPERSAMPLE
    y = 1.0 - (np.arange(rows * s) + 0.5) / (rows * s) * 2.0
    x = (np.arange(cols * s) + 0.5) / (cols * s) * 2.0 - 1.0
    return np.meshgrid(x, y)


def draw_text(
    text: str,
    *,
    shape: Sequence[int] = (30, 120),
    margin: float = 0.08,
    keep_aspect: bool = False,
    weight: float = 0.04,
) -> NDArray[np.bool_]:
    """Render ``text`` with Pillow's bundled default font, scaled to fill ``shape``, centred.

    Parameters
    ----------
    text : str
        The text; ``"\\n"`` separates lines.
    shape : (rows, cols)
        Output size in units.
    margin : float
        Blank border on every side, as a fraction of the size (0 <= margin < 0.5).
    keep_aspect : bool
        Keep the glyphs' aspect ratio (centred, possibly leaving blank space); by default the text
        is stretched to fill the box inside the margin, which keeps letters legible in the wide,
        short or square grids knitting uses.
    weight : float
        Stroke thickening, as a fraction of the font size (knitted letters read better bold).

    Returns
    -------
    ndarray of bool, shape (rows, cols)
        ``True`` where there is ink.

    Examples
    --------
    >>> m = draw_text("HI", shape=(10, 12))
    >>> m.shape, bool(m.any()), bool(m.all())
    ((10, 12), True, False)
    """
    check_str(text, "text")
    margin = check_number(margin, "margin", min=0, max=0.49, error=ImageInputError)
    check_bool(keep_aspect, "keep_aspect")
    weight = check_number(weight, "weight", min=0, max=1, error=ImageInputError)
    from PIL import Image, ImageDraw, ImageFont

    rows, cols = _check_shape(shape, minimum=3)
    if not isinstance(text, str) or not text.strip():
        raise ImageInputError("`text` must be a non-empty string")
    if not 0.0 <= margin < 0.5:
        raise ImageInputError(f"`margin` must be in [0, 0.5), got {margin}")
    if not 0.0 <= weight <= 0.3:
        raise ImageInputError(f"`weight` must be in [0, 0.3], got {weight}")
    size = 96
    font = ImageFont.load_default(size=size)
    stroke = round(weight * size)
    probe = ImageDraw.Draw(Image.new("L", (1, 1)))
    box = probe.multiline_textbbox((0, 0), text, font=font, stroke_width=stroke, align="center")
    w, h = int(box[2] - box[0]), int(box[3] - box[1])
    canvas = Image.new("L", (w + 4, h + 4), 0)
    ImageDraw.Draw(canvas).multiline_text(
        (2 - box[0], 2 - box[1]),
        text,
        fill=255,
        font=font,
        stroke_width=stroke,
        stroke_fill=255,
        align="center",
    )
    ink = np.asarray(canvas) > 127
    ys, xs = np.nonzero(ink)
    glyphs = canvas.crop((xs.min(), ys.min(), xs.max() + 1, ys.max() + 1))

    s = _SUPERSAMPLE
    inner_r = max(1, round(rows * s * (1 - 2 * margin)))
    inner_c = max(1, round(cols * s * (1 - 2 * margin)))
    if keep_aspect:
        scale = min(inner_r / glyphs.height, inner_c / glyphs.width)
        inner_r = max(1, round(glyphs.height * scale))
        inner_c = max(1, round(glyphs.width * scale))
    scaled = glyphs.resize((inner_c, inner_r), Image.Resampling.BILINEAR)
    big = np.zeros((rows * s, cols * s))
    r0 = (rows * s - inner_r) // 2
    c0 = (cols * s - inner_c) // 2
    big[r0 : r0 + inner_r, c0 : c0 + inner_c] = np.asarray(scaled, dtype=float) / 255.0
    return _downsample(big, (rows, cols))


def draw_heart(shape: Sequence[int], *, margin: float = 0.06) -> NDArray[np.bool_]:
    """A heart filling ``shape`` (inside the implicit curve (x²+y²-1)³ - x²y³ <= 0).

    Returns
    -------
    ndarray of bool, shape (rows, cols)
    """
    rows, cols = _check_shape(shape)
    x, y = _grid((rows, cols))
    # The curve spans x in [-1.14, 1.14], y in [-1, 1.24]; map the unit box onto it.
    k = 1.0 - 2 * margin
    hx = x * 1.14 / k
    hy = (y / k) * 1.12 + 0.12
    inside = (hx**2 + hy**2 - 1.0) ** 3 - hx**2 * hy**3 <= 0.0
    return _downsample(inside.astype(float), (rows, cols))


# One heartbeat of a stylised ECG (P wave, QRS complex, T wave): (time in [0, 1], level in [-1, 1]).
_ECG_BEAT = (
    (0.00, 0.0), (0.10, 0.0), (0.14, 0.18), (0.18, 0.22), (0.22, 0.0), (0.30, 0.0),
    (0.33, -0.25), (0.38, 1.0), (0.43, -0.6), (0.47, 0.0), (0.58, 0.0), (0.64, 0.3),
    (0.70, 0.35), (0.76, 0.0), (1.00, 0.0),
)  # fmt: skip


def draw_ecg(
    shape: Sequence[int], *, beats: int = 2, thickness: float | None = None, margin: float = 0.08
) -> NDArray[np.bool_]:
    """An ECG pulse line across ``shape``: ``beats`` heartbeats on a flat baseline.

    Parameters
    ----------
    shape : (rows, cols)
    beats : int
        Number of heartbeats drawn left to right.
    thickness : float, optional
        Line width in units; default ``max(2, rows / 10)``, thick enough to read when knitted.
    margin : float
        Blank border, fraction of the size.

    Returns
    -------
    ndarray of bool, shape (rows, cols)
    """
    from PIL import Image, ImageDraw

    rows, cols = _check_shape(shape, minimum=4)
    if beats < 1:
        raise ImageInputError(f"`beats` must be >= 1, got {beats}")
    width = max(2.0, rows / 10) if thickness is None else float(thickness)
    if width <= 0:
        raise ImageInputError(f"`thickness` must be positive, got {thickness}")
    s = _SUPERSAMPLE
    W, H = cols * s, rows * s
    pad_x = margin * W
    pad_y = margin * H + width * s / 2
    points = []
    for b in range(beats):
        for t, level in _ECG_BEAT:
            u = (b + t) / beats
            x = pad_x + u * (W - 2 * pad_x)
            # baseline a little below the middle, so the tall R peak fits
            y = H * 0.62 - level * (H * 0.62 - pad_y)
            y = min(max(y, pad_y), H - pad_y)
            points.append((x, y))
    img = Image.new("L", (W, H), 0)
    ImageDraw.Draw(img).line(points, fill=255, width=max(1, round(width * s)), joint="curve")
    return _downsample(np.asarray(img, dtype=float) / 255.0, (rows, cols))


def draw_plus(
    shape: Sequence[int], *, arm: float = 1 / 3, margin: float = 0.1
) -> NDArray[np.bool_]:
    """A plus sign (Greek cross) centred in ``shape``; ``arm`` is the bar width as a fraction.

    Returns
    -------
    ndarray of bool, shape (rows, cols)
    """
    rows, cols = _check_shape(shape)
    if not 0.0 < arm < 1.0:
        raise ImageInputError(f"`arm` must be in (0, 1), got {arm}")
    if not 0.0 <= margin < 0.5:
        raise ImageInputError(f"`margin` must be in [0, 0.5), got {margin}")
    # Drawn on whole units (not supersampled) so the bars have crisp, symmetric edges.
    out = np.zeros((rows, cols), dtype=bool)
    spans = []
    for n in (rows, cols):
        pad = round(margin * n)
        inner = n - 2 * pad
        bar = max(1, round(arm * inner))
        if (inner - bar) % 2:  # keep the bar centred on whole units
            bar += 1 if bar < inner else -1
        start = pad + (inner - bar) // 2
        spans.append((pad, n - pad, start, start + bar))
    (r0, r1, br0, br1), (c0, c1, bc0, bc1) = spans
    out[br0:br1, c0:c1] = True
    out[r0:r1, bc0:bc1] = True
    return out


def draw_circle(
    shape: Sequence[int],
    *,
    radius: float = 0.4,
    center: tuple[float, float] = (0.5, 0.5),
    ring: float | None = None,
) -> NDArray[np.bool_]:
    """A disc (or a ring of width ``ring``) in ``shape``.

    Parameters
    ----------
    shape : (rows, cols)
    radius : float
        Radius as a fraction of ``min(rows, cols)``.
    center : (row, col)
        Centre as fractions of (rows, cols).
    ring : float, optional
        Ring width as a fraction of ``min(rows, cols)``; a filled disc when omitted.

    Returns
    -------
    ndarray of bool, shape (rows, cols)
    """
    rows, cols = _check_shape(shape)
    if radius <= 0:
        raise ImageInputError(f"`radius` must be positive, got {radius}")
    s = _SUPERSAMPLE
    rr = (np.arange(rows * s) + 0.5) / s
    cc = (np.arange(cols * s) + 0.5) / s
    dr = rr[:, None] - center[0] * rows
    dc = cc[None, :] - center[1] * cols
    d = np.hypot(dr, dc) / min(rows, cols)
    inside = d <= radius
    if ring is not None:
        if ring <= 0:
            raise ImageInputError(f"`ring` must be positive, got {ring}")
        inside &= d >= radius - ring
    return _downsample(inside.astype(float), (rows, cols))


#: Drawn shapes by name (each takes ``shape`` and returns a mask), for manifests and CLIs.
DRAWINGS: dict[str, Callable[[Sequence[int]], NDArray[np.bool_]]] = {
    "heart": draw_heart,
    "ecg": draw_ecg,
    "plus": draw_plus,
    "circle": draw_circle,
}


def draw_shape(name: str, shape: Sequence[int]) -> NDArray[np.bool_]:
    """The drawn shape ``name`` (one of :data:`DRAWINGS`) at ``shape``."""
    fn = DRAWINGS.get(check_str(name, "name"))
    if fn is None:
        raise UnknownNameError("drawing", name, sorted(DRAWINGS))
    return fn(shape)


def skimage_image(
    name: str, shape: Sequence[int] | None = None, *, crop: bool = True
) -> NDArray[np.float64]:
    """One of scikit-image's bundled data pictures, as float RGB resized to ``shape``.

    Only images that ship inside the scikit-image wheel are allowed (:data:`BUNDLED_IMAGES`), read
    straight from the package folder, so nothing is ever downloaded.

    Parameters
    ----------
    name : str
        E.g. ``"astronaut"``, ``"coffee"``, ``"chelsea"``, ``"camera"``.
    shape : (rows, cols), optional
        Output size; the native size when omitted.
    crop : bool
        Centre-crop to the aspect ratio of ``shape`` before resizing (no distortion); otherwise
        the picture is stretched.

    Returns
    -------
    ndarray of float64, shape (rows, cols, 3)
        sRGB in [0, 1]; greyscale pictures are repeated over the three channels, alpha is
        composited on white. Resampled smoothly by :func:`illuknit.pictures.sizing.size_picture`.
    """
    import skimage.data

    from illuknit.pictures.images import load_image
    from illuknit.pictures.sizing import size_picture

    check_bool(crop, "crop")
    file = BUNDLED_IMAGES.get(check_str(name, "name"))
    if file is None:
        raise UnknownNameError("scikit-image bundled image", name, sorted(BUNDLED_IMAGES))
    path = Path(skimage.data.__file__).parent / file
    if not path.is_file():
        raise ImageInputError(
            f"scikit-image image {name!r} is not bundled in this install ({path})"
        )
    rgb = load_image(path)
    if shape is None:
        return rgb
    rows, cols = _check_shape(shape)
    if crop:
        h, w = rgb.shape[:2]
        target = cols / rows
        if w / h > target:
            nw = max(1, round(h * target))
            x0 = (w - nw) // 2
            rgb = rgb[:, x0 : x0 + nw]
        else:
            nh = max(1, round(w / target))
            y0 = (h - nh) // 2
            rgb = rgb[y0 : y0 + nh]
    return size_picture(rgb, width=cols, height=rows, smooth=True)


def to_index_image(
    mask: ArrayLike, *, ink: int = 0, paper: int = 1, invert: bool = False
) -> NDArray[np.int16]:
    """A two-colour index image from a mask: ``ink`` where ``mask`` is True, else ``paper``.

    Parameters
    ----------
    mask : array_like of bool, shape (N, M)
    ink, paper : int
        Colour indices (e.g. yarn indices: 0 dark ink on 1 light paper by default).
    invert : bool
        Swap ink and paper.

    Returns
    -------
    ndarray of int16, shape (N, M)
    """
    m = np.asarray(mask, dtype=bool)
    if m.ndim != 2:
        raise ImageInputError(f"`mask` must be 2-D, got shape {m.shape}")
    if invert:
        ink, paper = paper, ink
    return np.where(m, np.int16(ink), np.int16(paper)).astype(np.int16)


def layer_masks(
    masks: Sequence[ArrayLike], *, background: int = 0, indices: Sequence[int] | None = None
) -> NDArray[np.int16]:
    """Paint masks over each other into one index image (later masks on top).

    Parameters
    ----------
    masks : sequence of array_like of bool, each shape (N, M)
    background : int
        Index where no mask is set.
    indices : sequence of int, optional
        Index painted by each mask; ``1, 2, ...`` (after ``background=0``) when omitted.

    Returns
    -------
    ndarray of int16, shape (N, M)

    Examples
    --------
    >>> layer_masks([[[True, False]], [[True, True]]], indices=[5, 7]).tolist()
    [[7, 7]]
    """
    arrays = [np.asarray(m, dtype=bool) for m in masks]
    if not arrays:
        raise ImageInputError("`masks` must hold at least one mask")
    shape = arrays[0].shape
    if len(shape) != 2 or any(a.shape != shape for a in arrays):
        raise ImageInputError(f"`masks` must be 2-D of one shape, got {[a.shape for a in arrays]}")
    if indices is None:
        indices = [background + 1 + i for i in range(len(arrays))]
    if len(indices) != len(arrays):
        raise ImageInputError(f"`indices` must have {len(arrays)} entries, got {len(indices)}")
    out = np.full(shape, background, dtype=np.int16)
    for a, k in zip(arrays, indices, strict=True):
        out[a] = k
    return out
