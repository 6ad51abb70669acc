"""How a tile candidate reads: its perceptual measures, and where a design fails.

The tile assignment ranks candidates by a *score* of colour closeness, stripe and yarn counts
(:mod:`illuknit.design.tiles.assign`); nothing in it looks at the result. This module renders each
compiled candidate at the viewing angle (:func:`illuknit.design.measures.angled_renders`, the
renderer of :mod:`illuknit.design.render`) and measures, per view, against the designer's quantised
picture (not the repainted one the candidate was designed against):

* **readability** -- the Pearson correlation of blurred linear-light luminance of the render and
  of the picture (:func:`illuknit.design.measures.render_correlation`): is the picture there?
* **contrast** -- the least-squares gain of render luminance on picture luminance (same blur):
  how much of the picture's light/dark difference survives. 1 reproduces it, 0 is a flat field.
  Readability is blind to it: a background repainted as a dark stripe against black shapes keeps
  a high correlation but almost no contrast.
* **ghosting** (double view) -- how much of the *other* picture shows through
  (:func:`illuknit.design.measures.ghosting`): the correlation of what the picture leaves
  unexplained in the render with the other picture.
* **visible ghosting** -- that correlation scaled by how much of the render the picture leaves
  unexplained, ``|ghosting| * sqrt(1 - readability**2)`` (the semipartial correlation): the share
  of the render's light/dark variation that follows the other picture. Ghosting alone says what
  the *error* looks like, however small: a render that reproduces its picture at readability 0.99
  leaves 2 % of its variance unexplained, and a 0.3 ghosting correlation of that residue is a
  faint outline (visible ghosting 0.04), while at readability 0.9 it would be a second picture
  (0.13).
* optionally the **machine knitting time** and passes, measured by a function the caller passes
  (``knit_time``, a :data:`KnitMeasure` such as :func:`illuknit.bench.metrics.knit_stats` with
  its machine bound: the passes the SWG machine runs for the candidate's program). Knitting sits
  above design, so the design floor takes the measurement rather than knitting itself.

:func:`diagnostic_rgb` shows *where* a view fails: units whose perceived luminance, after the
best gain and offset, is far from the picture's (red) and units where the other picture's
pattern shows through (blue), over the picture in grey. :func:`seen_blur` and
:func:`seen_from` give what an eye resolves of the fabric from a viewing distance.

How the candidates are ranked on these measures is :mod:`illuknit.design.tiles.perception`,
which also re-exports every public name of this module.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.errors import OptionError
from illuknit.core.pattern import LogicalPattern
from illuknit.design.hand_cost import HandCost, hand_cost
from illuknit.design.measures import (
    BLUR_SIGMA,
    RENDER_ANGLE,
    angled_renders,
    blurred_luminance,
    correlation,
    residual_correlation,
)

__all__ = [
    "ACUITY_ARCMIN",
    "CONTRAST_FLOOR",
    "CONTRAST_PENALTY",
    "GHOST_THRESHOLD",
    "WRONG_THRESHOLD",
    "CandidateMeasures",
    "KnitMeasure",
    "diagnostic_rgb",
    "eye_blur_units",
    "measure_candidate",
    "seen_blur",
    "seen_from",
    "seen_targets",
]

#: The finest detail a normal eye (20/20) resolves, in minutes of arc.
ACUITY_ARCMIN = 1.0

#: Below this worse-view contrast (gain of render on picture luminance) the score is penalised.
CONTRAST_FLOOR = 0.25
#: Score lost per unit of contrast below :data:`CONTRAST_FLOOR`.
CONTRAST_PENALTY = 1.0
#: Knits a pattern and measures it on a machine: the fields ``knit_time_min``, ``carriage_passes``
#: and ``knit_note`` of :func:`illuknit.bench.metrics.knit_stats` (a number may be None, with the
#: note saying why).
KnitMeasure = Callable[[LogicalPattern], Mapping[str, Any]]
#: A unit is marked "wrong" where the fitted render is off by more than this (linear luminance).
WRONG_THRESHOLD = 0.15
#: A unit is marked "ghost" where the other picture explains more than this of the residual.
GHOST_THRESHOLD = 0.05


@dataclass(frozen=True)
class CandidateMeasures:
    """Perceptual measures of one candidate, per view, in the order of its views.

    Attributes
    ----------
    views : tuple of str
        The names of the measured views (``("A", "B")``, or ``("headon", "side")``).
    readability, contrast : tuple of float or None
        Per view; nan where the render is flat (nothing reads), None where the picture itself is
        a plain field (a head-on design's side: there is nothing to read, only to hide).
    ghosting : tuple of float or None
        Per view; None where there is no other picture to ghost.
    knit_minutes : float or None
        Machine knitting time, when measured.
    machine_passes : int or None
        The machine's carriage passes, when measured.
    """

    views: tuple[str, ...]
    readability: tuple[float | None, ...]
    contrast: tuple[float | None, ...]
    ghosting: tuple[float | None, ...]
    knit_minutes: float | None = None
    machine_passes: int | None = None
    knit_note: str = field(default="")
    sides_read: int | None = None
    hand: HandCost | None = None

    @property
    def worse_readability(self) -> float:
        """The lower readability of the views (nan counts as 0: nothing reads)."""
        return min((_num(r) for r in self.readability if r is not None), default=0.0)

    @property
    def worse_contrast(self) -> float:
        return min((_num(c) for c in self.contrast if c is not None), default=0.0)

    @property
    def worst_ghosting(self) -> float:
        return max((abs(g) for g in self.ghosting if g is not None and g == g), default=0.0)

    @property
    def visible_ghosting(self) -> tuple[float | None, ...]:
        """Per view, the share of the render's variation that follows the other picture.

        ``|ghosting| * sqrt(1 - readability**2)``: the ghosting correlation is taken of what the
        view's own picture leaves unexplained, and ``sqrt(1 - readability**2)`` is how much that
        is (all of it where the picture is plain or nothing reads). None where no ghosting is
        measured.
        """
        out: list[float | None] = []
        for g, r in zip(self.ghosting, self.readability, strict=True):
            if g is None or g != g:
                out.append(None)
                continue
            read = 0.0 if r is None else min(1.0, abs(_num(r)))
            out.append(abs(g) * float(np.sqrt(1.0 - read * read)))
        return tuple(out)

    @property
    def worst_visible_ghosting(self) -> float:
        return max((g for g in self.visible_ghosting if g is not None), default=0.0)

    @property
    def perceptual_score(self) -> float:
        """The documented combination the default ranking sorts by (higher is better)."""
        shortfall = max(0.0, CONTRAST_FLOOR - self.worse_contrast)
        return self.worse_readability - CONTRAST_PENALTY * shortfall

    def to_json(self) -> dict[str, Any]:
        def r(x: float | None) -> float | None:  # JSON has no nan
            return None if x is None or x != x else round(float(x), 4)

        return {
            "views": list(self.views),
            "readability": [r(v) for v in self.readability],
            "contrast": [r(v) for v in self.contrast],
            "ghosting": [r(v) for v in self.ghosting],
            "worse_readability": r(self.worse_readability),
            "worse_contrast": r(self.worse_contrast),
            "worst_ghosting": r(self.worst_ghosting),
            "visible_ghosting": [r(v) for v in self.visible_ghosting],
            "worst_visible_ghosting": r(self.worst_visible_ghosting),
            "perceptual_score": r(self.perceptual_score),
            "knit_minutes": r(self.knit_minutes),
            "machine_passes": self.machine_passes,
            "knit_note": self.knit_note,
            "sides_read": self.sides_read,
            "hand": None if self.hand is None else self.hand.to_json(),
        }


def _num(x: float) -> float:
    return 0.0 if x != x else float(x)


def _grey(rgb: ArrayLike) -> NDArray[np.float64]:
    return blurred_luminance(rgb, BLUR_SIGMA)


def _gain(render: NDArray[np.float64], target: NDArray[np.float64]) -> float:
    t = target.ravel() - target.mean()
    var = float((t * t).sum())
    if var < 1e-12:
        return float("nan")
    return float((t * (render.ravel() - render.mean())).sum() / var)


def _float_rgb(img: ArrayLike) -> NDArray[np.float64]:
    a = np.asarray(img)
    out = a.astype(np.float64)
    return out / 255.0 if np.issubdtype(a.dtype, np.integer) else out


def _view_renders(
    pattern: LogicalPattern, views: Sequence[str], *, angle: float, params: Any = None
) -> list[list[NDArray[np.float64]]]:
    """For each measured view, the renders it is seen in (a side view is seen from both ends)."""
    renders, _ = angled_renders(pattern, angle=angle, params=params)
    table = {"A": ["A"], "B": ["B"], "headon": ["headon"], "side": ["A", "B"]}
    return [[renders[k] for k in table[v]] for v in views]


def measure_candidate(
    pattern: LogicalPattern,
    pictures: Sequence[ArrayLike],
    *,
    views: Sequence[str] = ("A", "B"),
    ghost: bool = True,
    knit_time: KnitMeasure | None = None,
    angle: float | None = None,
    blur: float | None = None,
    params: Any = None,
) -> CandidateMeasures:
    """Measure how a compiled candidate reads in each of its views.

    Parameters
    ----------
    pattern : LogicalPattern
        The compiled candidate, N x M units.
    pictures : sequence of ndarray of shape (N, M, 3)
        The designer's quantised picture per view (uint8 or float sRGB in [0, 1]).
    views : sequence of str
        ``("A", "B")`` for a double view, ``("headon", "side")`` for the head-on variant.
    ghost : bool
        Measure ghosting between the two pictures: how much of the other picture shows in each
        view (for a head-on design, how much of the front picture is left at an angle).
    knit_time : KnitMeasure, optional
        Also knit the pattern with this function and keep the machine's passes and time.
    angle : float, optional
        Viewing angle of the side renders (default the bench's).
    blur : float, optional
        The blur, in units, of what is compared (default the bench's fixed 1.5 units): e.g.
        :func:`eye_blur_units` of a viewing distance, to judge what an eye resolves from there.
    params : RenderParams, optional
        The renderer's parameters (default ones when None): e.g. ``with_tall_bumps()`` for a
        pattern knitted with tall bumps, or a measured split share.
    """
    if len(pictures) != len(views):
        raise OptionError(f"need one picture per view {tuple(views)}, got {len(pictures)}")
    sigma = BLUR_SIGMA if blur is None else float(blur)
    if not sigma >= 0:
        raise OptionError(f"`blur` must be a non-negative number of units, got {blur!r}")

    def _grey(rgb: ArrayLike) -> NDArray[np.float64]:
        return blurred_luminance(rgb, sigma)

    targets = [_grey(_float_rgb(p)) for p in pictures]
    seen = _view_renders(
        pattern, views, angle=RENDER_ANGLE if angle is None else angle, params=params
    )
    read: list[float | None] = []
    contrast: list[float | None] = []
    ghosting: list[float | None] = []
    for k, (t, renders) in enumerate(zip(targets, seen, strict=True)):
        greys = [_grey(r) for r in renders]
        plain = float(np.ptp(t)) < 1e-9
        read.append(None if plain else min((correlation(g, t) for g in greys), key=_num))
        contrast.append(None if plain else min((_gain(g, t) for g in greys), key=_num))
        if ghost and len(targets) == 2:
            other = targets[1 - k]
            worst = max(
                (residual_correlation(g, t, other) for g in greys), key=lambda x: abs(_num(x))
            )
            if worst != worst and float(np.ptp(other)) >= 1e-9:
                # what is seen is all explained by this view's own picture (a head-on design
                # that vanishes into a plain field): none of the other picture shows
                worst = 0.0
            ghosting.append(None if worst != worst else worst)
        else:
            ghosting.append(None)
    measured = CandidateMeasures(
        views=tuple(views),
        readability=tuple(read),
        contrast=tuple(contrast),
        ghosting=tuple(ghosting),
        hand=hand_cost(pattern),
    )
    return _with_knit_time(measured, pattern, knit_time) if knit_time is not None else measured


def _with_knit_time(
    m: CandidateMeasures, pattern: LogicalPattern, knit_time: KnitMeasure
) -> CandidateMeasures:
    from dataclasses import replace

    stats = knit_time(pattern)
    return replace(
        m,
        knit_minutes=stats["knit_time_min"],
        machine_passes=stats["carriage_passes"],
        knit_note=stats["knit_note"],
    )


def diagnostic_rgb(
    pattern: LogicalPattern,
    picture: ArrayLike,
    other: ArrayLike | None = None,
    *,
    view: str = "A",
    angle: float | None = None,
) -> tuple[NDArray[np.uint8], dict[str, float]]:
    """Where a view fails: an (N, M, 3) uint8 image and the fractions of units marked.

    The picture is shown in grey; a unit is **red** where the render's blurred luminance, after
    the least-squares gain and offset onto the picture, is off by more than
    :data:`WRONG_THRESHOLD` (it shows the wrong shade), and **blue** where the residual follows
    the ``other`` picture by more than :data:`GHOST_THRESHOLD` (it ghosts through).
    """
    t = _grey(_float_rgb(picture))
    seen = _view_renders(pattern, [view], angle=RENDER_ANGLE if angle is None else angle)[0]
    g = np.mean([_grey(r) for r in seen], axis=0)
    design = np.stack([np.ones(t.size), t.ravel()], axis=1)
    coef, *_ = np.linalg.lstsq(design, g.ravel(), rcond=None)
    residual = g.ravel() - design @ coef
    # Refit on the units that agree best, so that a wrong patch does not bend the fit (and so
    # mark the whole picture) but stands out on its own.
    keep = np.abs(residual) <= np.quantile(np.abs(residual), 0.8)
    if keep.sum() >= 2 and np.ptp(t.ravel()[keep]) > 1e-9:
        coef, *_ = np.linalg.lstsq(design[keep], g.ravel()[keep], rcond=None)
        residual = g.ravel() - design @ coef
    residual = residual.reshape(t.shape)
    wrong = np.abs(residual) > WRONG_THRESHOLD
    ghost = np.zeros_like(wrong)
    if other is not None:
        o = _grey(_float_rgb(other))
        oc = o - o.mean()
        scale = float(np.abs(oc).max()) or 1.0
        ghost = (residual * oc / scale > GHOST_THRESHOLD) & ~wrong
    base = 0.35 + 0.5 * (t - t.min()) / max(float(np.ptp(t)), 1e-9)
    img = np.repeat(base[..., None], 3, axis=2)
    img[wrong] = (0.9, 0.1, 0.1)
    img[ghost] = (0.15, 0.35, 0.95)
    stats = {"wrong": float(wrong.mean()), "ghost": float(ghost.mean())}
    return (np.clip(img, 0, 1) * 255 + 0.5).astype(np.uint8), stats


def eye_blur_units(
    distance_m: float, *, gauge: float = 7.0, acuity_arcmin: float = ACUITY_ARCMIN
) -> float:
    """The blur, in units, of what an eye resolves of a fabric ``distance_m`` metres away.

    The finest detail the eye resolves spans ``acuity_arcmin`` minutes of arc: at ``distance_m``
    that is ``distance_m * tan(acuity)`` on the fabric, taken as the full width at half maximum
    of a Gaussian blur. One unit is 2 stitches wide, ``2 * 25.4 / gauge`` mm. Returns the
    Gaussian's standard deviation in units (at 7 stitches per inch and 1 arc-minute: 0.034
    units at 2 m, 0.17 at 10 m; the fixed blur of the readability measures, 1.5 units, is what
    a 20/20 eye resolves from about 88 m).

    Raises
    ------
    OptionError
        ``distance_m``, ``gauge`` or ``acuity_arcmin`` is not positive.
    """
    import math

    for name, value in (("distance", distance_m), ("gauge", gauge), ("acuity", acuity_arcmin)):
        if not (isinstance(value, int | float) and value > 0 and math.isfinite(value)):
            raise OptionError(f"`{name}` must be a positive number, got {value!r}")
    detail_mm = 1000.0 * distance_m * math.tan(math.radians(acuity_arcmin / 60.0))
    unit_mm = 2 * 25.4 / gauge
    return detail_mm / unit_mm / (2 * math.sqrt(2 * math.log(2)))


def seen_blur(distance_m: float, *, gauge: float = 7.0) -> float:
    """The blur, in units, the measures see a render through from ``distance_m`` metres.

    What the eye resolves there (:func:`eye_blur_units`) followed by the pooling that makes a
    fill's stripes read as one region, :data:`~illuknit.design.measures.BLUR_SIGMA` (1.5
    units): two Gaussian blurs, so ``hypot(BLUR_SIGMA, eye_blur_units(distance_m))``. From a
    few metres the eye resolves every unit and the pooling alone counts (1.501 units from 3 m
    at 7 stitches per inch, 1.51 from 10 m); it adds measurably from about 20 m (1.54 units,
    1.73 from 50 m), and from 88 m the eye's blur is as large as the pooling (2.12 units). docs/tiles.md shows, on the bundled pairs, why the pooling is kept
    rather than the eye's resolution alone or a multi-scale structural similarity.
    """
    import math

    return math.hypot(BLUR_SIGMA, eye_blur_units(distance_m, gauge=gauge))


def seen_from(rgb: ArrayLike, sigma_px: float) -> NDArray[np.uint8]:
    """A picture (uint8 sRGB) as an eye sees it through a Gaussian blur of ``sigma_px`` pixels,
    blurred in linear light (where the colours of stripes mix); see :func:`eye_blur_units`."""
    from illuknit.design.measures import blur_image

    a = np.asarray(rgb, dtype=np.float64) / 255.0
    if sigma_px <= 0:
        return np.asarray(rgb, dtype=np.uint8)
    out = blur_image(a, sigma=float(sigma_px))
    return np.clip(np.round(out * 255.0), 0, 255).astype(np.uint8)


def seen_targets(qa: Any, qb: Any | None) -> list[NDArray[np.uint8]]:
    """What each view of a tile design should show, as :func:`rank_designs` takes it: the
    designer's quantised pictures (:class:`~illuknit.quantize.QuantisedImage`), or for a head-on
    design without a side picture, the plain side :func:`~illuknit.design.tiles.headon.uniform_side`
    stands for."""
    if qb is not None:
        return [qa.rgb(), qb.rgb()]
    from illuknit.design.tiles.headon import uniform_side

    side_idx, side_colors = uniform_side(qa)
    return [qa.rgb(), np.asarray(side_colors, dtype=np.uint8)[np.asarray(side_idx)]]
