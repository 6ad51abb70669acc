"""Image input: load a picture, resize it to the logical grid, quantise it to yarn colours.

* :func:`load_image` reads PNG, JPEG, GIF, BMP (and whatever else Pillow reads): alpha is composited
  on white, greyscale and palette images become RGB, the first frame of an animation is used.
* :func:`resize_to_units` resamples to a grid given by a width in units (or a physical width and a
  gauge), keeping the aspect ratio unless a height is given. Which grid a picture (or a pair) gets
  by default is decided by :mod:`illuknit.pictures.sizing`, the one sizing policy.
* :func:`quantise_image` maps the picture to at most ``n_colors`` colours by k-means in CIELAB
  (a perceptual space; conversions by scikit-image), then maps each colour to a yarn, either the
  user's yarns (one-to-one, nearest in CIELAB by an optimal assignment) or yarns chosen from the
  picture itself. Pictures that already have few colours are mapped exactly, with no clustering.

Image arrays are float RGB of shape (H, W, 3) in [0, 1], row 0 at the top.
"""

from __future__ import annotations

import math
import numbers
import os
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.arguments import (
    check_array,
    check_bool,
    check_int,
    check_path,
    check_seed,
    check_unit_aspect,
    got,
)
from illuknit.core.colors import color_name, hex_color, lab_from_rgb, luminance
from illuknit.core.errors import ImageInputError
from illuknit.core.pattern import MAX_UNITS, MAX_YARNS, Yarn, check_yarns
from illuknit.pictures.decode import DECODE_MAX_SIDE, MAX_PIXELS, PictureNote, read_picture

__all__ = [
    "MAX_PIXELS",
    "QuantisedImage",
    "auto_yarns",
    "check_image",
    "count_colors",
    "flat_color_count",
    "load_image",
    "quantise_image",
    "resize_to_units",
    "units_for_width",
]


def load_image(
    path: str | os.PathLike[str] | bytes, *, max_side: int | None = DECODE_MAX_SIDE
) -> NDArray[np.float64]:
    """Read a picture file as float RGB of shape (H, W, 3) in [0, 1].

    Decoding is :func:`illuknit.pictures.decode.read_picture` (16-bit, palettes, CMYK, EXIF orientation,
    the first frame of an animation; reduced while decoding to at most ``max_side`` pixels on the
    longer side). Each note about the reading is issued as a
    :class:`~illuknit.pictures.decode.PictureNote` warning.

    Raises
    ------
    ImageInputError
        Missing or unreadable file, not an image, above the pixel limit, or smaller than 2 x 2.
    """
    if not isinstance(path, bytes):
        check_path(path, "path")
    if max_side is not None:
        check_int(max_side, "max_side", min=2, max=MAX_PIXELS)
    pic = read_picture(path, max_side=max_side)
    for note in pic.notes:
        warnings.warn(f"{pic.source}: {note}", PictureNote, stacklevel=2)
    return check_image(pic.rgb, name=pic.source)


def check_image(rgb: ArrayLike, *, name: str = "image") -> NDArray[np.float64]:
    """Validate an RGB array (float in [0, 1] or uint8), returning float RGB (H, W, 3)."""
    if not isinstance(rgb, np.ndarray) or rgb.dtype.kind not in "biuf":
        check_array(rgb, name, ndim=(2, 3))  # a clear message for None, text, ragged lists
    a = np.asarray(rgb)
    if a.ndim == 2:
        a = np.repeat(a[..., None], 3, axis=2)
    if a.ndim != 3 or a.shape[2] not in (3, 4):
        raise ImageInputError(f"`{name}` must have shape (H, W, 3), got {a.shape}")
    if a.shape[2] == 4:
        alpha = a[..., 3:4].astype(np.float64) / (255.0 if a.dtype == np.uint8 else 1.0)
        base = a[..., :3].astype(np.float64) / (255.0 if a.dtype == np.uint8 else 1.0)
        a = base * alpha + (1.0 - alpha)
    elif a.dtype == np.uint8:
        a = a.astype(np.float64) / 255.0
    else:
        a = a.astype(np.float64)
    if a.shape[0] < 2 or a.shape[1] < 2:
        raise ImageInputError(
            f"{name} is {a.shape[1]} x {a.shape[0]} pixels: an illusion needs at least 2 x 2"
        )
    if not np.all(np.isfinite(a)) or a.min() < 0 or a.max() > 1:
        raise ImageInputError(f"{name}: RGB values must lie in [0, 1]")
    return a


