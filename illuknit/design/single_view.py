"""The push-button single-view compiler (paper section 5, Fig. 7).

Input: a picture mapped to 2 or 3 yarns. Output: a :class:`LogicalPattern` whose side views show
the picture while head-on it is a plain stripe.

Rows alternate stripe colours ``c1, c2, c1, ...`` (row 0 is ``c1``; every unit of a row has the
row's yarn). A unit is raised where the picture has the row's own colour, and flat elsewhere:

* 2 colours: a ``c1`` pixel in a ``c1`` row is a ``c1`` bump, a ``c2`` pixel in a ``c1`` row a
  ``c1`` flat (and symmetrically). Seen from above (view A), a flat lets the next row's colour
  through and a bump shows its own, so ``VA[i] = picture[i-1]`` for every ``i >= 1``; from below
  ``VB[i] = picture[i+1]`` for ``i <= N-2``. The picture appears **shifted by one row** toward the
  viewer's far edge; the boundary rows ``VA[0]`` and ``VB[N-1]`` show the stripe colour.
* 3 colours: the middle colour (by brightness) is raised in every row, so a middle-colour region is
  seen as alternating ``c1``/``c2`` stripes, which read as the mix (the paper's "two adjacent bump
  rows"). Tolerance: pixels of the outer colours are exact (shifted as above); a middle pixel is
  seen as the stripe colour of its own row, so over any two vertically adjacent middle pixels the
  view is exactly half ``c1`` and half ``c2``.

By default ``c1`` is the darkest yarn, so the top stripe is dark.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from illuknit.core.arguments import check_array, check_choice
from illuknit.core.colors import luminance
from illuknit.core.errors import ImageInputError
from illuknit.core.pattern import LogicalPattern, Yarn
from illuknit.pictures.images import QuantisedImage, check_image, count_colors, load_image

__all__ = [
    "compile_single_view",
    "prepare_single_view_image",
    "single_view_errors",
    "single_view_roles",
]


def single_view_roles(
    yarns: tuple[Yarn, ...], *, first: Literal["dark", "light"] = "dark"
) -> tuple[int, int, int | None]:
    """(c1, c2, middle) yarn indices: c1 is the first stripe colour; middle only with 3 yarns."""
    k = len(yarns)
    if k not in (2, 3):
        raise ImageInputError(
            f"a single-view illusion needs a 2- or 3-colour picture, got {k} colour(s)"
        )
    if first not in ("dark", "light"):
        raise ImageInputError(f"`first` must be 'dark' or 'light', got {first!r}")
    lum = luminance(np.array([y.rgb for y in yarns], dtype=np.float64))
    order = [int(i) for i in np.argsort(lum, kind="stable")]
    dark, light = order[0], order[-1]
    middle = order[1] if k == 3 else None
    return (dark, light, middle) if first == "dark" else (light, dark, middle)


def compile_single_view(
    image: QuantisedImage | ArrayLike,
    *,
    yarns: tuple[Yarn, ...] | None = None,
    first: Literal["dark", "light"] = "dark",
) -> LogicalPattern:
    """Compile a 2- or 3-colour picture into a single-view illusion pattern.

    Parameters
    ----------
    image : QuantisedImage or ndarray of shape (N, M)
        The picture as yarn indices (from :func:`illuknit.pictures.images.quantise_image`), or a raw index
        array together with ``yarns``.
    yarns : tuple of Yarn, optional
        Required with a raw index array; ignored for a QuantisedImage.
    first : {"dark", "light"}
        Colour of the top stripe row (``c1``).

    Returns
    -------
    LogicalPattern
        Same N x M size as the picture, knitted with the two stripe yarns only (a middle colour
        is an impression, not a yarn); ``meta`` records the roles and the one-row shift.

    Examples
    --------
    >>> from illuknit.core.pattern import parse_yarns
    >>> pic = np.array([[0, 1], [1, 0], [0, 0]])
    >>> p = compile_single_view(pic, yarns=parse_yarns("black,white"))
    >>> p.yarn.tolist(), p.raised.astype(int).tolist()
    ([[0, 0], [1, 1], [0, 0]], [[1, 0], [1, 0], [1, 1]])
    """
    check_choice(first, "first", ("dark", "light"), error=ImageInputError)
    if isinstance(image, QuantisedImage):
        if yarns is not None:
            raise ImageInputError(
                "pass `yarns` only with an index array: a QuantisedImage has them"
            )
        idx, yarns = np.asarray(image.indices), image.yarns
    else:
        check_array(
            image,
            "image",
            ndim=2,
            integer=True,
            what="a QuantisedImage or a 2-D array of yarn indices",
        )
        if yarns is None:
            raise ImageInputError("`yarns` is required when `image` is an index array")
        idx = np.asarray(image)
        yarns = tuple(yarns)
        if idx.ndim != 2 or not np.issubdtype(idx.dtype, np.integer):
            raise ImageInputError(
                f"`image` must be a 2-D integer array, got {idx.dtype} {idx.shape}"
            )
        if idx.size and (idx.min() < 0 or idx.max() >= len(yarns)):
            raise ImageInputError(f"picture indices must lie in 0..{len(yarns) - 1}")
    if idx.shape[0] < 2 or idx.shape[1] < 1:
        raise ImageInputError(f"picture of shape {idx.shape} is too small: need at least 2 rows")
    c1, c2, middle = single_view_roles(yarns, first=first)
    n = idx.shape[0]
    row_yarn = np.where(np.arange(n) % 2 == 0, c1, c2)[:, None]
    yarn = np.broadcast_to(row_yarn, idx.shape)
    raised = idx == row_yarn
    if middle is not None:
        raised = raised | (idx == middle)
    # The middle colour is an impression made of the two stripe yarns; it is never knitted, so the
    # pattern's palette holds only c1 and c2 (in their original order).
    used = sorted((c1, c2))
    remap = np.zeros(len(yarns), dtype=np.int16)
    remap[used[0]], remap[used[1]] = 0, 1
    meta = {
        "compiler": "single-view",
        "c1": yarns[c1].name,
        "c2": yarns[c2].name,
        "middle": None if middle is None else yarns[middle].name,
        "view_shift": "view A shows picture row i-1 at row i; view B shows picture row i+1 at row i",
    }
    return LogicalPattern(remap[yarn], raised, tuple(yarns[i] for i in used), meta)


def single_view_errors(picture: QuantisedImage, pattern: LogicalPattern) -> tuple[float, float]:
    """Logical error of views A and B against the picture shifted by one row.

    Only pixels of the two stripe colours are compared (a middle colour is seen as stripes by
    design). Boundary rows, which show the stripe colour, are excluded. 0.0 means exact.
    """
    from illuknit.core.views import can_see

    pic = picture.palette[picture.indices].astype(np.int16)
    va = pattern.palette[can_see(pattern, "A")].astype(np.int16)
    vb = pattern.palette[can_see(pattern, "B")].astype(np.int16)
    pal = pattern.palette.astype(np.int16)
    outer = ((pic[..., None, :] == pal[None, None]).all(-1)).any(-1)
    wrong_a = (va[1:] != pic[:-1]).any(-1) & outer[:-1]
    wrong_b = (vb[:-1] != pic[1:]).any(-1) & outer[1:]
    na, nb = int(outer[:-1].sum()), int(outer[1:].sum())
    return (float(wrong_a.sum()) / na if na else 0.0, float(wrong_b.sum()) / nb if nb else 0.0)


def prepare_single_view_image(
    source: object,
    *,
    yarns: tuple[Yarn, ...] | None = None,
    n_colors: int | None = None,
    **resize: object,
) -> QuantisedImage:
    """Load, resize and quantise a picture for the single-view compiler.

    A single-view illusion is knitted with two yarns but can show a third, middle colour as their
    stripe. So the picture keeps up to 3 colours (``n_colors``, default: its own count if it has
    at most 3, else 3); with two user yarns the darkest picture colour becomes the darker yarn, the
    lightest the lighter yarn, and a middle colour stays a picture colour (never knitted). With
    three user yarns, picture colours map one-to-one to the nearest yarns.
    """
    from illuknit.pictures.sizing import prepare_image

    if isinstance(source, (str, bytes)) or hasattr(source, "__fspath__"):
        rgb = load_image(source)
    else:
        rgb = check_image(source)  # type: ignore[arg-type]
    if n_colors is not None and n_colors not in (2, 3):
        raise ImageInputError(
            f"a single-view illusion shows 2 or 3 colours, got --colors {n_colors}"
        )
    if yarns is not None and len(yarns) not in (2, 3):
        raise ImageInputError(
            f"a single-view illusion is knitted with 2 yarns (3 with a middle colour), got {len(yarns)}"
        )
    distinct = count_colors(rgb)
    if n_colors is None:
        if yarns is not None and len(yarns) == 3:
            n_colors = 3
        elif distinct <= 2 or (yarns is not None and not resize.get("allow_quantise", True)):
            n_colors = 2
        else:
            n_colors = 3
    # prepare_image would count the colours again to choose its resampling.
    resize.setdefault("smooth", distinct > 16)
    if yarns is not None and len(yarns) == n_colors:
        return prepare_image(rgb, yarns=yarns, n_colors=n_colors, **resize)  # type: ignore[arg-type]
    q = prepare_image(rgb, yarns=None, n_colors=n_colors, **resize)  # type: ignore[arg-type]
    if yarns is None:
        if len(q.yarns) < 3:
            return q
        # The middle colour is knitted as a stripe of the outer two: name it so, in its colour.
        return QuantisedImage(
            q.indices, (q.yarns[0], _mix(q.yarns[0], q.yarns[2]), q.yarns[2]), q.colors
        )
    # Two yarns for a 3-colour picture: outer colours by brightness, middle a stripe of both.
    lum = luminance(np.array([y.rgb for y in yarns], dtype=np.float64))
    dark, light = (yarns[0], yarns[1]) if lum[0] <= lum[1] else (yarns[1], yarns[0])
    if len(q.yarns) < 3:
        mapped = (dark, light)[: len(q.yarns)] if len(q.yarns) == 2 else (dark,)
    else:
        mapped = (dark, _mix(dark, light), light)
    return QuantisedImage(q.indices, mapped, q.colors)


def _mix(dark: Yarn, light: Yarn) -> Yarn:
    """The middle colour of a single-view piece: a stripe of ``dark`` and ``light``, seen mixed."""
    rgb = tuple(int(v) for v in np.round((np.array(dark.rgb) + np.array(light.rgb)) / 2))
    return Yarn(f"mix of {dark.name} and {light.name}", rgb)  # type: ignore[arg-type]
