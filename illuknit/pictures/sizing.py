"""Pair sizing: one or two pictures in, unit grids of one size out.

The one stage that decides how big a design is, used by ``illuknit single``, ``double``,
``headon`` and ``solve``, by the benchmark's picture inputs and by the design app, so the same
pictures give the same grid everywhere. The policy:

1. **Width.** An explicit width in units wins; else a physical width (``width_cm`` at ``gauge``
   stitches per inch, :func:`~illuknit.pictures.images.units_for_width`); else an explicit ``height`` alone
   sets the grid (width from the aspect ratio); else the picture's own width in pixels, at most
   :data:`DEFAULT_MAX_WIDTH` units. A width outside 1..``MAX_UNITS`` is an
   :class:`~illuknit.core.errors.ImageInputError`.
2. **Height** follows picture A's aspect ratio *as knitted* unless ``height`` is given: a unit is
   2 stitches x 2 rows, ``unit_aspect`` (its height over its width, the gauge's
   :attr:`~illuknit.core.gauge.Gauge.unit_aspect`; default 0.7, stocking stitch's 5 : 7) times as
   tall as wide, so the grid gets ``1 / unit_aspect`` times the rows a square grid would and
   the finished piece has the picture's proportions. ``unit_aspect=1`` gives square units
   (``--square-units``): as many rows as the picture is tall, a piece 0.7 as tall.
3. **Picture B** is fitted onto A's grid. It is accepted when it covers the same piece: its grid at
   A's width has A's height, or its aspect ratio (height / width) is within
   :data:`ASPECT_TOLERANCE` of A's. Otherwise the pictures do not match: a
   :class:`~illuknit.core.errors.PictureSizeMismatchError`, unless ``stretch`` is set, which stretches
   B onto A's grid and says so in :attr:`SizedPair.notes`.
4. **Resampling.** Pictures with more than :data:`SMOOTH_ABOVE_COLORS` distinct colours
   (photographs) are resampled with anti-aliasing; fewer (pixel art, charts) with
   nearest-neighbour so no blend colours appear; ``smooth`` overrides both.

>>> import numpy as np
>>> pair = size_pair(np.zeros((300, 600, 3)), np.ones((150, 300, 3)))
>>> pair.shape
(71, 100)
>>> size_pair(np.zeros((300, 600, 3)), unit_aspect=1.0).shape
(50, 100)
"""

from __future__ import annotations

import numbers
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.arguments import check_int, check_unit_aspect, got, with_knobs
from illuknit.core.errors import ImageInputError, PictureSizeMismatchError
from illuknit.core.gauge import STOCKINETTE_COURSE_ASPECT
from illuknit.core.pattern import MAX_UNITS, Yarn
from illuknit.pictures.images import (
    QuantisedImage,
    check_image,
    count_colors,
    load_image,
    quantise_image,
    resize_to_units,
    units_for_width,
)

__all__ = [
    "ASPECT_TOLERANCE",
    "DEFAULT_MAX_WIDTH",
    "SMOOTH_ABOVE_COLORS",
    "GridSize",
    "SizedPair",
    "grid_picture",
    "grid_size",
    "grid_width",
    "prepare_image",
    "size_pair",
    "size_picture",
]

#: Default grid width: the picture's own width in pixels, at most this many units.
DEFAULT_MAX_WIDTH = 100
#: Largest relative difference of aspect ratios (height / width) for which B covers A's piece.
ASPECT_TOLERANCE = 0.02
#: Pictures with more distinct colours than this are resampled smoothly (photographs).
SMOOTH_ABOVE_COLORS = 16


@dataclass(frozen=True, eq=False)
class SizedPair:
    """Pictures resampled to one unit grid.

    Attributes
    ----------
    a : ndarray of float64, shape (N, M, 3)
        Picture A on the grid (sRGB in [0, 1]).
    b : ndarray of float64, shape (N, M, 3), or None
        Picture B on the same grid, or None for a single picture.
    stretched : bool
        B did not cover A's piece and was stretched onto A's grid (``stretch=True``).
    notes : tuple of str
        What the sizing did that the user should hear about.
    """

    a: NDArray[np.float64]
    b: NDArray[np.float64] | None
    stretched: bool = False
    notes: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.b is not None and self.b.shape != self.a.shape:
            raise ImageInputError(f"sized pictures differ: {self.a.shape} and {self.b.shape}")

    @property
    def shape(self) -> tuple[int, int]:
        """(N, M): rows and columns of units."""
        return (int(self.a.shape[0]), int(self.a.shape[1]))


