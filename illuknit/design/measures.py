"""How a pattern's pictures read: the measures the ranking of designs and the benchmark share.

* **Render error** per view: MSE and SSIM between the angled render (:mod:`illuknit.design.render` at
  :data:`RENDER_ANGLE` degrees, resampled to one pixel per unit) and the target in yarn colours.
  Both images are first blurred by the same kernel, :func:`blur_image`: a Gaussian of standard
  deviation :data:`BLUR_SIGMA` units along both axes, applied in *linear light* (stripes mix like
  light, the same mixing the tile fills use) with reflected edges, then converted back to sRGB.
  A 2-row c1/c2 stripe is attenuated to under 1 % of its contrast, a 3-row stripe to ~0.7 %, a
  4-row stripe to ~6 %, so stripes count as their average colour while regions of a few units
  survive. MSE is over sRGB in [0, 1] averaged over pixels and channels; SSIM is scikit-image's
  ``structural_similarity`` with ``channel_axis=2``, ``data_range=1`` and a 7 x 7 window (smaller
  for tiny images).
* **Readability** per view: the Pearson correlation between the blurred render's and the blurred
  target's relative luminance (linear light, same kernel) (:func:`render_correlation`). Unlike MSE
  it ignores a uniform loss of contrast or a shift in brightness (a striped background that reads
  as mid-tone), so it asks "is the picture there?" rather than "are the colours right?".
* **Ghosting** (double view): how much of the *other* view's target shows through
  (:func:`ghosting`): the luminance of view A's render is fitted by least squares on target A, and
  the residual is correlated with target B (and vice versa); 0 means no trace of B in view A.
  This is the "visual interference" of paper Fig. 19 (a).
* **Head-on visibility**: the largest absolute correlation of the blurred head-on render with
  either target. A single-view illusion should hide its picture head-on (close to 0).
* **Colour changes per course**: for each pattern row (both of its knitting courses carry the same
  colours), the number of horizontally adjacent unit pairs of different yarn; mean and max over
  rows. Also the distinct yarns per row (mean, max) -- a lower bound on carriers per course.

* **Multi-scale structural similarity** (:func:`multiscale_ssim`): a candidate measure compared
  against readability (docs/tiles.md, "Which measure matches the eye"): scikit-image's
  ``structural_similarity`` in CIELAB at five scales, each half the resolution of the one
  before (what an eye resolves from twice as far), averaged with the weights of Wang,
  Simoncelli and Bovik's MS-SSIM. It is not the ranking measure: on the bundled pairs it
  prefers solid shapes on striped grounds even where the colours or the ground are lost.

The building blocks (:func:`blurred_luminance`, :func:`correlation`,
:func:`residual_correlation`) are public so that a ranking can compute each image's blurred
luminance once and score it many times.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.colors import linear_from_srgb, luminance, srgb_from_linear
from illuknit.core.pattern import LogicalPattern

__all__ = [
    "BLUR_SIGMA",
    "MS_SSIM_WEIGHTS",
    "RENDER_ANGLE",
    "angled_renders",
    "blur_image",
    "blurred_luminance",
    "color_changes",
    "correlation",
    "ghosting",
    "multiscale_ssim",
    "picture_scores",
    "render_correlation",
    "render_error",
    "residual_correlation",
]


#: Standard deviation of the Gaussian blur applied before render error, in units.
BLUR_SIGMA = 1.5


#: Viewing elevation angle (degrees) of the angled renders.
RENDER_ANGLE = 30.0


def blur_image(rgb: ArrayLike, *, sigma: float = BLUR_SIGMA) -> NDArray[np.float64]:
    """Gaussian blur in linear light (see the module docstring).

    Parameters
    ----------
    rgb : ndarray of shape (N, M, 3)
        sRGB in [0, 1].

    Returns
    -------
    ndarray of float64, shape (N, M, 3)
        Blurred sRGB in [0, 1].
    """
    from scipy.ndimage import gaussian_filter

    a = np.asarray(rgb, dtype=np.float64)
    lin = linear_from_srgb(a * 255.0)
    blurred = gaussian_filter(lin, sigma=(sigma, sigma, 0), mode="reflect", truncate=4.0)
    return srgb_from_linear(blurred) / 255.0


def render_error(
    rendered: ArrayLike, target: ArrayLike, *, sigma: float = BLUR_SIGMA
) -> tuple[float, float]:
    """(MSE, SSIM) between two (N, M, 3) sRGB images in [0, 1], both blurred by :func:`blur_image`."""
    from skimage.metrics import structural_similarity

    r = blur_image(rendered, sigma=sigma)
    t = blur_image(target, sigma=sigma)
    if r.shape != t.shape:
        raise ValueError(f"render shape {r.shape} differs from target {t.shape}")
    mse = float(np.mean((r - t) ** 2))
    side = min(r.shape[0], r.shape[1])
    win = min(7, side if side % 2 else side - 1)
    if win < 3:
        return mse, float("nan")
    ssim = structural_similarity(r, t, channel_axis=2, data_range=1.0, win_size=win)
    return mse, float(ssim)


def blurred_luminance(rgb: ArrayLike, sigma: float) -> NDArray[np.float64]:
    """Blurred relative luminance in linear light (where light, and so stripes, mix linearly)."""
    from scipy.ndimage import gaussian_filter

    y = luminance(np.asarray(rgb, dtype=np.float64) * 255.0)
    return gaussian_filter(y, sigma=sigma, mode="reflect", truncate=4.0)


def correlation(x: NDArray[np.float64], y: NDArray[np.float64]) -> float:
    """Pearson correlation of two arrays (nan when either is flat)."""
    x = x.ravel() - x.mean()
    y = y.ravel() - y.mean()
    den = float(np.sqrt((x * x).sum() * (y * y).sum()))
    if den < 1e-12:
        return float("nan")
    return float((x * y).sum() / den)


def render_correlation(
    rendered: ArrayLike, target: ArrayLike, *, sigma: float = BLUR_SIGMA
) -> float:
    """Pearson correlation of blurred linear-light luminance of a render and a target.

    nan when either is flat. Invariant to contrast and brightness: ``a + b * target`` scores 1.

    Parameters
    ----------
    rendered, target : ndarray of shape (N, M, 3)
        sRGB in [0, 1].
    """
    return correlation(blurred_luminance(rendered, sigma), blurred_luminance(target, sigma))


def ghosting(
    rendered: ArrayLike, own: ArrayLike, other: ArrayLike, *, sigma: float = BLUR_SIGMA
) -> float:
    """How much of ``other`` shows in ``rendered`` beyond what its ``own`` target explains.

    The blurred luminance of ``rendered`` is fitted as ``alpha + beta * own`` by least squares;
    the result is the correlation of the residual with ``other`` (nan when undefined).
    """
    return residual_correlation(
        blurred_luminance(rendered, sigma),
        blurred_luminance(own, sigma),
        blurred_luminance(other, sigma),
    )


def residual_correlation(
    g: NDArray[np.float64], o: NDArray[np.float64], x: NDArray[np.float64]
) -> float:
    """:func:`ghosting` on blurred luminances: ``g`` fitted on ``o``, the residual against ``x``."""
    g, o = g.ravel(), o.ravel()
    design = np.stack([np.ones_like(o), o], axis=1)
    coef, *_ = np.linalg.lstsq(design, g, rcond=None)
    return correlation(g - design @ coef, x)


def picture_scores(
    renders: dict[str, NDArray[np.float64]],
    target_a: ArrayLike,
    target_b: ArrayLike,
    *,
    double: bool,
    sigma: float = BLUR_SIGMA,
) -> dict[str, float | None]:
    """Readability, ghosting and head-on visibility of a pattern's renders, as result fields.

    The same numbers as :func:`render_correlation` and :func:`ghosting`, with each image's
    blurred luminance computed once instead of once per score.

    Parameters
    ----------
    renders : dict
        ``{"A", "B", "headon"}`` -> ndarray of shape (N, M, 3), as from :func:`angled_renders`.
    target_a, target_b : ndarray of shape (N, M, 3)
        The targets in yarn colours, sRGB in [0, 1].
    double : bool
        A double-view instance (ghosting is measured, head-on against both targets).

    Returns
    -------
    dict
        ``render_corr_a``, ``render_corr_b``, ``ghost_a``, ``ghost_b`` (None unless ``double``)
        and ``headon_visibility`` (None when every head-on correlation is nan).
    """
    ga, gb, gh = (blurred_luminance(renders[v], sigma) for v in ("A", "B", "headon"))
    ta, tb = blurred_luminance(target_a, sigma), blurred_luminance(target_b, sigma)
    head = [correlation(gh, t) for t in ((ta, tb) if double else (ta,))]
    return {
        "render_corr_a": correlation(ga, ta),
        "render_corr_b": correlation(gb, tb),
        "ghost_a": residual_correlation(ga, ta, tb) if double else None,
        "ghost_b": residual_correlation(gb, tb, ta) if double else None,
        "headon_visibility": max((abs(h) for h in head if h == h), default=None),
    }


#: The scale weights of MS-SSIM (Wang, Simoncelli and Bovik 2003), finest scale first.
MS_SSIM_WEIGHTS = (0.0448, 0.2856, 0.3001, 0.2363, 0.1333)


def multiscale_ssim(rendered: ArrayLike, target: ArrayLike, *, sigma: float = BLUR_SIGMA) -> float:
    """Multi-scale SSIM of a render against a target, both blurred by ``sigma`` units first.

    Both images are blurred in linear light (:func:`blur_image`), then compared in CIELAB
    (scaled to about [-1, 1]) by scikit-image's ``structural_similarity`` (7 x 7 window, the
    mean over the colour channels) at each scale, halving the resolution (a 2 x 2 mean in linear
    light) between scales while the picture is at least 7 pixels on a side; the scales' SSIMs
    are averaged with :data:`MS_SSIM_WEIGHTS` (renormalised over the scales that fit).
    1 is identical; nan when the images are under 7 pixels on a side.

    Parameters
    ----------
    rendered, target : ndarray of shape (N, M, 3)
        sRGB in [0, 1].
    """
    from skimage.color import rgb2lab
    from skimage.metrics import structural_similarity
    from skimage.transform import downscale_local_mean

    a = linear_from_srgb(blur_image(rendered, sigma=sigma) * 255.0)
    b = linear_from_srgb(blur_image(target, sigma=sigma) * 255.0)
    if a.shape != b.shape:
        raise ValueError(f"render shape {a.shape} differs from target {b.shape}")
    values = []
    for _ in MS_SSIM_WEIGHTS:
        if min(a.shape[:2]) < 7:
            break
        la, lb = (rgb2lab(srgb_from_linear(x) / 255.0) / 100.0 for x in (a, b))
        values.append(structural_similarity(la, lb, data_range=2.0, win_size=7, channel_axis=2))
        a, b = (downscale_local_mean(x, (2, 2, 1)) for x in (a, b))
    if not values:
        return float("nan")
    w = np.asarray(MS_SSIM_WEIGHTS[: len(values)])
    return float(np.dot(w / w.sum(), values))


def _to_units(img: NDArray[np.float64], shape: tuple[int, int]) -> NDArray[np.float64]:
    if img.shape[:2] == shape:
        return img
    from skimage.transform import resize

    return np.clip(resize(img, (*shape, 3), order=1, anti_aliasing=True, mode="edge"), 0.0, 1.0)


def angled_renders(
    pattern: LogicalPattern, *, angle: float = RENDER_ANGLE, params: Any = None
) -> tuple[dict[str, NDArray[np.float64]], str]:
    """Renders of both sides at ``angle``, one pixel per unit, and the renderer's name.

    Uses :func:`illuknit.design.render.render_views` (illuknit's own renderer: always there),
    with ``params`` (a :class:`~illuknit.design.render.params.RenderParams`; default ones when
    None), e.g. the tall bump height or a measured split share.

    Returns
    -------
    (dict, str)
        ``{"A": (N, M, 3), "B": (N, M, 3), "headon": (N, M, 3)}`` float sRGB in [0, 1], and the
        renderer's name, e.g. ``"angled@30"``.
    """
    from illuknit.design.render import render_views

    views = render_views(pattern, angle=angle, params=params)
    out = {}
    for v in ("A", "B", "headon"):
        raw = np.asarray(views[v])
        img = raw.astype(np.float64)
        if np.issubdtype(raw.dtype, np.integer):  # uint8 sRGB renders
            img = img / 255.0
        out[v] = _to_units(img, pattern.shape)
    return out, f"angled@{angle:g}"


def color_changes(pattern: LogicalPattern) -> dict[str, float]:
    """Colour changes and distinct yarns per course (pattern row).

    Returns
    -------
    dict
        ``changes_mean``, ``changes_max``, ``yarns_per_course_mean``, ``yarns_per_course_max``.

    Examples
    --------
    >>> from illuknit.core.pattern import parse_yarns
    >>> p = LogicalPattern([[0, 1, 1, 0], [0, 0, 0, 0]], [[0] * 4] * 2, parse_yarns("black,white"))
    >>> color_changes(p)["changes_mean"]
    1.0
    """
    c = pattern.yarn
    changes = (c[:, 1:] != c[:, :-1]).sum(axis=1) if c.shape[1] > 1 else np.zeros(c.shape[0])
    k = len(pattern.yarns)
    per_row = (np.stack([(c == y).any(axis=1) for y in range(k)], axis=1)).sum(axis=1)
    return {
        "changes_mean": float(np.mean(changes)),
        "changes_max": float(np.max(changes)),
        "yarns_per_course_mean": float(np.mean(per_row)),
        "yarns_per_course_max": float(np.max(per_row)),
    }
