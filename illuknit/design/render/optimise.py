"""Gradient-descent design of a double-view pattern through the renderer (paper section 8.3).

Variables (continuous, per unit of the N x M grid):

* ``z[i, j]``: raised logit; ``t = sigmoid(z / tau)`` is how raised the unit is and its height is
  ``flat_height + t (bump_height - flat_height)``;
* ``u[i, j, :]``: yarn logits; ``p = softmax(u / tau)`` are yarn probabilities and the unit's colour
  is ``p @ palette`` in linear light.

Objective (minimised with Adam)::

    MSE(render_A(theta), target_A) + MSE(render_B(theta), target_B)
      + binary_weight(step) * mean(t (1 - t) + 1 - |p|^2)       # push towards a binary design
      + change_weight * mean(P[yarn differs from the next unit of the course])

Renders and targets are linear-light RGB. Annealing lowers the temperature ``tau`` geometrically
from 1 to ``final_temperature`` and ramps the binariness weight from 0 up to ``binary_weight``,
so the design starts smooth and ends close to binary. Finally ``raised = t > 1/2`` and
``yarn = argmax p`` give a :class:`~illuknit.core.pattern.LogicalPattern`.

The report compares the soft design with the binarised pattern: objective, render error (mean
over the two views of the MSE of the render against the target, linear light in [0, 1]) and logical error (fraction of cells whose seen yarn differs
from the target yarn; for the soft design, its expectation when each unit is independently raised
with probability ``t`` and of yarn ``k`` with probability ``p_k``).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.arguments import (
    check_callable,
    check_instance,
)
from illuknit.core.colors import lab_from_rgb, linear_from_srgb
from illuknit.core.errors import ImageInputError, OptionError, RenderParamsError, YarnSpecError
from illuknit.core.pattern import LogicalPattern, Yarn, check_yarns
from illuknit.core.views import View, can_see, logical_error
from illuknit.design.render.grad import render_value_and_grad
from illuknit.design.render.gradient_options import GradientOptions, gradient_options
from illuknit.design.render.params import RenderParams

__all__ = [
    "DesignResult",
    "DesignStep",
    "GradientOptions",
    "optimise_design",
    "targets_to_indices",
]


@dataclass(frozen=True)
class DesignStep:
    """Progress of one optimisation step (passed to the ``callback``)."""

    step: int
    loss: float
    render_error: float
    temperature: float
    elapsed: float


@dataclass(frozen=True, eq=False)
class DesignResult:
    """Outcome of :func:`optimise_design`.

    Attributes
    ----------
    pattern : LogicalPattern
        The binarised design.
    raised_soft : ndarray of shape (N, M)
        Final soft raisedness ``t`` in [0, 1].
    yarn_soft : ndarray of shape (N, M, K)
        Final yarn probabilities.
    history : ndarray of shape (steps,)
        Objective at every step.
    report : mapping
        ``before`` / ``after`` binarisation, each with ``loss``, ``render_error`` and
        ``logical_error`` (and its A / B parts), plus ``steps`` and ``seconds``.
    """

    pattern: LogicalPattern
    raised_soft: NDArray[np.float64]
    yarn_soft: NDArray[np.float64]
    history: NDArray[np.float64]
    report: Any = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "report", MappingProxyType(dict(self.report)))


def targets_to_indices(
    target: ArrayLike, yarns: Sequence[Yarn], *, name: str = "target"
) -> NDArray[np.int16]:
    """A target as yarn indices: index images pass through (checked), RGB maps to the nearest yarn.

    Parameters
    ----------
    target : ndarray of shape (N, M) integer, or (N, M, 3) RGB (uint8 0..255 or float 0..1)
    """
    t = np.asarray(target)
    k = len(yarns)
    if t.ndim == 2:
        if not np.issubdtype(t.dtype, np.integer):
            raise ImageInputError(f"`{name}` as an index image must hold integers, got {t.dtype}")
        if t.size and (t.min() < 0 or t.max() >= k):
            raise ImageInputError(
                f"`{name}` yarn indices must lie in 0..{k - 1}, got {t.min()}..{t.max()}"
            )
        return t.astype(np.int16)
    rgb = _rgb255(t, name)
    pal = np.array([y.rgb for y in yarns], dtype=np.float64)
    d = ((lab_from_rgb(rgb)[:, :, None, :] - lab_from_rgb(pal)[None, None]) ** 2).sum(-1)
    return np.argmin(d, axis=-1).astype(np.int16)


def _rgb255(t: NDArray[Any], name: str) -> NDArray[np.float64]:
    if t.ndim != 3 or t.shape[2] != 3:
        raise ImageInputError(f"`{name}` must have shape (N, M) or (N, M, 3), got {t.shape}")
    if np.issubdtype(t.dtype, np.integer):
        return t.astype(np.float64)
    f = t.astype(np.float64)
    if not np.all(np.isfinite(f)) or f.min() < 0 or f.max() > 1:
        raise ImageInputError(f"`{name}` float RGB must lie in [0, 1]")
    return f * 255.0


def _target_linear(
    t: NDArray[Any], palette_lin: NDArray[np.float64], name: str
) -> NDArray[np.float64]:
    if t.ndim == 2:
        return palette_lin[t]
    return linear_from_srgb(_rgb255(t, name))


def _softmax(u: NDArray[np.float64]) -> NDArray[np.float64]:
    e = np.exp(u - u.max(axis=-1, keepdims=True))
    return e / e.sum(axis=-1, keepdims=True)


def _sigmoid(z: NDArray[np.float64]) -> NDArray[np.float64]:
    return 0.5 * (1.0 + np.tanh(0.5 * z))


def _expected_logical_error(
    t: NDArray[np.float64], p: NDArray[np.float64], ia: NDArray[np.int16], ib: NDArray[np.int16]
) -> tuple[float, float]:
    """Expected can_see mismatch of a soft design, units independent."""
    n, m = t.shape
    rows, cols = np.indices((n, m))
    hit = p[rows, cols, ia]  # P(unit i has yarn target_A[i])
    prev = np.zeros((n, m))
    prev[1:] = p[rows[:-1], cols[:-1], ia[1:]]
    ok_a = hit.copy()
    ok_a[1:] = t[:-1] * prev[1:] + (1 - t[:-1]) * hit[1:]
    hit_b = p[rows, cols, ib]
    nxt = p[rows[1:], cols[1:], ib[:-1]]
    ok_b = hit_b.copy()
    ok_b[:-1] = t[1:] * nxt + (1 - t[1:]) * hit_b[:-1]
    return float(1 - ok_a.mean()), float(1 - ok_b.mean())


class _Objective:
    """Value and gradient of the design objective with respect to the logits (z, u)."""

    def __init__(self, ta, tb, palette_lin, params, change_weight, raised_weight):
        self.ta, self.tb = ta, tb
        self.pal = palette_lin
        self.params = params
        self.change_weight = change_weight
        self.raised_weight = raised_weight

    def __call__(self, z, u, tau, bin_w):
        prm = self.params
        t = _sigmoid(z / tau)
        p = _softmax(u / tau)
        h = prm.flat_height + t * prm.relief
        col = p @ self.pal
        g_h = np.zeros_like(h)
        g_col = np.zeros_like(col)
        render_err = 0.0
        views: tuple[tuple[View, NDArray[np.float64]], ...] = (("A", self.ta), ("B", self.tb))
        for view, tgt in views:
            mse, _, gh, gc = render_value_and_grad(h, col, tgt, params=prm, view=view)
            render_err += 0.5 * mse
            g_h += gh
            g_col += gc
        loss = 2.0 * render_err
        g_t = g_h * prm.relief
        g_p = g_col @ self.pal.T
        if bin_w > 0:
            loss += bin_w * float(np.mean(t * (1 - t)) + np.mean(1 - (p * p).sum(-1)))
            g_t += bin_w * (1 - 2 * t) / t.size
            g_p += bin_w * (-2 * p) / (p.size / p.shape[-1])
        if self.raised_weight > 0:
            loss += self.raised_weight * float(np.mean(t))
            g_t += self.raised_weight / t.size
        if self.change_weight > 0 and p.shape[1] > 1:
            same = (p[:, 1:] * p[:, :-1]).sum(-1)
            loss += self.change_weight * float(np.mean(1 - same))
            c = -self.change_weight / same.size
            g_p[:, 1:] += c * p[:, :-1]
            g_p[:, :-1] += c * p[:, 1:]
        g_z = g_t * t * (1 - t) / tau
        g_u = p * (g_p - (p * g_p).sum(-1, keepdims=True)) / tau
        return loss, render_err, g_z, g_u, t, p


def optimise_design(
    target_a: ArrayLike,
    target_b: ArrayLike,
    yarns: Sequence[Yarn],
    *,
    params: RenderParams | None = None,
    options: GradientOptions | None = None,
    pinned: ArrayLike | None = None,
    callback: Callable[[DesignStep], None] | None = None,
    **knobs: Any,
) -> DesignResult:
    """Optimise soft heights and yarns so renders at ±theta match two targets, then binarise.

    Parameters
    ----------
    target_a, target_b : ndarray of shape (N, M) (yarn indices) or (N, M, 3) (RGB)
        What view A (from above) and view B (from below) should show.
    yarns : sequence of Yarn
        The palette (at least two yarns).
    params : RenderParams, optional
        Geometry and the viewing angle ``theta``.
    options : GradientOptions, optional
        How to optimise (steps, learning rate, weights, annealing, ``mix``, seed, time limit;
        defaults: ``GradientOptions()``).
    pinned : ndarray of shape (N, M), int, optional
        Yarn fixed per unit, -1 where free.
    callback : callable, optional
        Called with a :class:`DesignStep` after every step.
    **knobs
        Shorthand for fields of ``options`` (``optimise_design(a, b, yarns, steps=50)`` is
        ``optimise_design(a, b, yarns, options=GradientOptions(steps=50))``); they replace
        those fields of ``options`` when both are given.

    Returns
    -------
    DesignResult
    """
    ta_raw, tb_raw = np.asarray(target_a), np.asarray(target_b)
    yarns, params = _checked_arguments(yarns, params, shapes=(ta_raw.shape, tb_raw.shape))
    opts = gradient_options(options, knobs)
    check_callable(callback, "callback")
    ia, ib, ta, tb, pal_lin, pin = _prepared_targets(
        ta_raw, tb_raw, yarns, mix=opts.mix, pinned=pinned
    )
    objective = _Objective(ta, tb, pal_lin, params, opts.change_weight, opts.raised_weight)
    z, u, fixed = _initial_logits(ia, ib, len(yarns), pin, seed=opts.seed)
    start = time.perf_counter()
    history, tau = _descend(
        objective, z, u, fixed=fixed, options=opts, callback=callback, start=start
    )
    meta = {
        "method": "gradient",
        "steps": len(history),
        "theta": params.theta,
        "binary_weight": opts.binary_weight,
        "change_weight": opts.change_weight,
        "raised_weight": opts.raised_weight,
        "mix": opts.mix,
        "seed": opts.seed,
    }
    soft = (z, u, tau)
    return _binarised(objective, soft, opts.binary_weight, (ia, ib), yarns, meta, history, start)


def _checked_arguments(
    yarns: Sequence[Yarn],
    params: RenderParams | None,
    *,
    shapes: tuple[tuple[int, ...], tuple[int, ...]],
) -> tuple[tuple[Yarn, ...], RenderParams]:
    """Check :func:`optimise_design`'s yarns, render parameters and target shapes (a library
    error naming each); the yarns as a tuple and the render parameters (the defaults when None)."""
    check_yarns(yarns)
    if params is not None:
        check_instance(params, RenderParams, "params", error=RenderParamsError)
    yarns = tuple(yarns)
    if len(yarns) < 2 or not all(isinstance(y, Yarn) for y in yarns):
        raise YarnSpecError("`yarns` must be a sequence of at least two Yarn")
    sa, sb = shapes
    if sa[:2] != sb[:2] or len(sa) < 2:
        raise ImageInputError(
            f"`target_a` and `target_b` must have the same (N, M) shape, got {sa} and {sb}"
        )
    return yarns, RenderParams() if params is None else params


def _binarised(
    objective: _Objective,
    soft: tuple[NDArray[np.float64], NDArray[np.float64], float],
    binary_weight: float,
    targets: tuple[NDArray[Any], NDArray[Any]],
    yarns: tuple[Yarn, ...],
    meta: dict[str, Any],
    history: list[float],
    start: float,
) -> DesignResult:
    """The soft design (logits ``z``, ``u`` at temperature ``tau``) rounded to a pattern, and
    both scored by the same objective."""
    z, u, tau = soft
    ia, ib = targets
    k = len(yarns)
    loss, render_err, _, _, t, p = objective(z, u, tau, binary_weight)
    la, lb = _expected_logical_error(t, p, ia, ib)
    raised = t > 0.5
    yarn = np.argmax(p, axis=-1).astype(np.int16)
    # Evaluate the binary design with the same objective: logits at +-inf are t, p in {0, 1}.
    loss_b, render_b, _, _, _, _ = objective(
        np.where(raised, 50.0, -50.0),
        np.where(np.arange(k) == yarn[..., None], 50.0, -50.0),
        1.0,
        binary_weight,
    )
    pattern = LogicalPattern(yarn, raised, yarns, meta=meta)
    ea = logical_error(can_see(pattern, "A"), ia)
    eb = logical_error(can_see(pattern, "B"), ib)
    report = {
        "steps": len(history),
        "seconds": round(time.perf_counter() - start, 3),
        "before": _errors(loss, render_err, la, lb),
        "after": _errors(loss_b, render_b, ea, eb),
    }
    return DesignResult(pattern, t, p, np.asarray(history), report)


def _prepared_targets(
    ta_raw: NDArray[Any],
    tb_raw: NDArray[Any],
    yarns: tuple[Yarn, ...],
    *,
    mix: str,
    pinned: ArrayLike | None,
) -> tuple[
    NDArray[np.int16],
    NDArray[np.int16],
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[Any] | None,
]:
    """Target yarn indices, targets and palette in the space ``mix`` renders in, and the
    checked ``pinned`` array: ``(ia, ib, ta, tb, palette, pin)``."""
    ia = targets_to_indices(ta_raw, yarns, name="target_a")
    ib = targets_to_indices(tb_raw, yarns, name="target_b")
    n, m = ia.shape
    k = len(yarns)
    if mix == "rgb":
        pal_lin = linear_from_srgb(np.array([y.rgb for y in yarns], dtype=np.float64))
        ta = _target_linear(ta_raw, pal_lin, "target_a")
        tb = _target_linear(tb_raw, pal_lin, "target_b")
    elif mix == "yarn":
        pal_lin = np.eye(k)
        ta, tb = pal_lin[ia], pal_lin[ib]
    else:
        raise OptionError(f"`mix` must be 'rgb' or 'yarn', got {mix!r}")
    pin = None
    if pinned is not None:
        pin = np.asarray(pinned)
        if pin.shape != (n, m) or not np.issubdtype(pin.dtype, np.integer):
            raise OptionError(f"`pinned` must be an int array of shape {(n, m)}")
        if pin.min() < -1 or pin.max() >= k:
            raise OptionError(f"`pinned` values must lie in -1..{k - 1}")
    return ia, ib, ta, tb, pal_lin, pin


def _initial_logits(
    ia: NDArray[np.int16], ib: NDArray[np.int16], k: int, pin: NDArray[Any] | None, *, seed: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_] | None]:
    """Small random logits ``(z, u)``, yarns leaning to the targets', and the pinned mask."""
    n, m = ia.shape
    rng = np.random.default_rng(seed)
    z = rng.normal(0.0, 0.1, (n, m))
    # Start each unit leaning towards the yarns its two targets ask for.
    u = rng.normal(0.0, 0.1, (n, m, k))
    rows, cols = np.indices((n, m))
    u[rows, cols, ia] += 0.5
    u[rows, cols, ib] += 0.5
    fixed = None
    if pin is not None:
        # Pinned units keep their yarn: saturated logits whose gradient is masked below.
        fixed = pin >= 0
        u[fixed] = np.where(np.arange(k) == pin[fixed][:, None], 30.0, -30.0)
    return z, u, fixed


