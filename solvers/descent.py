"""Exact-block coordinate descent for the knit-time-aware illusion model (b).

The objective of model (b) (:mod:`illuknit.illusion_models`) is a sum of terms over *pairs of
units that are neighbours in the grid*:

* view A at row i and view B at row i-1 couple units (i-1, j) and (i, j) of one wale; a bump's
  knit<->purl changes are a cost of the unit alone;
* a colour change couples units (i, j) and (i, j+1) of one course.

So the grid is a 4-neighbour pairwise model over the 2K states ``(yarn, raised)`` of each unit,
and two kinds of *blocks* can be re-optimised **exactly** while the rest stays fixed:

* **a wale** (column j): with wales j-1 and j+1 fixed, their colours turn the colour-change terms
  into unary costs of wale j, which is then a chain — the per-wale shortest path of
  :mod:`illuknit.solvers.dp` with extra unary costs;
* **a course** (unit row i): with rows i-1 and i+1 fixed, every view term that involves row i
  becomes a unary cost of one of its units (e.g. view A at row i+1 sees ``C[i]`` if ``R[i]`` else
  the fixed ``C[i+1]``), and the colour changes along the row make it a chain over the columns.

Wales of one parity share no term (red-black order), so all even wales are re-optimised at once,
vectorised with numpy, then all odd wales, then even rows, then odd rows; each block update
returns the exact optimum of its block given the rest, so **no update increases the objective**.
Sweeps repeat until a whole sweep improves nothing (a local optimum under all wale and row
moves).

Around that local search, an iterated local search keeps the best pattern of several starts —
the DP optimum of the per-wale part (zero colour-change terms: the paper's MaxSAT optimum), a
row-majority start (each unit row in the colour most common in the two targets' row) — and of
perturbations of the incumbent (a random band of rows or block of wales repainted in its majority
colour, flat), each followed by descent; equal-cost results are accepted, so the search drifts on
plateaus. It stops at the time limit, or after ``stall`` perturbations without improvement.

The DP optimum of the per-wale part is also a valid **lower bound** (colour-change terms are
non-negative), reported as ``bound``. The backend is a heuristic (``exact = False``): status
``feasible`` (``timeout`` when the time limit stopped it), never ``optimal`` for a model with
colour-change terms. Per-wale models (no colour term) and the single-view model are solved
exactly by the DP instead. A hard colour-change cap per course is not handled.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from illuknit.illusion_problem import IllusionProblem, pass_events, raised_cost, row_passes
from illuknit.solvers.base import BackendBase, ProgressCallback, ProgressEvent, Solution, Status
from illuknit.solvers.dp import DPBackend, solve_dp, values_from_pattern

if TYPE_CHECKING:
    from illuknit.model import Model

__all__ = [
    "DescentBackend",
    "DescentResult",
    "descend",
    "optimise_descent",
    "pattern_cost",
    "update_rows",
    "update_wales",
]

_INF = np.int64(1) << np.int64(40)


# -- the objective --------------------------------------------------------------------------


def _unit_costs(problem: IllusionProblem) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """(bump cost per unit (N, M), pinned-yarn penalty (N, M, K)) of ``problem``."""
    n, m = problem.shape
    k = problem.n_yarns
    bump = raised_cost(n, m, problem.transfer_weight)
    pin = np.zeros((n, m, k), dtype=np.int64)
    if problem.pinned is not None:
        p = problem.pinned.astype(np.int64)
        pin[(p[:, :, None] >= 0) & (np.arange(k)[None, None, :] != p[:, :, None])] = _INF
    return bump, pin


def pattern_cost(
    problem: IllusionProblem, yarn: NDArray[np.integer], raised: NDArray[np.bool_]
) -> int:
    """Objective of model (b) (or (a)/(c)) for a (yarn, raised) grid, without the hard caps.

    Equals ``build_model(problem).evaluate(values)`` for every pattern that satisfies the hard
    constraints (a pinned unit in another yarn costs ``2**40``).
    """
    c = np.asarray(yarn, dtype=np.int64)
    r = np.asarray(raised, dtype=bool)
    a = problem.target_a
    b = problem.target_b
    va = c.copy()
    va[1:] = np.where(r[:-1], c[:-1], c[1:])
    vb = c.copy()
    vb[:-1] = np.where(r[1:], c[1:], c[:-1])
    bump, pin = _unit_costs(problem)
    n, m = c.shape
    ii, jj = np.indices((n, m))
    cost = problem.view_weight * (int((va != a).sum()) + int((vb != b).sum()))
    cost += int(bump[r].sum()) + int(pin[ii, jj, c].sum())
    cost += problem.color_weight * int((c[:, 1:] != c[:, :-1]).sum())
    if problem.pass_weight:
        passes = row_passes(c, r, problem.n_yarns, problem.weights.float_gap)
        cost += problem.pass_weight * int(passes.sum())
    return int(cost)


# -- exact block updates --------------------------------------------------------------------


def _chain_argmin(
    unary: NDArray[np.int64],
    pair: NDArray[np.int64] | None,
    pair_fn: Callable[[int], NDArray[np.int64]] | None = None,
) -> NDArray[np.int64]:
    """Min-cost state sequence of L independent chains.

    Parameters
    ----------
    unary : ndarray of shape (L, T, S)
    pair : ndarray broadcastable to (L, S', S), the same for every step, or None with
        ``pair_fn(t) -> (L, S', S)`` the cost between steps t-1 and t.

    Returns
    -------
    ndarray of shape (L, T), int64 — the states.
    """
    lc, tc, sc = unary.shape
    back = np.zeros((tc, lc, sc), dtype=np.int64)
    v = unary[:, 0].copy()
    for t in range(1, tc):
        p = pair_fn(t) if pair_fn is not None else pair
        assert p is not None
        tot = v[:, :, None] + p  # (L, S', S)
        back[t] = tot.argmin(axis=1)
        v = tot.min(axis=1) + unary[:, t]
    states = np.empty((lc, tc), dtype=np.int64)
    states[:, tc - 1] = v.argmin(axis=1)
    rows = np.arange(lc)
    for t in range(tc - 1, 0, -1):
        states[:, t - 1] = back[t][rows, states[:, t]]
    return states


def _state_parts(k: int) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    s = np.arange(2 * k)
    return s // 2, (s % 2).astype(bool)


def update_wales(
    problem: IllusionProblem,
    yarn: NDArray[np.int64],
    raised: NDArray[np.bool_],
    cols: NDArray[np.int64],
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """Re-optimise the wales ``cols`` exactly, all other wales fixed.

    ``cols`` must hold no two neighbouring wales (e.g. all even ones): their updates are then
    independent. Returns new (yarn, raised) arrays; the objective never increases.
    """
    n, m = problem.shape
    k = problem.n_yarns
    cs, rs = _state_parts(k)
    wv = problem.view_weight
    wc = problem.color_weight
    a = problem.target_a.astype(np.int64)[:, cols]  # (N, L)
    b = problem.target_b.astype(np.int64)[:, cols]
    bump, pin = _unit_costs(problem)
    u = np.zeros((len(cols), n, 2 * k), dtype=np.int64)
    u += bump[:, cols].T[:, :, None] * rs[None, None, :]
    u += pin[:, cols][:, :, cs].transpose(1, 0, 2)
    u[:, 0] += wv * (cs[None, :] != a[0][:, None])
    u[:, n - 1] += wv * (cs[None, :] != b[n - 1][:, None])
    if wc:
        for side in (-1, 1):
            nb = cols + side
            ok = (nb >= 0) & (nb < m)
            if ok.any():
                other = yarn[:, nb[ok]].T  # (L', N)
                u[ok] += wc * (cs[None, None, :] != other[:, :, None])
    if problem.pass_weight:
        u += _row_terms_outside(problem, yarn, raised, cols)
    seen_a = np.where(rs[:, None], cs[:, None], cs[None, :])  # (S', S)
    seen_b = np.where(rs[None, :], cs[None, :], cs[:, None])

    def pair(t: int) -> NDArray[np.int64]:
        return wv * (
            (seen_a[None] != a[t][:, None, None]).astype(np.int64)
            + (seen_b[None] != b[t - 1][:, None, None])
        )

    st = _chain_argmin(u, None, pair)  # (L, N)
    y = yarn.copy()
    r = raised.copy()
    y[:, cols] = (st // 2).T
    r[:, cols] = (st % 2).astype(bool).T
    return y, r


def _row_terms_outside(
    problem: IllusionProblem, yarn: NDArray[np.int64], raised: NDArray[np.bool_], cols: Any
) -> NDArray[np.int64]:
    """Unary costs (L, N, S) of the pass terms for the wales ``cols`` (a yarn new to the row, a
    first bump and the segments it turns into bump-row segments), judged against the rest of
    each row (the other updated wales left out). Not exact when
    several updated wales are a row's only users of a yarn; :func:`descend` keeps an update
    only if the whole objective does not increase. Extra carriers are left to that check."""
    n, m = problem.shape
    k = problem.n_yarns
    cs, rs = _state_parts(k)
    p = problem.pass_weight
    rest = np.ones(m, dtype=bool)
    rest[cols] = False
    c = np.asarray(yarn)[:, rest]
    used = np.stack([(c == y).any(axis=1) for y in range(k)], axis=1)  # (N, K)
    bumped: NDArray[np.bool_] = np.asarray(np.asarray(raised)[:, rest].any(axis=1), dtype=bool)
    _, _, extra = pass_events(yarn, raised, k, problem.weights.float_gap)
    segments = used.sum(axis=1) + extra  # (N,), the rest's segments (extras of the whole row)
    new_yarn = ~used[:, cs]  # (N, S)
    new_bump = rs[None, :] & ~bumped[:, None]
    u = (2 * p) * new_yarn + p * (new_yarn & (bumped[:, None] | rs[None, :]))
    u = u + p * new_bump * (1 + segments[:, None])
    return np.broadcast_to(u[None], (len(cols), n, 2 * k))


def update_rows(
    problem: IllusionProblem,
    yarn: NDArray[np.int64],
    raised: NDArray[np.bool_],
    rows: NDArray[np.int64],
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """Re-optimise the unit rows ``rows`` exactly, all other rows fixed.

    ``rows`` must hold no two neighbouring rows. Returns new (yarn, raised); the objective never
    increases.
    """
    n = problem.shape[0]
    k = problem.n_yarns
    cs, rs = _state_parts(k)
    wv = problem.view_weight
    wc = problem.color_weight
    a = problem.target_a.astype(np.int64)
    b = problem.target_b.astype(np.int64)
    bump, pin = _unit_costs(problem)
    c_all = np.asarray(yarn, dtype=np.int64)
    r_all = np.asarray(raised, dtype=bool)
    u = bump[rows][:, :, None] * rs[None, None, :] + pin[rows][:, :, cs]  # (L, M, S)
    c = cs[None, None, :]
    r = rs[None, None, :]
    up = rows - 1
    dn = rows + 1
    has_up = up >= 0
    has_dn = dn < n
    upc = np.clip(up, 0, n - 1)
    dnc = np.clip(dn, 0, n - 1)
    cu, ru = c_all[upc][:, :, None], r_all[upc][:, :, None]  # row above (L, M, 1)
    cd, rd = c_all[dnc][:, :, None], r_all[dnc][:, :, None]  # row below
    ai, bi = a[rows][:, :, None], b[rows][:, :, None]
    bu = b[upc][:, :, None]  # view B of the row above
    ad = a[dnc][:, :, None]  # view A of the row below
    hu = has_up[:, None, None]
    hd = has_dn[:, None, None]
    mis = np.zeros(u.shape, dtype=np.int64)
    # view A at this row: row 0 sees itself; else the row above if raised, else this unit
    mis += np.where(hu, np.where(ru, cu != ai, c != ai), c != ai)
    # view A at the row below sees this unit if raised, else the row below's own colour
    mis += hd & np.where(r, c != ad, cd != ad)
    # view B at this row: the last row sees itself; else the row below if raised, else this unit
    mis += np.where(hd, np.where(rd, cd != bi, c != bi), c != bi)
    # view B at the row above sees this unit if raised, else the row above's own colour
    mis += hu & np.where(r, c != bu, cu != bu)
    u = u + wv * mis
    pair = (wc * (cs[:, None] != cs[None, :])).astype(np.int64)[None]  # (1, S', S)
    st = _best_row_states(problem, u, pair) if problem.pass_weight else _chain_argmin(u, pair)
    y = c_all.copy()
    rr = r_all.copy()
    y[rows] = st // 2
    rr[rows] = (st % 2).astype(bool)
    return y, rr


def _best_row_states(
    problem: IllusionProblem, u: NDArray[np.int64], pair: NDArray[np.int64]
) -> NDArray[np.int64]:
    """Row chains with the yarn-used and bump-row terms, exactly: one chain per nonempty set of
    allowed yarns and per bumps allowed or not, each charged its pass terms; the cheapest wins
    per row. (Extra carriers are left to :func:`descend`'s check.)"""
    k = problem.n_yarns
    cs, rs = _state_parts(k)
    p = problem.pass_weight
    best_cost: NDArray[np.int64] | None = None
    best: NDArray[np.int64] | None = None
    for mask in range(1, 2**k):
        allowed = np.array([(mask >> y) & 1 for y in range(k)], dtype=bool)
        for bumps in (False, True):
            ok = allowed[cs] & (rs <= bumps)
            uu = np.where(ok[None, None, :], u, _INF)
            st = _chain_argmin(uu, pair)
            cost = np.take_along_axis(uu, st[:, :, None], axis=2)[:, :, 0].sum(axis=1)
            cost = cost + pair[0][st[:, :-1], st[:, 1:]].sum(axis=1)
            used = int(allowed.sum())
            cost = cost + p * (2 * used + int(bumps) * (used + 1))
            if best_cost is None or best is None:
                best_cost, best = cost, st
            else:
                better = cost < best_cost
                best_cost = np.where(better, cost, best_cost)
                best[better] = st[better]
    assert best is not None
    return best


def descend(
    problem: IllusionProblem,
    yarn: NDArray[np.integer],
    raised: NDArray[np.bool_],
    *,
    max_sweeps: int = 200,
    deadline: float | None = None,
) -> tuple[NDArray[np.int64], NDArray[np.bool_], int, int]:
    """Block coordinate descent from (yarn, raised) to a local optimum.

    One sweep updates even wales, odd wales, even rows, odd rows (each exactly). Stops when a
    sweep improves nothing, after ``max_sweeps``, or at ``deadline`` (``time.perf_counter()``).

    Returns
    -------
    yarn : ndarray of shape (N, M), int64
    raised : ndarray of shape (N, M), bool
    cost : int
    sweeps : int
    """
    n, m = problem.shape
    y = np.asarray(yarn, dtype=np.int64).copy()
    r = np.asarray(raised, dtype=bool).copy()
    cost = pattern_cost(problem, y, r)
    blocks = [
        ("wales", np.arange(0, m, 2)),
        ("wales", np.arange(1, m, 2)),
        ("rows", np.arange(0, n, 2)),
        ("rows", np.arange(1, n, 2)),
    ]
    sweeps = 0
    for sweeps in range(1, max_sweeps + 1):  # noqa: B007 - the count is returned
        before = cost
        for kind, idx in blocks:
            if idx.size == 0:
                continue
            fn = update_wales if kind == "wales" else update_rows
            y2, r2 = fn(problem, y, r, idx)
            c2 = pattern_cost(problem, y2, r2)
            if c2 <= cost:  # always true for an exact block update; kept as a guard
                y, r, cost = y2, r2, c2
        if cost >= before or (deadline is not None and time.perf_counter() >= deadline):
            break
    return y, r, cost, sweeps


# -- starts, perturbation, and the search -----------------------------------------------------


def _row_majority(problem: IllusionProblem) -> NDArray[np.int64]:
    """Per unit row, the yarn most common in the two targets' row (ties: lower index)."""
    k = problem.n_yarns
    both = np.concatenate([problem.target_a, problem.target_b], axis=1).astype(np.int64)
    counts = np.stack([(both == c).sum(axis=1) for c in range(k)], axis=1)
    return counts.argmax(axis=1)


@dataclass(frozen=True)
class DescentResult:
    """What :func:`optimise_descent` returns: the best pattern, its cost, and how it was found."""

    yarn: NDArray[np.int64]
    raised: NDArray[np.bool_]
    cost: int
    bound: int
    start_costs: dict[str, int]
    rounds: int
    improvements: int
    sweeps: int
    timed_out: bool
    interrupted: bool = False


def optimise_descent(
    problem: IllusionProblem,
    *,
    time_limit: float | None = None,
    seed: int = 0,
    stall: int = 40,
    starts: dict[str, tuple[NDArray[np.integer], NDArray[np.bool_]]] | None = None,
    progress: ProgressCallback | None = None,
) -> DescentResult:
    """Iterated block descent on ``problem`` (see the module docstring).

    Parameters
    ----------
    time_limit : float, optional
        Seconds; None stops only by ``stall``.
    stall : int
        Stop after this many perturbations in a row that found nothing better.
    starts : dict, optional
        Extra named starting patterns ``{name: (yarn, raised)}`` (e.g. a tile pattern).
    """
    t0 = time.perf_counter()
    deadline = None if time_limit is None else t0 + time_limit
    n, m = problem.shape
    rng = np.random.default_rng(seed)
    dp_y, dp_r, bound = solve_dp(problem)
    init: dict[str, tuple[NDArray[np.integer], NDArray[np.bool_]]] = {"dp": (dp_y, dp_r)}
    maj = _row_majority(problem)
    init["row-majority"] = (np.repeat(maj[:, None], m, axis=1), np.zeros((n, m), dtype=bool))
    if problem.pinned is not None:  # a pinned unit keeps its yarn in every start
        p = problem.pinned.astype(np.int64)
        y0, r0 = init["row-majority"]
        init["row-majority"] = (np.where(p >= 0, p, y0), r0)
    if starts:
        init.update(starts)
    # the DP start is a valid answer from the outset: Ctrl-C at any point keeps the best so far
    dp_c = pattern_cost(problem, dp_y, dp_r)
    best: tuple[NDArray[np.int64], NDArray[np.bool_], int] = (
        dp_y.astype(np.int64),
        dp_r,
        dp_c,
    )
    state = {"sweeps": 0, "rounds": 0, "improvements": 0, "timed_out": False}
    start_costs: dict[str, int] = {}
    interrupted = False
    try:
        best = _search(
            problem, init, best, bound, maj, rng, deadline, stall, start_costs, state, progress, t0
        )
    except KeyboardInterrupt:
        interrupted = True
        best = state.get("best", best)  # type: ignore[assignment]
    return DescentResult(
        best[0],
        best[1],
        int(best[2]),
        int(bound),
        start_costs,
        int(state["rounds"]),
        int(state["improvements"]),
        int(state["sweeps"]),
        bool(state["timed_out"]),
        interrupted,
    )


def _search(
    problem: IllusionProblem,
    init: dict[str, tuple[NDArray[np.integer], NDArray[np.bool_]]],
    best: tuple[NDArray[np.int64], NDArray[np.bool_], int],
    bound: int,
    maj: NDArray[np.int64],
    rng: np.random.Generator,
    deadline: float | None,
    stall: int,
    start_costs: dict[str, int],
    state: dict,
    progress: ProgressCallback | None,
    t0: float,
) -> tuple[NDArray[np.int64], NDArray[np.bool_], int]:
    """The iterated local search of :func:`optimise_descent`; ``state`` tracks counters and the
    best pattern so far (read back after an interrupt)."""
    n, m = problem.shape
    state["best"] = best
    total_sweeps = 0
    timed_out = False
    for name, (y0, r0) in init.items():
        y, r, c, sw = descend(problem, y0, r0, deadline=deadline)
        total_sweeps += sw
        state["sweeps"] = total_sweeps
        start_costs[name] = c
        if c < best[2] or name == "dp":
            best = (y, r, c)
            state["best"] = best
            if progress:
                progress(ProgressEvent(time.perf_counter() - t0, c, bound, f"start {name}"))
        if deadline is not None and time.perf_counter() >= deadline:
            timed_out = True
            break
    cur_y, cur_r, cur_c = best
    rounds = improvements = since = 0
    while not timed_out and since < stall and best[2] > bound:
        if deadline is not None and time.perf_counter() >= deadline:
            timed_out = True
            break
        rounds += 1
        y = cur_y.copy()
        r = cur_r.copy()
        if rng.random() < 0.5 and n > 1:  # a band of rows
            h = int(rng.integers(1, max(2, n // 6) + 1))
            i0 = int(rng.integers(0, n - h + 1))
            j0, w = 0, m
            if rng.random() < 0.5 and m > 2:
                w = int(rng.integers(max(1, m // 4), m + 1))
                j0 = int(rng.integers(0, m - w + 1))
            band = (slice(i0, i0 + h), slice(j0, j0 + w))
            y[band] = maj[i0 : i0 + h, None]
        else:  # a block of wales keeps its rows but takes each row's majority there
            w = int(rng.integers(1, max(2, m // 6) + 1))
            j0 = int(rng.integers(0, m - w + 1))
            blk = y[:, j0 : j0 + w]
            k = problem.n_yarns
            counts = np.stack([(blk == c).sum(axis=1) for c in range(k)], axis=1)
            choice = np.where(rng.random(n) < 0.5, counts.argmax(axis=1), rng.integers(0, k, n))
            y[:, j0 : j0 + w] = choice[:, None]
            band = (slice(0, n), slice(j0, j0 + w))
        r[band] = False
        if problem.pinned is not None:
            p = problem.pinned.astype(np.int64)
            y = np.where(p >= 0, p, y)
        y, r, c, sw = descend(problem, y, r, deadline=deadline)
        total_sweeps += sw
        state.update(sweeps=total_sweeps, rounds=rounds)
        if c <= cur_c:
            since = 0 if c < cur_c else since + 1
            cur_y, cur_r, cur_c = y, r, c
        else:
            since += 1
        if c < best[2]:
            improvements += 1
            best = (y, r, c)
            state.update(best=best, improvements=improvements)
            if progress:
                progress(ProgressEvent(time.perf_counter() - t0, c, bound, "descent improved"))
    state["timed_out"] = timed_out
    return best


# -- the backend ----------------------------------------------------------------------------


class DescentBackend(BackendBase):
    """Iterated exact-block coordinate descent (wales and courses) for illusion models."""

    name = "descent"
    #: a heuristic on the knit-aware model: ``optimal`` only where the DP proves it
    exact = False

    def __init__(self, *, stall: int = 40) -> None:
        self.stall = stall

    def why_not(self, model: Model) -> str | None:
        p = model.problem
        if not isinstance(p, IllusionProblem):
            return "block descent solves only illusion models built by illuknit.illusion_models"
        if p.color_cap is not None:
            return "block descent cannot guarantee a hard colour-change cap; use --solver cpsat"
        return None

    def solve(
        self,
        model: Model,
        *,
        time_limit: float | None = None,
        seed: int = 0,
        progress: ProgressCallback | None = None,
    ) -> Solution:
        problem = model.problem
        if problem.per_wale or problem.rows_tied:
            # no cross-wale term (or rows tied to one yarn): the DP is exact
            sol = DPBackend().solve(model, time_limit=time_limit, seed=seed, progress=progress)
            stats = {**sol.stats, "method": "dp (exact for this model)"}
            return replace(sol, stats=stats, backend=self.name)
        t0 = time.perf_counter()
        res = optimise_descent(
            problem, time_limit=time_limit, seed=seed, stall=self.stall, progress=progress
        )
        vals = values_from_pattern(model, res.yarn, res.raised)
        ok, cost = model.evaluate(vals)
        wall = time.perf_counter() - t0
        info: dict[str, object] = {
            "starts": dict(res.start_costs),
            "rounds": res.rounds,
            "improvements": res.improvements,
            "sweeps": res.sweeps,
            "interrupted": res.interrupted,
        }
        if not ok or cost != res.cost:
            info["message"] = (
                f"descent cost {res.cost} disagrees with the model ({cost}, feasible={ok})"
            )
            return Solution(Status.ERROR, vals, cost, None, wall, info, self.name, model.pool)
        if cost <= res.bound:
            st = Status.OPTIMAL  # met the DP lower bound: proven
        else:
            st = Status.TIMEOUT if res.timed_out and not res.interrupted else Status.FEASIBLE
        return Solution(st, vals, cost, float(res.bound), wall, info, self.name, model.pool)
