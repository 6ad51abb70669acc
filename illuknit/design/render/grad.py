"""Vector-Jacobian product of the renderer, hand-written in numpy.

Why by hand rather than with an autodiff library: the renderer is a handful of piecewise-linear
operations (a running maximum, a ``max``, a cumulative sum, and sampling a piecewise-linear
integral at a uniform grid), and each has a short closed-form adjoint:

* image ``img_k = (F(p_{k+1}) - F(p_k)) / dp`` with ``F(p) = sum_t col_t |[x_t, x_{t+1}] ∩ [0, p]|``.
  Hence ``d/d col_t = H(x_{t+1}) - H(x_t)`` where ``H(x) = sum_k g_k |[p_k, p_{k+1}] ∩ [0, x]| / dp``
  is piecewise linear on the *uniform* pixel grid (no search needed), and
  ``d/d x_t = (col_{t-1} - col_t) . g_{k(x_t)} / dp`` with ``k(x)`` the pixel containing ``x``;
* ``D = max(e, C_prev)`` routes the gradient to whichever argument is larger;
* ``C = cummax(b)`` routes each ``C_i``'s gradient to the running arg-max (one ``bincount``);
* ``e = a + h cos``, ``b = e + L sin``.

So the backward pass costs about as much as the forward pass, uses no extra dependency, and the
same forward code (:func:`illuknit.design.render.raycast.render_soft` with ``return_tape=True``) serves
previews and optimisation. At kinks (ties between heights) the gradient is a valid one-sided
subgradient.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.errors import ImageInputError, OptionError
from illuknit.core.views import View
from illuknit.design.render.params import RenderParams
from illuknit.design.render.raycast import Tape, cumsum_rows, render_soft, take_rows

__all__ = ["render_value_and_grad", "render_vjp"]


def render_vjp(
    tape: Tape, grad_image: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Pull an image gradient back to heights and colours.

    Parameters
    ----------
    tape : Tape
        From ``render_soft(..., return_tape=True)``.
    grad_image : ndarray of shape (N * supersample, M, K)
        dLoss/dImage.

    Returns
    -------
    grad_heights : ndarray of shape (N, M)
    grad_colors : ndarray of shape (N, M, K)
    """
    g = np.asarray(grad_image, dtype=np.float64)
    x, segcol = tape.x, tape.segcol
    t2, m, k = segcol.shape
    n = t2 // 2
    if g.shape != (tape.n_pixels, m, k):
        raise OptionError(f"`grad_image` must have shape {(tape.n_pixels, m, k)}, got {g.shape}")
    if tape.view == "B":
        g = g[::-1]
    n_pix, dp = tape.n_pixels, tape.pixel

    # Pixel of each knot and the running integral H of the image gradient at the knot.
    pos = (x - tape.p0) / dp
    j = np.clip(np.floor(pos).astype(np.intp), 0, n_pix - 1)
    frac = np.clip(pos - j, 0.0, 1.0)
    cum = np.empty((n_pix + 1, m, k))
    cum[0] = 0.0
    cumsum_rows(g, cum[1:])
    gj = take_rows(g, j)  # (2N+1, M, K)
    h_at = take_rows(cum, j) + frac[..., None] * gj
    g_segcol = np.diff(h_at, axis=0)  # (2N, M, K)

    inside = (x >= tape.p0) & (pos < n_pix)
    dcol = np.empty((t2 + 1, m, k))
    dcol[0] = 0.0 - segcol[0]  # knot 0 is fixed at 0; its value is never used
    dcol[1:-1] = segcol[:-1] - segcol[1:]
    dcol[-1] = segcol[-1]
    g_x = np.where(inside, np.einsum("tmk,tmk->tm", dcol, gj) / dp, 0.0)

    g_d = g_x[1::2]
    g_c = g_x[2::2].copy()
    take_e = tape.e >= tape.cprev
    g_e = np.where(take_e, g_d, 0.0)
    g_cprev = np.where(take_e, 0.0, g_d)
    g_c[:-1] += g_cprev[1:]
    # C = cummax(b): each C_i's gradient goes to the b that attains it.
    c = tape.x[2::2]
    is_max = tape.b >= c
    arg = np.maximum.accumulate(np.where(is_max, np.arange(n)[:, None], 0), axis=0)
    flat = (arg * m + np.arange(m)[None, :]).ravel()
    g_b = np.bincount(flat, weights=g_c.ravel(), minlength=n * m).reshape(n, m)
    g_h: NDArray[np.float64] = np.asarray((g_e + g_b) * tape.cos, dtype=np.float64)
    g_col = tape.shading * g_segcol[0::2] + g_segcol[1::2]
    if tape.view == "B":
        g_h, g_col = g_h[::-1], g_col[::-1]
    return g_h, g_col


def render_value_and_grad(
    heights: ArrayLike,
    colors: ArrayLike,
    target: ArrayLike,
    *,
    params: RenderParams | None = None,
    view: View = "A",
    angle: float | None = None,
    supersample: int = 1,
) -> tuple[float, NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Mean squared error of a render against ``target`` and its gradient.

    Returns
    -------
    loss : float
    image : ndarray of shape (N * supersample, M, K)
    grad_heights : ndarray of shape (N, M)
    grad_colors : ndarray of shape (N, M, K)
    """
    img, tape = render_soft(
        heights,
        colors,
        params=params,
        view=view,
        angle=angle,
        supersample=supersample,
        return_tape=True,
    )
    t = np.asarray(target, dtype=np.float64)
    if t.ndim == 2:
        t = t[..., None]
    if t.shape != img.shape:
        raise ImageInputError(f"`target` must have shape {img.shape}, got {t.shape}")
    r = img - t
    loss = float(np.mean(r * r))
    gh, gc = render_vjp(tape, 2.0 * r / r.size)
    return loss, img, gh, gc