def units_for_width(*, width_cm: float, gauge: float) -> int:
    """Units across a piece ``width_cm`` wide at ``gauge`` stitches per inch (2 stitches per unit)."""
    if not (math.isfinite(width_cm) and math.isfinite(gauge)) or width_cm <= 0 or gauge <= 0:
        raise ImageInputError(
            f"physical width and gauge must be positive finite numbers, got width_cm={width_cm}, "
            f"gauge={gauge}"
        )
    units = width_cm / 2.54 * gauge / 2
    if not units <= MAX_UNITS:  # also inf
        raise ImageInputError(
            f"`width_cm` {width_cm:g} cm at gauge {gauge:g} is {units:.3g} units, above the "
            f"{MAX_UNITS}-unit limit; ask for a narrower piece"
        )
    return max(1, round(units))


def resize_to_units(
    rgb: ArrayLike,
    *,
    width: int | None = None,
    height: int | None = None,
    unit_aspect: float = 1.0,
    smooth: bool = True,
) -> NDArray[np.float64]:
    """Resample a picture to a grid of ``height`` x ``width`` units.

    Parameters
    ----------
    rgb : ndarray of shape (H, W, 3)
    width, height : int, optional
        Grid size in units. With only one given, the other keeps the picture's aspect ratio
        (scaled by ``unit_aspect``); with neither, the picture's own size is used.
    unit_aspect : float
        Physical height / width of one unit; > 1 means units are taller than wide, so fewer rows
        are needed for the same picture height.
    smooth : bool
        Anti-aliased resampling (good for photographs); False uses nearest-neighbour (pixel art).
    """
    from skimage.transform import resize

    a = check_image(rgb, name="rgb")
    h0, w0 = a.shape[:2]
    for label, v in (("width", width), ("height", height)):
        if v is not None and not (
            isinstance(v, numbers.Integral) and not isinstance(v, bool) and 1 <= v <= MAX_UNITS
        ):
            raise ImageInputError(
                f"`{label}` must be a whole number of units between 1 and {MAX_UNITS}, got {got(v)}"
            )
    unit_aspect = check_unit_aspect(unit_aspect)
    check_bool(smooth, "smooth")
    if width is None and height is None:
        width, height = w0, max(1, round(h0 / unit_aspect))
    elif height is None:
        assert width is not None
        height = max(1, round(width * h0 / w0 / unit_aspect))
    elif width is None:
        width = max(1, round(height * w0 / h0 * unit_aspect))
    if height > MAX_UNITS or width > MAX_UNITS:
        raise ImageInputError(
            f"resized grid {width} x {height} units exceeds the {MAX_UNITS}-unit limit; ask for fewer units"
        )
    if (height, width) == (h0, w0):
        return a
    out = resize(
        a,
        (height, width),
        order=1 if smooth else 0,
        anti_aliasing=smooth and (height < h0 or width < w0),
        preserve_range=True,
        mode="edge",
    )
    return np.clip(np.asarray(out, dtype=np.float64), 0.0, 1.0)


