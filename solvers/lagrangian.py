"""A Lagrangian lower bound for the knit-aware model (b): the machine-pass terms kept, the rows
and the wales solved apart.

The per-wale DP (:mod:`illuknit.solvers.dp`) bounds model (b) by dropping every term that
couples the wales -- colour changes and the machine passes, which make up about a third of the
objective on photo pairs -- so its bound is weak there. The passes of unit row ``i`` are
``2 S + b (S + 1)`` with ``S`` the row's carrier segments (yarns used plus extra carriers) and
``b`` whether the row has a bump (:func:`illuknit.design.models.illusion_problem.row_passes`). Cut the row into
blocks of ``float_gap + 1`` units: a yarn used in two blocks with a whole unused block between
them needs an extra carrier there, so ``S`` is at least the number of **runs of used blocks**
summed over the yarns. The row-wide "or"s behind those runs and behind ``b`` are what couple the
wales:

    z[i, t, k] >= x[i, j, k]  (unit (i, j) of block t in yarn k),   bump[i] >= r[i, j]  (raised).

Relaxing exactly these with multipliers ``lam[i, j, k] >= 0`` and ``mu[i, j] >= 0`` splits the
model into

* **wales**: the per-wale chains of the DP with the extra unary cost ``lam[i, j, yarn] +
  mu[i, j] * raised`` on each unit -- every view and transfer term exact, colour changes
  (non-negative) dropped;
* **rows**: per row and bump flag ``b``, each yarn's block pattern ``z`` minimises
  ``machine_pass (2 + b) runs(z) - sum_t z[t] sum_(j in t) lam[i, j, k]`` by a shortest path
  over the blocks (a row uses at least one yarn), plus ``b (machine_pass - sum_j mu[i, j])``.

For any non-negative multipliers the sum of both minima is a lower bound of the optimum (weak
duality: a feasible pattern satisfies the relaxed inequalities, so their penalty is never
positive; the extra carriers the runs do not see are non-negative). With zero multipliers it is the DP bound plus two passes per row (the trivial
additive bound); subgradient ascent (Polyak steps towards the best pattern found) raises it.
Every wale solution is itself a pattern, so each step also yields an upper bound.
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


_BIG = 1e18


def _runs_dp(
    lam_blocks: NDArray[np.float64], c: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64], NDArray[np.int64]]:
    """Per (row, yarn): the least ``c * runs(z) - sum_t lam_blocks[t] * z[t]`` over block
    patterns ``z`` (any, and with at least one block used), and the minimising patterns.

    ``lam_blocks`` has shape (L, T); returns (best (L,), best with a use (L,), z (L, T), z with a
    use (L, T)). States per block: 0 nothing used yet, 1 used before but not here, 2 used here.
    """
    el, tc = lam_blocks.shape
    # pair[s', s]: the cost of moving from state s' to s (a run starts when entering 2 from 0/1)
    pair = np.array([[0.0, _BIG, c], [_BIG, 0.0, c], [_BIG, 0.0, 0.0]], dtype=np.float64)
    v = np.empty((el, 3))
    v[:, 0], v[:, 1], v[:, 2] = 0.0, _BIG, c - lam_blocks[:, 0]
    back = np.zeros((tc, el, 3), dtype=np.int64)
    for t in range(1, tc):
        tot = v[:, :, None] + pair[None]  # (L, S', S)
        back[t] = tot.argmin(axis=1)
        v = tot.min(axis=1)
        v[:, 2] -= lam_blocks[:, t]
    rows = np.arange(el)

    def trace(end: NDArray[np.int64]) -> NDArray[np.int64]:
        z = np.zeros((el, tc), dtype=np.int64)
        st = end
        for t in range(tc - 1, -1, -1):
            z[:, t] = st == 2
            if t:
                st = back[t][rows, st]
        return z

    end0 = v.argmin(axis=1)
    end1 = 1 + v[:, 1:].argmin(axis=1)
    return v[rows, end0], v[rows, end1], trace(end0), trace(end1)


def _rows(
    lam_blocks: NDArray[np.float64], mu_row: NDArray[np.float64], wp: int
) -> tuple[float, NDArray[np.int64], NDArray[np.int64]]:
    """The row subproblem: its least total, the chosen block patterns z (N, T, K) and bumps (N,).

    A row with bump flag b and ``runs_k`` runs of used blocks per yarn k costs ``wp * ((2 + b)
    * sum_k runs_k + b)`` passes at least (every run is a carrier segment: a yarn's first, or an
    extra carrier after a gap of a whole block), less the multipliers' prices.
    """
    n, tc, k = lam_blocks.shape
    flat = lam_blocks.transpose(0, 2, 1).reshape(n * k, tc)
    totals, zs = [], []
    for b in (0, 1):
        best0, best1, z0, z1 = _runs_dp(flat, float(wp * (2 + b)))
        best0, best1 = best0.reshape(n, k), best1.reshape(n, k)
        z0, z1 = z0.reshape(n, k, tc), z1.reshape(n, k, tc)
        # a row is knit: at least one yarn has a run (free when the optimum already uses one)
        force = (best1 - best0).argmin(axis=1)
        extra = (best1 - best0)[np.arange(n), force]
        z = z0.copy()
        z[np.arange(n), force] = z1[np.arange(n), force]
        totals.append(best0.sum(axis=1) + extra + b * (wp - mu_row))
        zs.append(z)
    pick = (totals[1] < totals[0]).astype(np.int64)
    total = float(np.where(pick == 1, totals[1], totals[0]).sum())
    z = np.where(pick[:, None, None] == 1, zs[1], zs[0])  # (N, K, T)
    return total, z.transpose(0, 2, 1), pick


def additive_bound(problem: IllusionProblem) -> int:
    """The DP bound plus two passes (one carrier segment) per unit row: every row is knit."""
    from illuknit.solvers.dp import solve_dp

    _, _, dp = solve_dp(problem)
    return int(dp) + 2 * problem.pass_weight * problem.shape[0]


def lagrangian_bound(
    problem: IllusionProblem,
    *,
    time_limit: float = 10.0,
    upper: int | None = None,
    max_iterations: int = 100_000,
    progress: ProgressCallback | None = None,
    theta0: float = 2.0,
    patience: int = 20,
    target_gap: float = 1.0,
) -> LagrangianResult:
    """The Lagrangian lower bound of ``problem`` (see the module docstring) after subgradient
    ascent for at most ``time_limit`` seconds; ``upper`` is a known pattern's cost (it steers
    the steps; the best pattern met on the way is used when it is lower or not given).

    Valid for any illusion problem; for the per-wale models (no pass or colour terms) it is the
    DP optimum.
    """
    from illuknit.solvers.descent_blocks import pattern_cost

    t0 = time.perf_counter()
    n, m = problem.shape
    k = problem.n_yarns
    wp = problem.pass_weight
    wales = _Wales(problem)
    width = problem.weights.float_gap + 1  # a block: a whole float's length
    starts = np.arange(0, m, width)
    block_of = np.arange(m) // width
    lam = np.zeros((n, m, k))
    mu = np.zeros((n, m))
    best_bound = -math.inf
    best_pattern: tuple[NDArray[np.int64], NDArray[np.bool_], int] | None = None
    theta, since = theta0, 0
    it = 0
    while it < max_iterations:
        it += 1
        extra = lam[:, :, wales.cs] + mu[:, :, None] * wales.rs[None, None, :]
        value, states = wales.solve(extra)
        yarn, raised = states // 2, (states % 2).astype(bool)
        lam_blocks = np.add.reduceat(lam, starts, axis=1)  # (N, T, K)
        row_total, z, bump = _rows(lam_blocks, mu.sum(axis=1), wp)
        total = value + row_total
        bound = math.ceil(total - 1e-6)
        if bound > best_bound:
            best_bound, since = bound, 0
            if progress is not None:
                progress(ProgressEvent(time.perf_counter() - t0, None, float(bound)))
        else:
            since += 1
        candidates = [(yarn, raised)]
        if wp and it % 5 == 1:
            # the Lagrangian heuristic: the wales again, each unit kept to the yarns its row
            # choice priced in for its block (and flat where the row has no bump)
            allowed = z[:, block_of, :]  # (N, M, K)
            banned = (allowed[:, :, wales.cs] == 0) | (
                (bump[:, None, None] == 0) & wales.rs[None, None, :]
            )
            _, st2 = wales.solve(np.where(banned, float(_INF), 0.0) + extra)
            candidates.append((st2 // 2, (st2 % 2).astype(bool)))
        for cy, cr in candidates:
            cost = pattern_cost(problem, cy, cr)
            if best_pattern is None or cost < best_pattern[2]:
                best_pattern = (cy, cr, cost)
        assert best_pattern is not None
        target = best_pattern[2] if upper is None else min(upper, best_pattern[2])
        if not wp or best_bound >= target or time.perf_counter() - t0 >= time_limit:
            break
        onehot = (yarn[:, :, None] == np.arange(k)[None, None, :]).astype(np.float64)
        g_lam = onehot - z[:, block_of, :]  # x[i, j, k] - z[i, block of j, k]
        g_mu = raised.astype(np.float64) - bump[:, None]
        # a multiplier at zero with a negative subgradient stays at zero: project it out
        g_lam[(lam <= 0) & (g_lam < 0)] = 0.0
        g_mu[(mu <= 0) & (g_mu < 0)] = 0.0
        norm = float((g_lam**2).sum() + (g_mu**2).sum())
        if norm == 0:
            break  # the relaxed constraints hold: the wale solution is optimal
        if since >= patience:
            theta, since = theta / 2, 0
            if theta < 1e-4:
                break
        step = theta * max(1.0, target_gap * (target - total)) / norm
        lam = np.maximum(0.0, lam + step * g_lam)
        mu = np.maximum(0.0, mu + step * g_mu)
    assert best_pattern is not None
    return LagrangianResult(
        int(best_bound),
        best_pattern[0],
        best_pattern[1],
        int(best_pattern[2]),
        it,
        time.perf_counter() - t0,
    )
