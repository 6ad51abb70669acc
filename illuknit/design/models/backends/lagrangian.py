"""A Lagrangian lower bound for the knit-aware model (b): the machine-pass terms kept, the rows'
choices made jointly, the wale chains cut between consecutive rows.

The per-wale DP (:mod:`illuknit.design.models.backends.dp`) bounds model (b) by dropping every term that
couples the wales -- colour changes and the machine passes, which make up about a third of the
objective on photo pairs -- so its bound is weak there. The passes of unit row ``i`` are
``2 S + b (S + 1)`` with ``S`` the row's carrier segments (at least its yarns used) and ``b``
whether the row has a bump (:func:`illuknit.design.models.illusion_problem.row_passes`). Call a
row's **option** ``d = (Y, b)``: the set of yarns ``Y`` it may use and whether it may have
bumps (``2 (2^K - 1)`` options, 14 for three yarns); a pattern whose row ``i`` keeps to option
``d`` pays at least ``P(d) = machine_pass ((2 + b) |Y| + b)`` passes there (extra carriers and
colour changes, non-negative, dropped).

Every other term lies on one wale: view cells and bed changes are costs of a unit's state
``s = (yarn, raised)`` and of the states of vertically neighbouring units. Write each wale's
chain as a sum over **consecutive row pairs** ``(i-1, i)``: the pair term plus half of each
unit's own cost (all of it for the first and last rows). Given the rows' options, each pair is
minimised on its own -- unit ``(i, j)`` may take one state in pair ``(i-1, i)`` and another in
pair ``(i, i+1)`` -- so the least total over the options is a **chain over the rows**:

    min over d_0..d_(N-1) of  sum_i P(d_i) + sum_i Phi_i(d_(i-1), d_i),
    Phi_i(d', d) = sum_j min over s' allowed by d', s allowed by d of theta_ij(s', s),

solved exactly by a DP over 14 options per row. Relaxing only the agreement of a unit's two
copies, with multipliers ``lam[i, j, s]`` added to its state in one pair and subtracted in the
other, this is a lower bound for every ``lam`` (weak duality); subgradient ascent (Polyak
steps towards the best pattern found, starting from the multipliers that the wale DP's forward
messages give, at which the relaxation is already at least the DP bound plus each row's
cheapest option) raises it. Because the rows' options stay integral, it is
much stronger than relaxing "yarn used" row by row: on three-yarn photo crops it proved the
optimum at 10 x 10 units, was 0.8 % under it at 12 x 12 and 1.5 % under the best pattern at
14 x 14 (docs/solvers-bench.md).

Each step also yields a pattern: the wales solved exactly with every unit kept to its row's
chosen option. The result's bound is never below the additive bound (the DP plus two passes a
row).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from illuknit.design.models.illusion_problem import IllusionProblem, raised_cost
from illuknit.solvers.base import ProgressCallback, ProgressEvent

__all__ = ["LagrangianResult", "additive_bound", "lagrangian_bound"]

_INF = np.int64(1) << np.int64(40)


@dataclass(frozen=True)
class LagrangianResult:
    """The best bound (an integer: the objective is), the best pattern met on the way and its
    cost, the number of subgradient steps and the seconds taken."""

    bound: int
    yarn: NDArray[np.int64]
    raised: NDArray[np.bool_]
    cost: int
    iterations: int
    seconds: float


class _Wales:
    """The wale subproblem: unary and pairwise costs of the per-wale chains, precomputed."""

    def __init__(self, problem: IllusionProblem) -> None:
        n, m = problem.shape
        k = problem.n_yarns
        self.n, self.m, self.k = n, m, k
        s = np.arange(2 * k)
        self.cs, self.rs = s // 2, (s % 2).astype(bool)
        cs, rs = self.cs, self.rs
        a = problem.target_a.astype(np.int64)
        b = problem.target_b.astype(np.int64)
        wv = problem.view_weight
        u = np.zeros((n, m, 2 * k), dtype=np.int64)
        u[0] += wv * (cs[None, :] != a[0][:, None])
        u[n - 1] += wv * (cs[None, :] != b[n - 1][:, None])
        u += raised_cost(n, m, problem.transfer_weight)[:, :, None] * rs[None, None, :]
        if problem.pinned is not None:
            p = problem.pinned.astype(np.int64)
            u[(p[:, :, None] >= 0) & (cs[None, None, :] != p[:, :, None])] += _INF
        self.unary = u
        seen_a = np.where(rs[:, None], cs[:, None], cs[None, :])  # (S', S)
        seen_b = np.where(rs[None, :], cs[None, :], cs[:, None])
        self.pair = np.zeros((n, m, 2 * k, 2 * k), dtype=np.int64)
        for i in range(1, n):
            self.pair[i] = wv * (
                (seen_a[None] != a[i][:, None, None]).astype(np.int64)
                + (seen_b[None] != b[i - 1][:, None, None])
            )

    def forward(self) -> NDArray[np.float64]:
        """(N, M, 2K): per unit and state, the least cost of its wale's chain from the first
        row down to it (the DP's forward messages, unary costs only)."""
        f = np.empty(self.unary.shape, dtype=np.float64)
        f[0] = self.unary[0]
        for i in range(1, self.n):
            f[i] = (f[i - 1][:, :, None] + self.pair[i]).min(axis=1) + self.unary[i]
        return f

    def solve(self, extra: NDArray[np.float64]) -> tuple[float, NDArray[np.int64]]:
        """(least total cost, states (N, M)) of all wales with unary costs ``extra`` added."""
        n, m = self.n, self.m
        u = self.unary + extra
        back = np.zeros((n, m, 2 * self.k), dtype=np.int64)
        v = u[0].copy()
        for i in range(1, n):
            tot = v[:, :, None] + self.pair[i]  # (M, S', S)
            back[i] = tot.argmin(axis=1)
            v = tot.min(axis=1) + u[i]
        cols = np.arange(m)
        states = np.empty((n, m), dtype=np.int64)
        states[n - 1] = v.argmin(axis=1)
        value = float(v[cols, states[n - 1]].sum())
        for i in range(n - 1, 0, -1):
            states[i - 1] = back[i][cols, states[i]]
        return value, states


def _option_min(x: NDArray[np.float64], k: int) -> NDArray[np.float64]:
    """``x`` (2K, ...) over the states ``2 * yarn + raised`` (first axis) -> (D, ...): per row
    option ``(mask - 1) * 2 + b`` (yarns of ``mask``, bumps allowed when ``b``), the least value
    over the states it allows. Subset minima built from smaller subsets, each a whole
    contiguous block: no masked copy of ``x``."""
    out = np.empty((2 * (2**k - 1), *x.shape[1:]), dtype=x.dtype)
    for mask in range(1, 2**k):
        low = mask & -mask
        y = low.bit_length() - 1
        flat, any_ = out[2 * (mask - 1)], out[2 * (mask - 1) + 1]
        if mask == low:
            flat[...] = x[2 * y]
            np.minimum(x[2 * y], x[2 * y + 1], out=any_)
        else:
            rest = 2 * ((mask ^ low) - 1)
            np.minimum(out[rest], x[2 * y], out=flat)
            np.minimum(out[rest + 1], x[2 * y], out=any_)
            np.minimum(any_, x[2 * y + 1], out=any_)
    return out


def _options(k: int, wp: int) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
    """(allowed states (D, 2K), passes cost P (D,)) of the row options, in ``_option_min``'s
    order."""
    allowed, cost = [], []
    for mask in range(1, 2**k):
        ys = [(mask >> y) & 1 for y in range(k)]
        for b in (0, 1):
            allowed.append([bool(ys[s // 2]) and s % 2 <= b for s in range(2 * k)])
            cost.append(wp * ((2 + b) * sum(ys) + b))
    return np.array(allowed, dtype=bool), np.array(cost, dtype=np.float64)


class _RowChain:
    """The relaxation of the module docstring for one problem: pair terms precomputed, every
    array state-major (the unit's state on the first axes) so that the subset minima run over
    contiguous blocks."""

    def __init__(self, problem: IllusionProblem, wales: _Wales) -> None:
        n = problem.shape[0]
        self.k = problem.n_yarns
        self.allowed, self.cost = _options(self.k, problem.pass_weight)
        self.penalty = np.where(self.allowed, 0.0, float(_INF))  # (D, 2K)
        u = np.moveaxis(wales.unary.astype(np.float64), 2, 0)  # (2K, N, M)
        share_down = np.full((1, n, 1), 0.5)  # of row i's own cost, into pair (i, i+1)
        share_down[0, 0] = 1.0
        share_up = 1.0 - share_down  # into pair (i-1, i)
        share_up[0, n - 1] = 1.0
        if n > 1:
            share_down[0, n - 1] = 0.0
        self.top = u[:, :-1] * share_down[:, :-1]  # row i-1's part of pair (i-1, i)
        self.bottom = u[:, 1:] * share_up[:, 1:]
        # pair[i][j, s', s] -> (2K lower s, 2K upper s', N-1, M)
        self.pair = np.ascontiguousarray(wales.pair[1:].astype(np.float64).transpose(3, 2, 0, 1))
        self.single = u[:, 0] if n == 1 else None

    def solve(
        self, lam: NDArray[np.float64]
    ) -> tuple[float, NDArray[np.int64], NDArray[np.float64] | None]:
        """(least total, options per row (N,), pair terms (2K lower, 2K upper, N-1, M) or None)
        for the multipliers ``lam`` (2K, N, M) (rows 0 and N-1 take none: they lie in one
        pair)."""
        if self.single is not None:  # one row: no pair, each unit alone
            per = _option_min(self.single, self.k).sum(axis=1) + self.cost
            return float(per.min()), np.array([int(per.argmin())]), None
        theta = self.pair + (self.bottom + lam[:, 1:])[:, None] + (self.top - lam[:, :-1])[None, :]
        lower = _option_min(theta, self.k)  # (D lower, 2K upper, N-1, M)
        both = _option_min(lower.swapaxes(0, 1), self.k)  # (D upper, D lower, N-1, M)
        phi = both.sum(axis=3).transpose(2, 0, 1)  # (N-1, D upper, D lower)
        n = phi.shape[0] + 1
        v = self.cost.copy()
        back = np.zeros((n, len(v)), dtype=np.int64)
        for i in range(1, n):
            tot = v[:, None] + phi[i - 1]
            back[i] = tot.argmin(axis=0)
            v = tot.min(axis=0) + self.cost
        d = np.empty(n, dtype=np.int64)
        d[-1] = int(v.argmin())
        for i in range(n - 1, 0, -1):
            d[i - 1] = back[i][d[i]]
        return float(v.min()), d, theta

    def subgradient(self, theta: NDArray[np.float64], d: NDArray[np.int64]) -> NDArray[np.float64]:
        """d total / d lam at the chosen options: a unit's state in its upper pair less its
        state in its lower pair (one-hot, (2K, N, M))."""
        s, _, n1, m = theta.shape
        masked = (
            theta
            + self.penalty[d[1:]].T[:, None, :, None]
            + self.penalty[d[:-1]].T[None, :, :, None]
        )
        flat = masked.reshape(s * s, n1, m).argmin(axis=0)
        lower_state, upper_state = flat // s, flat % s  # states of rows i and i-1 in pair i
        g = np.zeros((s, n1 + 1, m))
        rows, cols = np.ogrid[:n1, :m]
        g[:, 1:][lower_state, rows, cols] += 1.0  # unit (i, j) in pair (i-1, i): +lam
        g[:, :-1][upper_state, rows, cols] -= 1.0  # unit (i-1, j) in pair (i-1, i): -lam
        g[:, 0] = 0.0
        g[:, -1] = 0.0
        return g


def additive_bound(problem: IllusionProblem) -> int:
    """The DP bound plus two passes (one carrier segment) per unit row: every row is knit."""
    from illuknit.design.models.backends.dp import solve_dp

    _, _, dp = solve_dp(problem)
    return int(dp) + 2 * problem.pass_weight * problem.shape[0]


def lagrangian_bound(
    problem: IllusionProblem,
    *,
    time_limit: float = 10.0,
    upper: int | None = None,
    max_iterations: int = 100_000,
    progress: ProgressCallback | None = None,
    theta0: float = 1.0,
    patience: int = 20,
    heuristic_every: int = 3,
) -> LagrangianResult:
    """The Lagrangian lower bound of ``problem`` (see the module docstring) after subgradient
    ascent for at most ``time_limit`` seconds; ``upper`` is a known pattern's cost (it steers
    the steps; the best pattern met on the way is used when it is lower or not given). The
    step size halves after ``patience`` steps without a better bound; every
    ``heuristic_every`` steps the wales are solved within the rows' options for a pattern.

    Valid for any illusion problem; for the per-wale models (no pass or colour terms) it is the
    DP optimum.
    """
    from illuknit.design.models.backends.descent_blocks import pattern_cost

    t0 = time.perf_counter()
    n, m = problem.shape
    k = problem.n_yarns
    wales = _Wales(problem)
    chain = _RowChain(problem, wales)
    lam = np.zeros((2 * k, n, m))
    if n > 2 and problem.pinned is None:
        # start from the wale DP's forward messages: each pair term then has least value 0 but
        # the last, whose least is the DP optimum, so the first step is already at least the
        # additive bound (pins are left out: their huge costs would swamp the float sums)
        fwd = np.moveaxis(wales.forward(), 2, 0)
        lam[:, 1:-1] = 0.5 * np.moveaxis(wales.unary[1:-1], 2, 0) - fwd[:, 1:-1]
    best_bound = additive_bound(problem)
    if progress is not None:
        progress(ProgressEvent(time.perf_counter() - t0, None, float(best_bound)))
    best_pattern: tuple[NDArray[np.int64], NDArray[np.bool_], int] | None = None
    theta, since = theta0, 0
    it = 0
    while it < max_iterations:
        it += 1
        total, d, pair_terms = chain.solve(lam)
        bound = math.ceil(total - 1e-6)
        if bound > best_bound:
            best_bound, since = bound, 0
            if progress is not None:
                progress(ProgressEvent(time.perf_counter() - t0, None, float(bound)))
        else:
            since += 1
        if best_pattern is None or it % heuristic_every == 1 or pair_terms is None:
            # the wales solved exactly with every unit kept to its row's option: a pattern
            banned = ~chain.allowed[d]  # (N, 2K)
            _, st = wales.solve(np.where(banned[:, None, :], _INF, 0))
            cy, cr = st // 2, (st % 2).astype(bool)
            cost = pattern_cost(problem, cy, cr)
            if best_pattern is None or cost < best_pattern[2]:
                best_pattern = (cy, cr, cost)
        assert best_pattern is not None
        target = best_pattern[2] if upper is None else min(upper, best_pattern[2])
        if pair_terms is None or best_bound >= target or time.perf_counter() - t0 >= time_limit:
            break
        g = chain.subgradient(pair_terms, d)
        norm = float((g**2).sum())
        if norm == 0:
            break  # every unit's two copies agree: the pattern is optimal for the relaxation
        if since >= patience:
            theta, since = theta / 2, 0
            if theta < 1e-4:
                break
        lam += (theta * max(1.0, target - total) / norm) * g
    assert best_pattern is not None
    return LagrangianResult(
        int(best_bound),
        best_pattern[0],
        best_pattern[1],
        int(best_pattern[2]),
        it,
        time.perf_counter() - t0,
    )
