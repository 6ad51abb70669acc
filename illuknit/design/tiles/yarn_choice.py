"""Yarns for two pictures knitted together: each picture keeps its darkest and lightest colour.

Clustering the pictures jointly lets the picture that covers more, or has more shades, take every
yarn: ``illuknit double --colors 4`` once chose four dark yarns for two logos and lost one logo's
white background. A picture whose lightest (or darkest) colour has no yarn near it cannot show
its own contrast, whatever the tiles do. :func:`choose_yarns` therefore chooses each picture's
extremes first and fills the remaining yarns from the joint clusters.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.colors import lab_from_rgb, luminance
from illuknit.core.errors import YarnSpecError
from illuknit.core.pattern import Yarn

__all__ = ["SAME_COLOUR_LAB", "choose_yarns", "picture_extremes"]

#: Colours closer than this (CIELAB distance) count as one when choosing yarns.
SAME_COLOUR_LAB = 10.0


def picture_extremes(picture: ArrayLike, n_colors: int) -> NDArray[np.float64]:
    """The darkest and the lightest colour of ``picture`` quantised to ``n_colors``: an ndarray
    of shape (2, 3), sRGB 0-255."""
    from illuknit.pictures.images import quantise_image

    cols = quantise_image(picture, n_colors=n_colors).colors.astype(np.float64)
    lum = luminance(cols)
    return np.array([cols[int(np.argmin(lum))], cols[int(np.argmax(lum))]])


def _farthest_first(
    labs: NDArray[np.float64], chosen: list[int], among: Sequence[int], n: int
) -> None:
    """Add to ``chosen`` (in place: a local list) the index of ``among`` farthest from those
    chosen, while fewer than ``n`` and while it is more than :data:`SAME_COLOUR_LAB` away."""
    while len(chosen) < n:
        rest = [i for i in among if i not in chosen]
        if not rest:
            return
        dist = [min(float(np.linalg.norm(labs[i] - labs[j])) for j in chosen) for i in rest]
        if max(dist) <= SAME_COLOUR_LAB:
            return
        chosen.append(rest[int(np.argmax(dist))])


def choose_yarns(pictures: Sequence[ArrayLike], n: int) -> tuple[Yarn, ...]:
    """``n`` yarns (at most; fewer when the pictures have fewer distinct colours), darkest first.

    Each picture's darkest and lightest colour (quantised to ``n`` colours) is chosen first: the
    overall darkest and lightest, then the other extremes farthest first (near-equal ones once).
    The rest of the ``n`` come from the pictures' joint clusters, each time the one farthest
    (CIELAB) from those chosen.
    """
    from illuknit.pictures.images import auto_yarns, quantise_image

    if not 1 <= n <= 8:
        raise YarnSpecError(f"the number of yarns must be between 1 and 8, got {n}")
    if not pictures:
        raise YarnSpecError("choosing yarns needs at least one picture")
    extremes = [c for p in pictures for c in picture_extremes(p, n)]
    extremes.sort(key=lambda c: float(luminance(c)))
    joint = quantise_image(np.concatenate([np.asarray(p) for p in pictures], axis=0), n_colors=n)
    pool = [extremes[0], extremes[-1], *extremes[1:-1], *joint.colors.astype(np.float64)]
    labs = lab_from_rgb(np.array(pool))
    chosen = [0]
    _farthest_first(labs, chosen, range(len(extremes)), n)
    _farthest_first(labs, chosen, range(len(pool)), n)
    colors = np.array([pool[i] for i in chosen])
    order = np.argsort(luminance(colors), kind="stable")
    return auto_yarns(np.round(colors[order]).astype(np.uint8))