@dataclass(frozen=True, eq=False)
class QuantisedImage:
    """A picture mapped to yarns.

    Attributes
    ----------
    indices : ndarray of shape (N, M), int
        Yarn index of each pixel, into ``yarns``.
    yarns : tuple of Yarn
        The yarns used, darkest first when chosen automatically, else in the order given.
    colors : ndarray of shape (K, 3), uint8
        The picture colour that became each yarn (cluster centre in sRGB).
    counts : ndarray of shape (K,)
        Pixels per yarn.
    """

    indices: NDArray[np.int16]
    yarns: tuple[Yarn, ...]
    colors: NDArray[np.uint8]
    counts: NDArray[np.int64] = field(default_factory=lambda: np.zeros(0, np.int64))

    def __post_init__(self) -> None:
        idx = np.asarray(self.indices)
        if idx.ndim != 2:
            raise ImageInputError(f"`indices` must be 2-D, got shape {idx.shape}")
        if idx.dtype.kind not in "biu":
            raise ImageInputError(f"`indices` must hold yarn indices, got dtype {idx.dtype}")
        k = len(check_yarns(self.yarns))
        cols = check_array(self.colors, "colors", ndim=(1, 2), integer=True)
        if cols.min() < 0 or cols.max() > 255:
            raise ImageInputError("`colors` must hold sRGB values in 0..255")
        if cols.size != 3 * k:
            raise ImageInputError(f"`colors` must have shape ({k}, 3), got {cols.shape}")
        cols = cols.astype(np.uint8).reshape(-1, 3)
        counts = np.asarray(self.counts)
        if counts.ndim != 1 or counts.dtype.kind not in "iu":  # counted again from `indices`
            raise ImageInputError(f"`counts` must be a 1-D array of counts, got {got(self.counts)}")
        if cols.shape[0] != k:
            raise ImageInputError(f"`colors` must have shape ({k}, 3), got {cols.shape}")
        if idx.size and (idx.min() < 0 or idx.max() >= k):
            raise ImageInputError(f"`indices` must lie in 0..{k - 1}")
        counts = np.bincount(idx.ravel(), minlength=k).astype(np.int64)
        idx = np.array(idx, dtype=np.int16)
        idx.setflags(write=False)
        object.__setattr__(self, "indices", idx)
        object.__setattr__(self, "colors", cols)
        object.__setattr__(self, "counts", counts)
        object.__setattr__(self, "yarns", tuple(self.yarns))

    @property
    def shape(self) -> tuple[int, int]:
        return (int(self.indices.shape[0]), int(self.indices.shape[1]))

    @property
    def palette(self) -> NDArray[np.uint8]:
        """ndarray of shape (K, 3): the yarn colours."""
        return np.array([y.rgb for y in self.yarns], dtype=np.uint8)

    def rgb(self) -> NDArray[np.uint8]:
        """The quantised picture in yarn colours, (N, M, 3) uint8."""
        return self.palette[self.indices]

    def legend(self) -> list[dict[str, Any]]:
        """Which picture colour became which yarn, with pixel counts."""
        total = max(1, int(self.counts.sum()))
        return [
            {
                "index": i,
                "image_color": hex_color(self.colors[i]),
                "yarn": y.name,
                "yarn_color": y.hex,
                "pixels": int(self.counts[i]),
                "share": round(int(self.counts[i]) / total, 4),
            }
            for i, y in enumerate(self.yarns)
        ]


