"""Closed-form ray-casting renderer (paper section 5, "Differentiable Renderer").

Each wale (column) is an independent 2-D problem. Along the wale, unit ``i`` is a cuboid occupying
``[i L, (i+1) L]`` with height ``h_i`` (``flat_height`` or ``bump_height``; any value in between
for soft designs). An orthographic camera at elevation ``theta`` looks along the wale; in view A
it stands beyond the top edge, so row 0 is nearest. Projected onto the image line
``u = s sin(theta) + z cos(theta)`` (``s`` along the wale, ``z`` up)::

            camera (view A)
              \\  theta
               \\                 top face of i        u (image line)
                \\                 ________             ^
           ______\\_______        |        |            |  b_i = (i+1) L sin + h_i cos
          |  i-1 (bump)   |       |   i    |  h_i       |  e_i = i L sin + h_i cos
    ______|_______________|_______|________|______      |  a_i = i L sin
    row 0 ...           s ->

unit ``i`` covers ``[a_i, b_i]``: its leading face ``[a_i, e_i]`` and its top face ``[e_i, b_i]``.
Nearer units always win, and the projections of consecutive units overlap, so what remains of
unit ``i`` after removing every nearer projection is the interval ``[C_{i-1}, C_i]`` with
``C_i = max(b_0, ..., b_i)`` (a running maximum), split at ``D_i = max(e_i, C_{i-1})`` into a
visible leading part and a visible top part. The picture along the wale is therefore piecewise
constant with ``2N`` segments (knots ``0, D_0, C_0, D_1, C_1, ...``).

Output pixels are a fixed, rectangular grid: pixel row ``k`` (of ``N * supersample``) covers
``[f cos + k L sin / S, f cos + (k+1) L sin / S]`` where ``f`` is the flat height — exactly the
projection of the top face of a flat unit ``k`` (``S = 1``). Each pixel's colour is the
coverage-weighted average of the segments over it: the difference of the running integral of the
piecewise-constant picture at the pixel's two ends. Coverage sums to 1 because heights are at
least ``f``, so the segments always reach past the last pixel. View B flips the rows, renders as
view A and flips back; head-on is ``theta = 90``.

When ``bump_height - flat_height == unit_length * tan(theta)`` a bump hides exactly the next unit
and every pixel shows exactly the unit :func:`illuknit.core.views.can_see` names; taller bumps (or
lower angles) begin to hide the unit after that too.

A *split bump* (``LogicalPattern.upper``) takes a colour per view (:func:`unit_colors`): view A
sees ``split_share`` of its second course's yarn and ``1 - split_share`` of its first's, view B the
reverse, head-on half of each; everything else is unchanged. A pattern knitted with tall bumps is
rendered with :meth:`RenderParams.with_tall_bumps`.

Everything is vectorised over all wales at once; the forward pass keeps a small tape that
:mod:`illuknit.design.render.grad` uses for the vector-Jacobian product, so previews and optimisation
share one code path.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.arguments import check_choice, check_instance, check_int, check_number
from illuknit.core.colors import linear_from_srgb, srgb_from_linear
from illuknit.core.errors import OptionError, PatternValidationError, RenderParamsError
from illuknit.core.pattern import LogicalPattern, check_pattern
from illuknit.core.views import VIEWS, View
from illuknit.design.render.params import RenderParams, check_angle

__all__ = [
    "Tape",
    "coverage",
    "heights_from_pattern",
    "render_at",
    "render_image",
    "render_pattern",
    "render_soft",
    "render_views",
    "sweep_angles",
    "unit_colors",
]


@dataclass(frozen=True, eq=False)
class Tape:
    """What the forward pass keeps for the backward pass (arrays in view-A row order).

    ``x`` (2N+1, M) knots; ``segcol`` (2N, M, K) segment colours; ``e``, ``b``, ``cprev``
    (N, M) leading-face end, top-face end, and the running maximum before each unit.
    """

    x: NDArray[np.float64]
    segcol: NDArray[np.float64]
    e: NDArray[np.float64]
    b: NDArray[np.float64]
    cprev: NDArray[np.float64]
    view: View
    sin: float
    cos: float
    shading: float
    p0: float
    pixel: float
    n_pixels: int


def _camera(params: RenderParams, view: str, angle: float | None) -> tuple[float, float]:
    if view not in VIEWS:
        raise OptionError(f"`view` must be one of {VIEWS}, got {view!r}")
    theta = (
        90.0
        if view == "headon"
        else check_angle(params.theta if angle is None else angle, name="angle")
    )
    if theta == 90.0:
        return 1.0, 0.0
    t = math.radians(theta)
    return math.sin(t), math.cos(t)


def _check_soft(
    heights: ArrayLike, colors: ArrayLike, params: RenderParams, supersample: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    h = np.asarray(heights, dtype=np.float64)
    col = np.asarray(colors, dtype=np.float64)
    if h.ndim != 2 or h.size == 0:
        raise PatternValidationError(
            f"`heights` must be a non-empty 2-D array (N, M), got shape {h.shape}"
        )
    if col.ndim == 2:
        col = col[..., None]
    if col.ndim != 3 or col.shape[:2] != h.shape:
        raise PatternValidationError(
            f"`colors` must have shape {h.shape} + (K,), got {np.asarray(colors).shape}"
        )
    if not np.all(np.isfinite(h)):
        raise PatternValidationError("`heights` must be finite")
    # A tiny tolerance: optimisers produce flat_height plus rounding error.
    if h.min() < params.flat_height * (1 - 1e-9):
        raise PatternValidationError(
            f"`heights` must be at least flat_height ({params.flat_height}), got minimum {h.min()}"
        )
    if (
        isinstance(supersample, bool)
        or not isinstance(supersample, int | np.integer)
        or supersample < 1
    ):
        raise OptionError(f"`supersample` must be a positive integer, got {supersample!r}")
    return h, col


def take_rows(arr: NDArray[np.float64], idx: NDArray[np.intp]) -> NDArray[np.float64]:
    """``arr[idx[p, w], w]`` for arr (T, M, K) and idx (P, M) -> (P, M, K).

    ``np.take`` on flat indices is several times faster than two-array fancy indexing here.
    """
    t, m, k = arr.shape
    flat = idx * m + np.arange(m)[None, :]
    return np.take(arr.reshape(t * m, k), flat, axis=0)


def cumsum_rows(arr: NDArray[np.float64], out: NDArray[np.float64]) -> NDArray[np.float64]:
    """Running sum along axis 0 into ``out`` (same shape); a row loop beats ``np.cumsum(axis=0)``
    on (T, M, K) arrays because each step is one contiguous vector add."""
    out[0] = arr[0]
    for i in range(1, arr.shape[0]):
        np.add(out[i - 1], arr[i], out=out[i])
    return out


def _forward_a(
    h: NDArray[np.float64],
    col: NDArray[np.float64],
    *,
    sin: float,
    cos: float,
    params: RenderParams,
    supersample: int,
    view: View,
    keep_tape: bool,
) -> tuple[NDArray[np.float64], Tape | None]:
    """Render in view-A orientation. h (N, M), col (N, M, K) -> image (N*S, M, K) and tape.

    The running integral ``F`` of the picture is kept per *unit* (not per segment): at ``C_j`` it is
    ``G_{j+1} = G_j + col_j (shading (D_j - C_{j-1}) + (C_j - D_j))``, and inside unit ``j``'s
    visible interval ``F(p) = G_j + col_j phi_j(p)`` with the scalar
    ``phi_j(p) = shading (min(p, D_j) - C_{j-1}) + max(p - D_j, 0)``. This halves the work of a
    per-segment integral; the tape stores the per-segment form the backward pass uses.
    """
    n, m = h.shape
    k = col.shape[2]
    shade = params.shading
    ls = params.unit_length * sin
    a = (np.arange(n, dtype=np.float64) * ls)[:, None]
    e = a + h * cos
    b = e + ls
    cc = np.empty((n + 1, m))  # 0, C_0, ..., C_{N-1}
    cc[0] = 0.0
    np.maximum.accumulate(b, axis=0, out=cc[1:])
    c, cprev = cc[1:], cc[:-1]
    d = np.maximum(e, cprev)
    w = c - d
    if shade != 1.0:
        w += shade * (d - cprev)
    else:
        w += d - cprev
    g = np.empty((n + 1, m, k))
    g[0] = 0.0
    cumsum_rows(col * w[..., None], g[1:])

    n_pix = n * supersample
    pixel = ls / supersample
    p0 = params.flat_height * cos
    p = p0 + np.arange(n_pix + 1, dtype=np.float64) * pixel
    # Per-wale searchsorted in one call: shift each wale's (sorted) knots into its own range.
    big = max(float(cc[-1].max()), float(p[-1])) + 1.0
    off = np.arange(m, dtype=np.float64) * big
    knots = (cc.T + off[:, None]).ravel()
    queries = (p[None, :] + off[:, None]).ravel()
    unit = np.searchsorted(knots, queries, side="right").reshape(m, n_pix + 1)
    unit -= (np.arange(m) * (n + 1))[:, None] + 1
    np.clip(unit, 0, n - 1, out=unit)
    unit = unit.T  # (P+1, M): the unit whose visible interval holds each pixel edge
    pp = p[:, None]
    dj = np.take_along_axis(d, unit, axis=0)
    phi = np.maximum(pp - dj, 0.0)
    lead = np.minimum(pp, dj) - np.take_along_axis(cprev, unit, axis=0)
    phi += shade * lead if shade != 1.0 else lead
    f = take_rows(g, unit)
    f += take_rows(col, unit) * phi[..., None]
    img = np.diff(f, axis=0)
    img /= pixel
    if not keep_tape:
        return img, None
    x = np.empty((2 * n + 1, m))
    x[0] = 0.0
    x[1::2] = d
    x[2::2] = c
    segcol = np.empty((2 * n, m, k))
    segcol[0::2] = col * shade
    segcol[1::2] = col
    tape = Tape(x, segcol, e, b, cprev, view, sin, cos, shade, p0, pixel, n_pix)
    return img, tape


def render_soft(
    heights: ArrayLike,
    colors: ArrayLike,
    *,
    params: RenderParams | None = None,
    view: View = "A",
    angle: float | None = None,
    supersample: int = 1,
    return_tape: bool = False,
) -> Any:
    """Render continuous heights and per-unit colours.

    Parameters
    ----------
    heights : ndarray of shape (N, M)
        Unit heights, each at least ``params.flat_height``.
    colors : ndarray of shape (N, M, K) or (N, M)
        Any per-unit quantity that mixes linearly: linear-light RGB, yarn probabilities, ...
    params : RenderParams, optional
    view : {"A", "B", "headon"}
    angle : float, optional
        Elevation in degrees, overriding ``params.theta`` (ignored head-on).
    supersample : int
        Pixel rows per unit row.
    return_tape : bool
        Also return the :class:`Tape` for :func:`illuknit.design.render.grad.render_vjp`.

    Returns
    -------
    ndarray of shape (N * supersample, M, K)
        Coverage-weighted averages of ``colors`` (and the tape if asked).
    """
    params = RenderParams() if params is None else params
    h, col = _check_soft(heights, colors, params, supersample)
    sin, cos = _camera(params, view, angle)
    # View B is view A of the flipped rows.
    flip = view == "B"
    img, tape = _forward_a(
        h[::-1] if flip else h,
        col[::-1] if flip else col,
        sin=sin,
        cos=cos,
        params=params,
        supersample=supersample,
        view=view,
        keep_tape=return_tape,
    )
    if flip:
        img = img[::-1]
    return (img, tape) if return_tape else img


def heights_from_pattern(
    pattern: LogicalPattern, params: RenderParams | None = None
) -> NDArray[np.float64]:
    """ndarray of shape (N, M): ``bump_height`` where raised, else ``flat_height``."""
    params = RenderParams() if params is None else params
    return np.where(pattern.raised, params.bump_height, params.flat_height)


def coverage(
    heights: ArrayLike,
    *,
    params: RenderParams | None = None,
    view: View = "A",
    angle: float | None = None,
    supersample: int = 1,
) -> NDArray[np.float64]:
    """Fraction of each pixel covered by each unit of its wale (shading ignored).

    Returns
    -------
    ndarray of shape (N * supersample, M, N)
        ``out[k, j, i]``: share of pixel row ``k`` in wale ``j`` showing unit row ``i``; sums to 1
        over ``i``. Dense, so meant for small patterns.
    """
    h = np.asarray(heights, dtype=np.float64)
    if h.ndim != 2:
        raise PatternValidationError(f"`heights` must be 2-D (N, M), got shape {h.shape}")
    n, m = h.shape
    eye = np.broadcast_to(np.eye(n)[:, None, :], (n, m, n))
    p = RenderParams() if params is None else params
    return render_soft(
        h, eye, params=replace(p, shading=1.0), view=view, angle=angle, supersample=supersample
    )


def unit_colors(
    pattern: LogicalPattern, view: View, params: RenderParams | None = None
) -> NDArray[np.float64]:
    """ndarray of shape (N, M, 3): the linear-light colour of every unit seen from ``view``.

    A unit's yarn, except at split bumps, which mix their two courses' yarns: from view A
    ``split_share`` of the second course (``upper``), from view B ``split_share`` of the first
    (``yarn``), head-on half of each (see :mod:`illuknit.core.views`).
    """
    lin = linear_from_srgb(pattern.palette)
    col = lin[pattern.yarn]
    if pattern.upper is None:
        return col
    params = RenderParams() if params is None else params
    near = {"A": params.split_share, "B": 1.0 - params.split_share, "headon": 0.5}[view]
    mixed = near * lin[pattern.upper] + (1.0 - near) * col
    return np.where(pattern.split[..., None], mixed, col)


def _to_uint8(lin: NDArray[np.float64]) -> NDArray[np.uint8]:
    return np.rint(srgb_from_linear(lin)).astype(np.uint8)


def render_pattern(
    pattern: LogicalPattern,
    *,
    params: RenderParams | None = None,
    view: View = "A",
    angle: float | None = None,
    supersample: int = 1,
) -> NDArray[np.uint8]:
    """Render a pattern as an sRGB image.

    Colours are mixed in linear light (what the eye integrates) and converted back to sRGB.

    Returns
    -------
    ndarray of shape (N * supersample, M, 3), uint8
        Upright, rows in the pattern's picture order.
    """
    check_pattern(pattern)
    if params is not None:
        check_instance(params, RenderParams, "params", error=RenderParamsError)
    check_int(supersample, "supersample", min=1, max=8)
    check_choice(view, "view", ("A", "B", "headon"))
    if not isinstance(pattern, LogicalPattern):
        raise PatternValidationError(
            f"`pattern` must be a LogicalPattern, got {type(pattern).__name__}"
        )
    params = RenderParams() if params is None else params
    col = unit_colors(pattern, view, params)
    lin = render_soft(
        heights_from_pattern(pattern, params),
        col,
        params=params,
        view=view,
        angle=angle,
        supersample=supersample,
    )
    return _to_uint8(lin)


def render_at(
    pattern: LogicalPattern,
    angle: float,
    *,
    params: RenderParams | None = None,
    supersample: int = 1,
) -> NDArray[np.uint8]:
    """Render from a signed elevation: ``+a`` is view A at ``a`` degrees, ``-a`` view B, ±90 head-on.

    This is what a viewer walking past the hanging piece sees (the CLI's GIF sweeps it).
    """
    check_pattern(pattern)
    if params is not None:
        check_instance(params, RenderParams, "params", error=RenderParamsError)
    check_int(supersample, "supersample", min=1, max=8)
    if isinstance(angle, bool) or not isinstance(angle, int | float) or not 0 < abs(angle) <= 90:
        raise RenderParamsError(
            f"`angle` must be a non-zero number of degrees in [-90, 90], got {angle!r}"
        )
    a = check_angle(abs(float(angle)), name="angle")
    view: View = "headon" if a == 90.0 else ("A" if angle > 0 else "B")
    return render_pattern(pattern, params=params, view=view, angle=a, supersample=supersample)


def render_views(
    pattern: LogicalPattern,
    *,
    params: RenderParams | None = None,
    angle: float | None = None,
    supersample: int = 1,
) -> dict[str, NDArray[np.uint8]]:
    """Renders of views "A", "B" and "headon" as uint8 images of shape (N * supersample, M, 3).

    ``angle`` (degrees, (0, 90]) overrides ``params.theta`` for the side views.
    """
    check_pattern(pattern)
    if params is not None:
        check_instance(params, RenderParams, "params", error=RenderParamsError)
    check_int(supersample, "supersample", min=1, max=8)
    return {
        v: render_pattern(pattern, params=params, view=v, angle=angle, supersample=supersample)
        for v in VIEWS
    }


def render_image(
    pattern: LogicalPattern,
    angle: float,
    *,
    params: RenderParams | None = None,
    scale: int = 1,
    unit_aspect: float | None = None,
) -> NDArray[np.uint8]:
    """A picture for people: :func:`render_at` with each wale widened to ``scale`` pixels and
    several pixel rows per unit row (so partly hidden units show as partial bands).

    Parameters
    ----------
    scale : int
        Pixels per unit across, 1-64 (the renderer resolves at most 8 bands per unit row; finer
        pictures repeat its rows).
    unit_aspect : float, optional
        Height over width of a unit in the fabric (:attr:`illuknit.core.gauge.Gauge.unit_aspect`):
        the picture is drawn in the fabric's proportions as seen at ``angle``, ``round(N * scale
        * unit_aspect * sin|angle|)`` rows. None: ``N * scale`` rows, one unit row's projection
        as tall as the unit is wide.

    Returns
    -------
    ndarray of shape (rows, M * scale, 3), uint8
    """
    check_int(scale, "scale", min=1, max=64)
    n = pattern.shape[0] if isinstance(pattern, LogicalPattern) else 1
    if unit_aspect is None:
        rows = n * scale
    else:
        unit_aspect = check_number(unit_aspect, "unit_aspect", min=0.05, max=20)
        a = check_number(angle, "angle", min=-90, max=90, error=RenderParamsError)
        seen = math.sin(math.radians(abs(a)))
        rows = max(1, round(n * scale * unit_aspect * seen))
    supersample = int(min(8, max(1, math.ceil(rows / max(n, 1)))))
    img = render_at(pattern, angle, params=params, supersample=supersample)
    if img.shape[0] != rows:  # nearest-neighbour to the rows asked for
        img = img[(np.arange(rows) * img.shape[0]) // rows]
    return np.repeat(img, scale, axis=1)


def sweep_angles(angle: float, frames: int) -> list[float]:
    """Signed elevations for a walk past the piece: from ``+angle`` (view A) through head-on to
    ``-angle`` (view B), evenly spaced in the direction of view; ``frames`` >= 2 of them."""
    a = check_angle(angle, name="angle")
    if isinstance(frames, bool) or not isinstance(frames, int) or frames < 2:
        raise RenderParamsError(f"`frames` must be an integer >= 2, got {frames!r}")
    span = 90.0 - a
    out = []
    for phi in np.linspace(-span, span, frames):
        elev = 90.0 - abs(float(phi))
        out.append(elev if phi <= 0 else -elev)
    return out
