"""Decoding picture files into 8-bit RGB, right and within bounded memory.

:func:`read_picture` is the one place a picture file (or its bytes) is decoded:

* The pixel count is read from the header first; pictures above :data:`MAX_PIXELS` are refused
  with one line before anything is decoded (Pillow's own decompression-bomb limit is replaced by
  this check).
* 16-bit greyscale (``I;16``, ``I``) is scaled to 8 bits (a 16-bit value ``v * 257`` becomes ``v``),
  16-bit RGB is read at 8 bits, palettes with transparency and alpha channels are composited on
  white, CMYK (e.g. a CMYK JPEG) is converted to RGB, the EXIF orientation is applied, and of an
  animated picture the first frame is used.
* Large pictures are reduced *while decoding* (JPEG DCT scaling through ``draft``, then an integer
  ``reduce``; nearest-neighbour for pictures of few colours so no blend colours appear) to at most
  ``max_side`` pixels on the longer side, so no full-size float array ever exists.
* What was done to the picture (an animation's first frame, a CMYK conversion, a reduction) is
  listed in :attr:`Picture.notes`; :func:`illuknit.pictures.images.load_image` reports each note as a
  :class:`PictureNote` warning, which the command line prints as one ``note:`` line.

The result is uint8 RGB of shape (H, W, 3), row 0 at the top.
"""

from __future__ import annotations

import io
import math
import os
import warnings
from dataclasses import dataclass
from typing import IO, Any

import numpy as np
from numpy.typing import NDArray

from illuknit.core.errors import ImageInputError

__all__ = ["DECODE_MAX_SIDE", "MAX_PIXELS", "Picture", "PictureNote", "read_picture"]

#: Pictures with more pixels than this (read from the file header) are refused before decoding.
#: 100 megapixels, twice a 50-megapixel camera picture; decoding one stays well under 1 GB.
MAX_PIXELS = 100_000_000

#: Longer side, in pixels, that pictures are reduced to while decoding by default: twice the
#: largest pattern grid (:data:`illuknit.core.pattern.MAX_UNITS` units), so resampling to any grid
#: still has two pixels per unit to average over.
DECODE_MAX_SIDE = 2000

#: Pictures with at most this many colours are reduced with nearest-neighbour (no blend colours).
FEW_COLORS = 16

_ORIENTATION = 0x0112
_SIXTEEN_BIT_MODES = ("I;16", "I;16B", "I;16L", "I;16N", "I")


class PictureNote(UserWarning):
    """Something done to a picture while reading it that the user should hear about."""


@dataclass(frozen=True)
class Picture:
    """A decoded picture.

    Attributes
    ----------
    rgb : ndarray of shape (H, W, 3), uint8
        The picture in 8-bit sRGB, transparency composited on white, orientation applied.
    source : str
        The file name (or ``"picture"`` for bytes).
    original_size : tuple of int
        (rows, columns) of the picture as stored, before any reduction.
    notes : tuple of str
        What was done while reading it (first frame of an animation, a reduction, ...).
    """

    rgb: NDArray[np.uint8]
    source: str
    original_size: tuple[int, int]
    notes: tuple[str, ...] = ()


def read_picture(
    source: str | os.PathLike[str] | bytes | IO[bytes],
    *,
    max_side: int | None = DECODE_MAX_SIDE,
    name: str | None = None,
) -> Picture:
    """Decode a picture file (or its bytes) to 8-bit RGB, reduced to at most ``max_side`` pixels.

    Parameters
    ----------
    source : path, bytes or binary file
    max_side : int or None
        Reduce larger pictures while decoding so the longer side is at most this many pixels
        (integer factors, so usually a little less); None keeps the full size.
    name : str, optional
        Name used in messages (default: the file name).

    Raises
    ------
    ImageInputError
        Missing or unreadable file, not a picture, above :data:`MAX_PIXELS`, or smaller than 2 x 2.
    """
    label, fp = _open_source(source, name)
    try:
        return _read(fp, label, max_side=max_side)
    finally:
        if fp is not source and hasattr(fp, "close"):
            fp.close()


def _read(fp: Any, label: str, *, max_side: int | None) -> Picture:
    from PIL import Image, UnidentifiedImageError

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            limit, Image.MAX_IMAGE_PIXELS = Image.MAX_IMAGE_PIXELS, None
            try:
                im = Image.open(fp)
            finally:
                Image.MAX_IMAGE_PIXELS = limit
        with im:
            w, h = im.size
            if w * h > MAX_PIXELS:
                raise ImageInputError(
                    f"{label}: a picture of {w} x {h} pixels ({w * h / 1e6:.0f} megapixels) is "
                    f"above the {MAX_PIXELS / 1e6:.0f}-megapixel limit; scale it down first"
                )
            rgb, notes = _decode(im, max_side=max_side)
    except UnidentifiedImageError:
        raise ImageInputError(f"{label} is not an image Pillow can read") from None
    except (OSError, ValueError, SyntaxError, Image.DecompressionBombError) as e:
        raise ImageInputError(f"cannot read image {label}: {e}") from None
    if rgb.shape[0] < 2 or rgb.shape[1] < 2:
        raise ImageInputError(
            f"{label} is {rgb.shape[1]} x {rgb.shape[0]} pixels: an illusion needs at least 2 x 2"
        )
    return Picture(rgb=rgb, source=label, original_size=(h, w), notes=tuple(notes))