def grid_width(
    picture_width: int,
    *,
    width: int | None = None,
    width_cm: float | None = None,
    gauge: float | None = None,
    height: int | None = None,
) -> int | None:
    """The grid width in units under the policy (None: let an explicit ``height`` decide).

    Parameters
    ----------
    picture_width : int
        Width of picture A in pixels.
    width : int, optional
        Width in units; wins over everything else.
    width_cm, gauge : float, optional
        Physical width in cm at ``gauge`` stitches per inch (default 7).
    height : int, optional
        Height in units; with no width given, the width follows from the aspect ratio.
    """
    if width is not None and width_cm is not None:
        raise ImageInputError("give either a width in units or a physical width, not both")
    if width_cm is not None:
        width = units_for_width(width_cm=width_cm, gauge=gauge if gauge is not None else 7.0)
    if width is None:
        if height is not None:
            return None
        width = min(int(picture_width), DEFAULT_MAX_WIDTH)
    if not 1 <= width <= MAX_UNITS:
        raise ImageInputError(f"`width` must be between 1 and {MAX_UNITS} units, got {width}")
    return int(width)


def _smooth(rgb: NDArray[np.float64], smooth: bool | None) -> bool:
    return count_colors(rgb) > SMOOTH_ABOVE_COLORS if smooth is None else smooth


def _picture(source: str | os.PathLike[str] | ArrayLike) -> NDArray[np.float64]:
    if isinstance(source, (str, os.PathLike)):
        return load_image(source)
    return check_image(source)


@dataclass(frozen=True)
class GridSize:
    """How big the unit grid is asked to be (step 1 and 2 of the module's policy).

    Parameters
    ----------
    width, height : int, optional
        Width and height in units (1 to ``MAX_UNITS``); see :func:`grid_width`.
    width_cm, gauge : float, optional
        Physical width in cm at ``gauge`` stitches per inch (default 7), instead of ``width``.
    unit_aspect : float
        Height over width of one unit as knitted (:attr:`illuknit.core.gauge.Gauge.unit_aspect`);
        1.0 for square units.
    """

    width: int | None = None
    height: int | None = None
    width_cm: float | None = None
    gauge: float | None = None
    unit_aspect: float = STOCKINETTE_COURSE_ASPECT

    def __post_init__(self) -> None:
        for label in ("width", "height"):
            if getattr(self, label) is not None:
                check_int(getattr(self, label), label, min=1, max=MAX_UNITS, error=ImageInputError)
        for label in ("width_cm", "gauge"):
            v = getattr(self, label)
            if v is not None and (isinstance(v, bool) or not isinstance(v, numbers.Real)):
                raise ImageInputError(f"`{label}` must be a number, got {got(v)}")
        check_unit_aspect(self.unit_aspect)


def grid_size(size: GridSize | None, knobs: dict[str, Any]) -> GridSize:
    """``size`` (default ``GridSize()``) with the shorthand ``knobs`` in place of its fields
    (:func:`~illuknit.core.arguments.with_knobs`)."""
    return with_knobs(GridSize, size, knobs, name="size", what="grid size")


def _name(source: object, default: str) -> str:
    return os.path.basename(source) if isinstance(source, (str, os.PathLike)) else default


def size_picture(
    picture: str | os.PathLike[str] | ArrayLike,
    *,
    width: int | None = None,
    height: int | None = None,
    width_cm: float | None = None,
    gauge: float | None = None,
    smooth: bool | None = None,
    unit_aspect: float = STOCKINETTE_COURSE_ASPECT,
) -> NDArray[np.float64]:
    """One picture on its unit grid (:func:`size_pair` without a picture B)."""
    return size_pair(
        picture,
        None,
        width=width,
        height=height,
        width_cm=width_cm,
        gauge=gauge,
        smooth=smooth,
        unit_aspect=unit_aspect,
    ).a