def quantise_image(
    rgb: ArrayLike,
    *,
    n_colors: int | None = None,
    yarns: Sequence[Yarn] | None = None,
    allow_quantise: bool = True,
    seed: int = 0,
) -> QuantisedImage:
    """Map a picture to at most ``n_colors`` yarn colours.

    Parameters
    ----------
    rgb : ndarray of shape (N, M, 3)
        Usually already resized to the logical grid (:func:`resize_to_units`).
    n_colors : int, optional
        Number of colours to keep; defaults to ``len(yarns)`` or, without yarns, to the number of
        distinct colours if that is at most 3, else 2.
    yarns : sequence of Yarn, optional
        The yarns to map to. Each picture colour goes to a different yarn, chosen to minimise the
        total CIELAB distance; when the picture has fewer colours than yarns, only some are used.
    allow_quantise : bool
        If False, a picture with more distinct colours than ``n_colors`` is an error instead of
        being clustered.
    seed : int
        Seed of the k-means initialisation (the result is deterministic for a seed).

    Raises
    ------
    ImageInputError
        Too many colours with ``allow_quantise=False``, or ``n_colors`` out of range.
    """
    if n_colors is not None:
        check_int(n_colors, "n_colors", min=1, max=MAX_YARNS)
    if yarns is not None:
        check_yarns(yarns)
    check_seed(seed)
    check_bool(allow_quantise, "allow_quantise")
    a = check_image(rgb, name="rgb")
    h, w = a.shape[:2]
    pix8 = np.round(a.reshape(-1, 3) * 255).astype(np.uint8)
    uniq, inverse = _unique_colors(pix8)
    if yarns is not None:
        yarns = tuple(yarns)
        if not yarns:
            raise ImageInputError("`yarns` must not be empty")
    if n_colors is None:
        if yarns is not None:
            n_colors = min(len(yarns), len(uniq))
        else:
            n_colors = len(uniq) if len(uniq) <= 3 else 2
    if n_colors < 1:
        raise ImageInputError(f"`n_colors` must be at least 1, got {n_colors}")
    if yarns is not None and n_colors > len(yarns):
        raise ImageInputError(f"{n_colors} colours asked for but only {len(yarns)} yarn(s) given")
    if len(uniq) <= n_colors:
        centres = uniq.astype(np.float64)
        labels = inverse
    else:
        if not allow_quantise:
            raise ImageInputError(
                f"image has {len(uniq)} colours but only {n_colors} yarn(s), and quantising is "
                "off (`allow_quantise`): allow it or reduce the picture's colours"
            )
        centres, labels = _kmeans_lab(pix8, uniq, inverse, n_colors, seed)
    k = len(centres)
    # Order clusters dark -> light so automatic yarns and indices are predictable.
    order = np.argsort(luminance(centres), kind="stable")
    rank = np.empty(k, dtype=np.int64)
    rank[order] = np.arange(k)
    centres = centres[order]
    labels = rank[labels]
    colors8 = np.round(centres).clip(0, 255).astype(np.uint8)
    if yarns is None:
        chosen = auto_yarns(colors8)
        idx = labels
    else:
        from scipy.optimize import linear_sum_assignment

        ylab = lab_from_rgb(np.array([y.rgb for y in yarns], dtype=np.float64))
        clab = lab_from_rgb(centres)
        cost = ((clab[:, None, :] - ylab[None, :, :]) ** 2).sum(axis=2)
        rows, cols = linear_sum_assignment(cost)
        # Keep the used yarns in the order the user gave them.
        used = sorted(cols.tolist())
        remap = np.empty(k, dtype=np.int64)
        for r, c in zip(rows, cols, strict=True):
            remap[r] = used.index(int(c))
        chosen = tuple(yarns[c] for c in used)
        idx = remap[labels]
        colors8 = colors8[np.argsort(remap)]
    return QuantisedImage(idx.reshape(h, w).astype(np.int16), chosen, colors8)


def _unique_colors(pix8: NDArray[np.uint8]) -> tuple[NDArray[np.uint8], NDArray[np.intp]]:
    """Distinct colours of (P, 3) uint8 pixels and each pixel's index into them (fast 1-D unique)."""
    key = (pix8[:, 0].astype(np.int32) << 16) | (pix8[:, 1].astype(np.int32) << 8) | pix8[:, 2]
    keys, inverse = np.unique(key, return_inverse=True)
    uniq = np.stack([(keys >> 16) & 255, (keys >> 8) & 255, keys & 255], axis=1).astype(np.uint8)
    return uniq, inverse.reshape(-1)


def count_colors(rgb: ArrayLike) -> int:
    """Number of distinct 8-bit colours in an image."""
    a = check_image(rgb)
    return len(_unique_colors(np.round(a.reshape(-1, 3) * 255).astype(np.uint8))[0])