def _open_source(source: Any, name: str | None) -> tuple[str, Any]:
    if isinstance(source, (bytes, bytearray, memoryview)):
        return name or "picture", io.BytesIO(bytes(source))
    if hasattr(source, "read"):
        return name or str(getattr(source, "name", "picture")), source
    from illuknit.core.documents import open_input_file, shown_path

    # a regular file of at most INPUT_LIMITS["picture"] bytes: a pipe or /dev/zero is refused
    fp = open_input_file(source, error=ImageInputError, what="picture")
    return name or shown_path(source), fp


def _decode(im: Any, *, max_side: int | None) -> tuple[NDArray[np.uint8], list[str]]:
    notes: list[str] = []
    frames = int(getattr(im, "n_frames", 1) or 1)
    if frames > 1:
        im.seek(0)
        notes.append(f"animated picture: the first of its {frames} frames is used")
    orientation = im.getexif().get(_ORIENTATION, 1) if hasattr(im, "getexif") else 1
    w, h = im.size
    factor = 1 if max_side is None else max(1, math.ceil(max(w, h) / max_side))
    if factor > 1 and im.format == "JPEG":
        im.draft(im.mode, (math.ceil(w / factor), math.ceil(h / factor)))  # DCT scaling
    im = _to_8bit(im, notes)
    if factor > 1:
        im = _reduce(im, max_side=max_side or max(w, h))
        notes.append(f"reduced from {w} x {h} to {im.width} x {im.height} pixels while reading")
    transpose = _transpose_table().get(orientation)
    if transpose is not None:
        im = im.transpose(transpose)
    return _on_white(im), notes


def _to_8bit(im: Any, notes: list[str]) -> Any:
    """``im`` in one of L, LA, RGB, RGBA (8 bits per channel)."""
    from PIL import Image

    if im.mode in _SIXTEEN_BIT_MODES:
        a = np.asarray(im).astype(np.int64)
        top = 65535 if im.mode != "I" or a.max(initial=0) > 255 else 255
        grey = ((np.clip(a, 0, top) * 255 + top // 2) // top).astype(np.uint8)
        out = Image.fromarray(grey, "L")
        if "transparency" in im.info:  # one grey value marked transparent
            alpha = np.where(a == im.info["transparency"], 0, 255).astype(np.uint8)
            out = Image.merge("LA", (out, Image.fromarray(alpha, "L")))
        return out
    if im.mode == "F":
        return im.convert("L")
    if im.mode in ("P", "PA"):
        return im.convert("RGBA" if im.mode == "PA" or "transparency" in im.info else "RGB")
    if im.mode in ("L", "RGB") and "transparency" in im.info:
        return im.convert("LA" if im.mode == "L" else "RGBA")
    if im.mode in ("L", "LA", "RGB", "RGBA"):
        return im
    if im.mode == "CMYK":
        notes.append("CMYK picture converted to RGB")
    return im.convert("RGBA" if im.mode.endswith("A") or im.mode == "La" else "RGB")


def _reduce(im: Any, *, max_side: int) -> Any:
    from PIL import Image

    factor = max(1, math.ceil(max(im.size) / max_side))
    if factor == 1:
        return im
    size = (max(2, im.width // factor), max(2, im.height // factor))
    if im.getcolors(FEW_COLORS) is not None:  # few colours: keep them exact
        return im.resize(size, Image.Resampling.NEAREST)
    return im.reduce(factor)


def _on_white(im: Any) -> NDArray[np.uint8]:
    from PIL import Image

    if im.mode in ("LA", "RGBA"):
        im = im.convert("RGBA")
        white = Image.new("RGBA", im.size, (255, 255, 255, 255))
        im = Image.alpha_composite(white, im)
    return np.asarray(im.convert("RGB"), dtype=np.uint8)


def _transpose_table() -> dict[int, Any]:
    from PIL import Image

    t = Image.Transpose
    return {
        2: t.FLIP_LEFT_RIGHT,
        3: t.ROTATE_180,
        4: t.FLIP_TOP_BOTTOM,
        5: t.TRANSPOSE,
        6: t.ROTATE_270,
        7: t.TRANSVERSE,
        8: t.ROTATE_90,
    }