def size_pair(
    a: str | os.PathLike[str] | ArrayLike,
    b: str | os.PathLike[str] | ArrayLike | None = None,
    *,
    size: GridSize | None = None,
    stretch: bool = False,
    smooth: bool | None = None,
    names: tuple[str, str] = ("A", "B"),
    **knobs: Any,
) -> SizedPair:
    """Resample picture A (and B) to one unit grid under the module's policy.

    Parameters
    ----------
    a, b : path or array_like of shape (H, W, 3)
        The pictures: files (read by :func:`~illuknit.pictures.images.load_image`, and named by their
        file names in messages) or sRGB arrays (uint8 or floats in [0, 1]); ``b`` may be None.
    size : GridSize, optional
        The grid size asked for (``width``, ``height``, ``width_cm``, ``gauge``,
        ``unit_aspect``; see :func:`grid_width`); defaults: ``GridSize()``.
    stretch : bool
        Stretch a B that does not cover A's piece onto A's grid instead of raising.
    smooth : bool, optional
        Force smooth (True) or nearest-neighbour (False) resampling for both pictures.
    names : (str, str)
        How error messages and notes name array pictures (files are named by their file names).
    **knobs
        Shorthand for fields of ``size`` (``size_pair(a, width=40)`` is
        ``size_pair(a, size=GridSize(width=40))``); they replace those fields of ``size``.

    Raises
    ------
    PictureSizeMismatchError
        B's aspect ratio differs from A's (and ``stretch`` is off).
    ImageInputError
        A width or height out of range, or a picture that is not an image.
    """
    grid = grid_size(size, knobs)
    height, unit_aspect = grid.height, grid.unit_aspect
    names = (_name(a, names[0]), _name(b, names[1]))
    ra = _picture(a)
    w = grid_width(
        ra.shape[1], width=grid.width, width_cm=grid.width_cm, gauge=grid.gauge, height=height
    )
    sized_a = resize_to_units(
        ra, width=w, height=height, smooth=_smooth(ra, smooth), unit_aspect=unit_aspect
    )
    if b is None:
        return SizedPair(sized_a, None)
    rb = _picture(b)
    n, m = sized_a.shape[:2]
    # B covers A's piece when it lands on A's grid at A's width, or its aspect is close enough.
    own_height = max(1, round(m * rb.shape[0] / rb.shape[1] / unit_aspect))
    aspect_a, aspect_b = ra.shape[0] / ra.shape[1], rb.shape[0] / rb.shape[1]
    fits = own_height == n or abs(aspect_b - aspect_a) <= ASPECT_TOLERANCE * aspect_a
    notes: tuple[str, ...] = ()
    if not fits:
        if not stretch:
            raise PictureSizeMismatchError(
                f"the pictures have different sizes: {names[0]} is {ra.shape[1]} x {ra.shape[0]} "
                f"pixels ({m} x {n} units), {names[1]} is {rb.shape[1]} x {rb.shape[0]} pixels "
                f"({m} x {own_height} units at that width); give pictures of one aspect ratio "
                "or stretch the second onto the first (--resize)",
                a_pixels=(int(ra.shape[0]), int(ra.shape[1])),
                b_pixels=(int(rb.shape[0]), int(rb.shape[1])),
            )
        notes = (
            f"picture {names[1]} stretched from {rb.shape[1]} x {rb.shape[0]} pixels to the "
            f"shape of {names[0]}",
        )
    sized_b = resize_to_units(rb, width=m, height=n, smooth=_smooth(rb, smooth))
    return SizedPair(sized_a, sized_b, stretched=not fits, notes=notes)


def grid_picture(rgb: ArrayLike, *, unit_aspect: float, scale: int = 8) -> NDArray[np.uint8]:
    """A picture in the fabric's proportions whose sizing at its grid's width gives the grid back.

    For a picture already on a unit grid of ``(N, M)`` (an accepted edit of a sized picture), so
    that sizing it again, at ``M`` units and ``unit_aspect``, keeps its rows instead of
    stretching it once more: each unit becomes ``scale`` pixels across and ``scale *
    unit_aspect`` down (nearest-neighbour sizing samples every unit's middle).
    """
    a = np.asarray(rgb)
    if a.dtype != np.uint8:
        a = np.round(np.clip(a, 0, 1) * 255).astype(np.uint8)
    rows = max(1, round(a.shape[0] * scale * unit_aspect))
    return np.repeat(a, scale, axis=1)[(np.arange(rows) * a.shape[0]) // rows]


def prepare_image(
    source: str | os.PathLike[str] | ArrayLike,
    *,
    size: GridSize | None = None,
    n_colors: int | None = None,
    yarns: Sequence[Yarn] | None = None,
    allow_quantise: bool = True,
    smooth: bool | None = None,
    **knobs: Any,
) -> QuantisedImage:
    """Load (if a path), size (:func:`size_pair`: ``size`` or its fields as keywords, and
    ``smooth``) and quantise one picture in one call."""
    small = size_pair(source, None, size=grid_size(size, knobs), smooth=smooth).a
    return quantise_image(small, n_colors=n_colors, yarns=yarns, allow_quantise=allow_quantise)