def flat_color_count(rgb8: NDArray[np.uint8], *, most: int = 8) -> int | None:
    """How many colours an 8-bit (H, W, 3) picture is drawn in when it is drawn in at most
    ``most`` flat ones; None for a photo or a drawing with soft edges. A spread sample of the
    pixels is counted first, so a photo is told without sorting every pixel
    (:func:`count_colors` counts them all)."""
    px = np.asarray(rgb8).reshape(-1, 3).astype(np.uint32)
    key = (px[:, 0] << 16) | (px[:, 1] << 8) | px[:, 2]
    seen = np.unique(key[:: max(1, key.size // 4096)])
    if seen.size > most:
        return None
    n = int(seen.size + np.unique(key[~np.isin(key, seen)]).size)
    return n if n <= most else None


def auto_yarns(colors8: NDArray[np.uint8]) -> tuple[Yarn, ...]:
    """Yarns in the given colours (K, 3) uint8, named by their nearest colour names (unique)."""
    names: list[str] = []
    for c in colors8:
        n = color_name(c)
        names.append(n if n not in names else f"{n} {names.count(n) + 1}")
    return tuple(
        Yarn(n, (int(c[0]), int(c[1]), int(c[2]))) for n, c in zip(names, colors8, strict=True)
    )


def _kmeans_lab(
    pix8: NDArray[np.uint8], uniq: NDArray[np.uint8], inverse: NDArray[np.intp], k: int, seed: int
) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    """k-means on the distinct colours (weighted by pixel count) in CIELAB; returns sRGB centres.

    Photographs have tens of thousands of distinct colours; the centres are fitted on colours
    binned to 5 bits per channel (at most 32768 bins, weighted), then every distinct colour is
    assigned to its nearest centre.
    """
    weights_u = np.bincount(inverse, minlength=len(uniq)).astype(np.float64)
    if len(uniq) > 4096:
        binned = (uniq >> 3).astype(np.int64)
        key = (binned[:, 0] << 10) | (binned[:, 1] << 5) | binned[:, 2]
        _, bin_of = np.unique(key, return_inverse=True)
        bin_of = bin_of.reshape(-1)
        fit_w: NDArray[np.float64] = np.bincount(bin_of, weights=weights_u).astype(np.float64)
        sums = np.stack([np.bincount(bin_of, weights=weights_u * uniq[:, c]) for c in range(3)], 1)
        fit_rgb: NDArray[np.float64] = sums / fit_w[:, None]
        binned_fit = True
    else:
        fit_rgb, fit_w, binned_fit = uniq.astype(np.float64), weights_u, False
    lab = lab_from_rgb(fit_rgb)
    rng = np.random.default_rng(seed)
    # k-means++ initialisation, weighted by pixel count.
    centres = [lab[rng.choice(len(lab), p=fit_w / fit_w.sum())]]
    for _ in range(1, k):
        d2 = np.min(((lab[:, None, :] - np.array(centres)[None]) ** 2).sum(-1), axis=1)
        p = d2 * fit_w
        if p.sum() <= 0:
            break
        centres.append(lab[rng.choice(len(lab), p=p / p.sum())])
    c = np.array(centres)
    for _ in range(100):
        assign = ((lab[:, None, :] - c[None]) ** 2).sum(-1).argmin(axis=1)
        tot = np.bincount(assign, weights=fit_w, minlength=len(c))
        new = np.stack(
            [np.bincount(assign, weights=fit_w * lab[:, d], minlength=len(c)) for d in range(3)], 1
        )
        new = np.where(tot[:, None] > 0, new / np.maximum(tot, 1e-12)[:, None], c)
        if np.allclose(new, c, atol=1e-6):
            break
        c = new
    lab_u = lab_from_rgb(uniq.astype(np.float64)) if binned_fit else lab
    assign = ((lab_u[:, None, :] - c[None]) ** 2).sum(-1).argmin(axis=1)
    # Drop empty clusters; centres in sRGB are the weighted mean of member colours.
    used = np.unique(assign)
    tot = np.bincount(assign, weights=weights_u, minlength=len(c))
    srgb = np.stack(
        [np.bincount(assign, weights=weights_u * uniq[:, d], minlength=len(c)) for d in range(3)], 1
    )
    srgb = srgb[used] / tot[used][:, None]
    relabel = np.full(len(c), -1)
    relabel[used] = np.arange(len(used))
    return srgb, relabel[assign][inverse]