def _descend(
    objective: _Objective,
    z: NDArray[np.float64],
    u: NDArray[np.float64],
    *,
    fixed: NDArray[np.bool_] | None,
    options: GradientOptions,
    callback: Callable[[DesignStep], None] | None,
    start: float,
) -> tuple[list[float], float]:
    """Anneal and run Adam on the logits ``z`` and ``u`` (updated in place), as ``options`` say
    (steps, learning rate, binariness weight, final temperature, time limit).

    Returns the objective at every step and the last temperature. ``fixed`` units' yarn logits
    keep their values (their gradient is masked).
    """
    steps, learning_rate = options.steps, options.learning_rate
    binary_weight, final_temperature = options.binary_weight, options.final_temperature
    time_limit = options.time_limit
    params_vec = [z, u]
    mom = [np.zeros_like(z), np.zeros_like(u)]
    vel = [np.zeros_like(z), np.zeros_like(u)]
    b1, b2, eps = 0.9, 0.999, 1e-8
    history = []
    tau = 1.0
    for step in range(steps):
        frac = step / max(1, steps - 1)
        tau = final_temperature**frac
        loss, render_err, g_z, g_u, _, _ = objective(z, u, tau, binary_weight * frac)
        if fixed is not None:
            g_u[fixed] = 0.0
        history.append(loss)
        for i, g in enumerate((g_z, g_u)):
            mom[i] = b1 * mom[i] + (1 - b1) * g
            vel[i] = b2 * vel[i] + (1 - b2) * g * g
            mhat = mom[i] / (1 - b1 ** (step + 1))
            vhat = vel[i] / (1 - b2 ** (step + 1))
            params_vec[i] -= learning_rate * mhat / (np.sqrt(vhat) + eps)
        elapsed = time.perf_counter() - start
        if callback is not None:
            callback(DesignStep(step, loss, render_err, tau, elapsed))
        if time_limit is not None and elapsed > time_limit:
            break
    return history, tau


def _errors(loss: float, render_error: float, la: float, lb: float) -> dict[str, float]:
    """A report entry: objective, render error and logical error (mean and per view)."""
    return {
        "loss": loss,
        "render_error": render_error,
        "logical_error": (la + lb) / 2,
        "logical_error_a": la,
        "logical_error_b": lb,
    }
