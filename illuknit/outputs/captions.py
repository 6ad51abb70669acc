"""Captions measured from the pictures they describe: what a pattern shows head-on.

A single-view pattern shows stripes head-on; a double-view pattern shows both its pictures,
mixed; a head-on design shows a picture of its own. Which one a pattern is cannot be read from
the command that made it (a double-view design can come close to stripes, a single view can
leak its picture), so the caption is measured: the head-on render and each side's render (the
calibrated renderer, :func:`illuknit.design.render.render_views`) are turned to luminance,
averaged over each pair of unit rows (one stripe period: stripes average out as they do for the
eye a step back) and compared by correlation.

>>> likeness = headon_likeness(pattern)       # doctest: +SKIP
>>> likeness.caption()                        # doctest: +SKIP
'Head-on: both pictures, mixed (correlation with view A 0.84, with view B 0.71)'
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from illuknit.core.colors import luminance
from illuknit.core.pattern import LogicalPattern, check_pattern

__all__ = ["LIKE", "PLAIN", "SAME", "HeadOnLikeness", "headon_likeness"]

#: A correlation at least this high counts as "shows that picture" (a single view's head-on
#: measures 0.0, a double view's both pictures 0.5-0.9 on the designs we tried).
LIKE = 0.2
#: Both correlations at least this high: head-on shows what the sides show (nothing hides).
SAME = 0.95
#: Head-on luminance varying less than this (standard deviation, after the stripe average)
#: counts as plain stripes.
PLAIN = 0.02


@dataclass(frozen=True)
class HeadOnLikeness:
    """How much the head-on view looks like each side's picture.

    Attributes
    ----------
    like_a, like_b : float
        Correlation (-1..1) of the head-on luminance with view A's and view B's, averaged over
        each pair of unit rows.
    spread : float
        Standard deviation of that head-on luminance (0..0.5): near 0 is plain stripes.
    """

    like_a: float
    like_b: float
    spread: float

    @property
    def shows(self) -> str:
        """ "stripes", "same" (as both sides), "both" (mixed), "A", "B" or "own" (a picture
        like neither side's)."""
        if self.spread < PLAIN:
            return "stripes"
        if min(self.like_a, self.like_b) >= SAME:
            return "same"
        a, b = self.like_a >= LIKE, self.like_b >= LIKE
        return "both" if a and b else "A" if a else "B" if b else "own"

    def caption(self) -> str:
        """One line for a picture's caption, with the numbers it rests on."""
        numbers = f"correlation with view A {self.like_a:.2f}, with view B {self.like_b:.2f}"
        words = {
            "stripes": "Head-on: stripes (no picture)",
            "same": f"Head-on: the same picture as both sides ({numbers})",
            "both": f"Head-on: both pictures, mixed ({numbers})",
            "A": f"Head-on: mostly view A's picture ({numbers})",
            "B": f"Head-on: mostly view B's picture ({numbers})",
            "own": f"Head-on: a picture of its own ({numbers})",
        }
        return words[self.shows]

    def as_dict(self) -> dict[str, Any]:
        return {
            "shows": self.shows,
            "like_a": round(self.like_a, 3),
            "like_b": round(self.like_b, 3),
            "spread": round(self.spread, 4),
            "caption": self.caption(),
        }


def headon_likeness(pattern: LogicalPattern, *, params: Any = None) -> HeadOnLikeness:
    """Measure what ``pattern`` shows head-on against what each side shows.

    Parameters
    ----------
    pattern : LogicalPattern
    params : illuknit.design.render.RenderParams, optional
        Renderer parameters (default: the calibrated defaults).
    """
    from illuknit.design.render import render_views

    check_pattern(pattern)
    views = render_views(pattern, params=params)
    a, b, head = (_stripe_average(_luma(views[v])) for v in ("A", "B", "headon"))
    return HeadOnLikeness(
        like_a=_correlation(head, a), like_b=_correlation(head, b), spread=float(head.std())
    )


def _luma(rgb: NDArray[np.uint8]) -> NDArray[np.float64]:
    return np.asarray(luminance(rgb.astype(np.float64)))


def _stripe_average(lum: NDArray[np.float64]) -> NDArray[np.float64]:
    """Mean of each window of two consecutive rows (a single row is kept as it is)."""
    if lum.shape[0] < 2:
        return lum
    return (lum[1:] + lum[:-1]) / 2.0


def _correlation(x: NDArray[np.float64], y: NDArray[np.float64]) -> float:
    dx, dy = x - x.mean(), y - y.mean()
    norm = float(np.sqrt((dx * dx).sum() * (dy * dy).sum()))
    return float((dx * dy).sum() / norm) if norm > 1e-12 else 0.0
