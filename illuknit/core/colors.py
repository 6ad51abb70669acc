"""Yarn colours: parsing colour strings, naming colours, and perceptual colour arithmetic.

Colours are sRGB triples of uint8. Distances and averages that a person should judge are done in
CIELAB (D65) through scikit-image; physical mixing of yarns seen from afar (stripes) is averaged in
linear-light RGB, which is what the eye integrates, and converted back.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.errors import YarnSpecError

__all__ = [
    "color_name",
    "hex_color",
    "lab_from_rgb",
    "linear_from_srgb",
    "luminance",
    "mix_rgb",
    "parse_color",
    "srgb_from_linear",
]


def parse_color(text: str) -> tuple[int, int, int]:
    """Parse ``"#1b1b1b"``, ``"#fff"``, ``"rgb(1,2,3)"`` or a CSS colour name into an sRGB triple.

    Raises
    ------
    YarnSpecError
        If the string is not a colour.
    """
    from PIL import ImageColor

    s = text.strip()
    if not s:
        raise YarnSpecError("empty yarn colour string")
    try:
        rgb = ImageColor.getrgb(s)
    except ValueError:
        raise YarnSpecError(
            f"unknown yarn colour {text[:60]!r}{'...' if len(text) > 60 else ''}: use '#rrggbb', "
            "'#rgb' or a CSS colour name"
        ) from None
    return (int(rgb[0]), int(rgb[1]), int(rgb[2]))


def hex_color(rgb: Sequence[int]) -> str:
    """``(27, 27, 27) -> "#1b1b1b"``."""
    r, g, b = (int(v) for v in rgb)
    return f"#{r:02x}{g:02x}{b:02x}"


def linear_from_srgb(rgb: ArrayLike) -> NDArray[np.float64]:
    """sRGB in [0, 255] (any shape ending in 3) to linear-light RGB in [0, 1]."""
    c = np.asarray(rgb, dtype=np.float64) / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def srgb_from_linear(lin: ArrayLike) -> NDArray[np.float64]:
    """Linear-light RGB in [0, 1] to sRGB in [0, 255] (float; round it yourself)."""
    c = np.clip(np.asarray(lin, dtype=np.float64), 0.0, 1.0)
    s = np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)
    return s * 255.0


def lab_from_rgb(rgb: ArrayLike) -> NDArray[np.float64]:
    """sRGB in [0, 255] (shape (..., 3)) to CIELAB (D65)."""
    from skimage.color import rgb2lab

    arr = np.asarray(rgb, dtype=np.float64) / 255.0
    flat = arr.reshape(-1, 1, 3)
    return np.asarray(rgb2lab(flat).reshape(arr.shape))


def luminance(rgb: ArrayLike) -> NDArray[np.float64]:
    """Relative luminance Y in [0, 1] of sRGB colours (shape (..., 3))."""
    lin = linear_from_srgb(rgb)
    return np.asarray(lin @ np.array([0.2126, 0.7152, 0.0722]))


def mix_rgb(colors: ArrayLike, weights: ArrayLike) -> NDArray[np.float64]:
    """Average sRGB colours (shape (K, 3)) with weights (K,) in linear light; returns sRGB floats.

    This is how a stripe of yarns reads from a distance: light from the stripes adds up.
    """
    c = linear_from_srgb(colors)
    w = np.asarray(weights, dtype=np.float64)
    w = w / w.sum()
    return srgb_from_linear(w @ c)


@lru_cache(maxsize=1)
def _named_colors() -> tuple[tuple[str, ...], NDArray[np.float64]]:
    from PIL import ImageColor

    names = sorted(ImageColor.colormap)
    # Prefer the plain spelling of synonyms (grey/gray): keep "gray" forms only.
    names = [n for n in names if "grey" not in n]
    rgbs = np.array([ImageColor.getrgb(n)[:3] for n in names], dtype=np.float64)
    return tuple(names), lab_from_rgb(rgbs)


def color_name(rgb: Sequence[int]) -> str:
    """The nearest CSS colour name (in CIELAB) to an sRGB colour, for labels and instructions."""
    names, labs = _named_colors()
    lab = lab_from_rgb(np.asarray(rgb, dtype=np.float64)[None, :])[0]
    return names[int(np.argmin(((labs - lab) ** 2).sum(axis=1)))]
