"""Exact-block coordinate descent for the knit-time-aware illusion model (b).

The objective of model (b) (:mod:`illuknit.design.models.illusion_models`) is a sum of terms over *pairs of
units that are neighbours in the grid*:

* view A at row i and view B at row i-1 couple units (i-1, j) and (i, j) of one wale; a bump's
  knit<->purl changes are a cost of the unit alone;
* a colour change couples units (i, j) and (i, j+1) of one course.

So the grid is a 4-neighbour pairwise model over the 2K states ``(yarn, raised)`` of each unit,
and two kinds of *blocks* can be re-optimised **exactly** while the rest stays fixed:

* **a wale** (column j): with wales j-1 and j+1 fixed, their colours turn the colour-change terms
  into unary costs of wale j, which is then a chain — the per-wale shortest path of
  :mod:`illuknit.design.models.backends.dp` with extra unary costs;
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
non-negative). With machine-pass terms the backend also computes the Lagrangian bound of
:mod:`illuknit.design.models.backends.lagrangian`, which keeps the pass terms the DP drops: the bound first
(at most 35 % of the time; it stops when its steps die out), then the search for the rest, with
the best pattern the bound met (the wales solved within its rows' yarn sets) as one more start;
the better bound is reported. The backend is a heuristic (``exact = False``): status
``feasible`` (``timeout`` when the time limit stopped it), never ``optimal`` for a model with
colour-change terms. Per-wale models (no colour term) and the single-view model are solved
exactly by the DP instead. A hard colour-change cap per course is not handled.

The objective and the block moves are in :mod:`illuknit.design.models.backends.descent_blocks`; this module is
the search around them and the backend.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from illuknit.design.models.backends.descent_blocks import descend, pattern_cost
from illuknit.design.models.backends.dp import DPBackend, solve_dp, values_from_pattern
from illuknit.design.models.backends.lagrangian import LagrangianResult, lagrangian_bound
from illuknit.design.models.illusion_problem import (
    HANDS_SOLVERS,
    SPLIT_BUMPS_SOLVERS,
    IllusionProblem,
    problem_of,
)
from illuknit.solvers.base import (
    BackendBase,
    BackendKind,
    ProgressCallback,
    ProgressEvent,
    Solution,
    Status,
)

if TYPE_CHECKING:
    from illuknit.solvers.model import Model

__all__ = ["DescentBackend", "DescentResult", "bound_then_search", "optimise_descent"]

#: Most of the backend's time limit the Lagrangian bound may take on model (b) with pass terms,
#: before the search (which gets the rest); without a time limit, this many seconds.
LAGRANGIAN_SHARE = 0.35
LAGRANGIAN_SECONDS = 10.0


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
        search = _Search(problem, bound, maj, rng, deadline, stall, progress, t0)
        best = _search(search, init, best, start_costs, state)
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


@dataclass(frozen=True)
class _Search:
    """What the iterated local search of :func:`optimise_descent` reads and never changes."""

    problem: IllusionProblem
    #: the DP's lower bound: the search stops when it meets it
    bound: int
    #: per unit row, the yarn most common in the targets' row (:func:`_row_majority`)
    majority: NDArray[np.int64]
    rng: np.random.Generator
    deadline: float | None
    #: perturbations in a row that find nothing better before the search stops
    stall: int
    progress: ProgressCallback | None
    #: the clock reading (``time.perf_counter()``) progress times are measured from
    t0: float


def _search(
    search: _Search,
    init: dict[str, tuple[NDArray[np.integer], NDArray[np.bool_]]],
    best: tuple[NDArray[np.int64], NDArray[np.bool_], int],
    start_costs: dict[str, int],
    state: dict,
) -> tuple[NDArray[np.int64], NDArray[np.bool_], int]:
    """The iterated local search of :func:`optimise_descent`; ``state`` tracks counters and the
    best pattern so far (read back after an interrupt)."""
    problem, bound, maj, rng = search.problem, search.bound, search.majority, search.rng
    deadline, stall, progress, t0 = search.deadline, search.stall, search.progress, search.t0
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


def bound_then_search(
    problem: IllusionProblem,
    *,
    time_limit: float | None = None,
    seed: int = 0,
    stall: int = 40,
    progress: ProgressCallback | None = None,
) -> tuple[DescentResult, LagrangianResult | None]:
    """Model (b) with pass terms: the Lagrangian bound first (at most ``LAGRANGIAN_SHARE`` of
    the time; it stops sooner once its steps die out), then :func:`optimise_descent` for the
    rest of the time with the best pattern the bound met as one more start. The result's
    ``bound`` is the better of the DP's and the Lagrangian's; the Lagrangian result is returned
    too (None when interrupted)."""
    t0 = time.perf_counter()
    lag_time = LAGRANGIAN_SECONDS if time_limit is None else LAGRANGIAN_SHARE * time_limit
    try:
        lag = lagrangian_bound(problem, time_limit=max(0.5, lag_time))
    except KeyboardInterrupt:  # asked to stop: the pattern matters more than the bound
        lag = None
    starts: dict[str, tuple[NDArray[np.integer], NDArray[np.bool_]]] | None = (
        None if lag is None else {"lagrangian": (lag.yarn, lag.raised)}
    )
    left = None if time_limit is None else max(0.5, time_limit - (time.perf_counter() - t0))
    res = optimise_descent(
        problem, time_limit=left, seed=seed, stall=stall, starts=starts, progress=progress
    )
    if lag is not None and lag.bound > res.bound:
        res = replace(res, bound=lag.bound)
        if progress:
            progress(ProgressEvent(time.perf_counter() - t0, res.cost, lag.bound))
    return res, lag


# -- the backend ----------------------------------------------------------------------------


class DescentBackend(BackendBase):
    """Iterated exact-block coordinate descent (wales and courses) for illusion models."""

    name = "descent"
    kind = BackendKind.DOMAIN
    #: the descent is what the ``descent`` warm start runs
    accepts_warm_start = False
    #: a heuristic on the knit-aware model: ``optimal`` only where the DP proves it
    exact = False

    def __init__(self, *, stall: int = 40) -> None:
        self.stall = stall

    def why_not(self, model: Model) -> str | None:
        p = model.problem
        if not isinstance(p, IllusionProblem):
            return "block descent solves only illusion models built by illuknit.design.models.illusion_models"
        if p.for_hands:
            return HANDS_SOLVERS
        if p.color_cap is not None:
            return "block descent cannot guarantee a hard colour-change cap; use --solver cpsat"
        if p.split_bumps:
            return SPLIT_BUMPS_SOLVERS
        return None

    def solve(
        self,
        model: Model,
        *,
        time_limit: float | None = None,
        seed: int = 0,
        progress: ProgressCallback | None = None,
    ) -> Solution:
        problem = problem_of(model)
        if problem.per_wale or problem.rows_tied:
            # no cross-wale term (or rows tied to one yarn): the DP is exact
            sol = DPBackend().solve(model, time_limit=time_limit, seed=seed, progress=progress)
            stats = {**sol.stats, "method": "dp (exact for this model)"}
            return replace(sol, stats=stats, backend=self.name)
        t0 = time.perf_counter()
        lag = None
        if problem.pass_weight:
            res, lag = bound_then_search(
                problem, time_limit=time_limit, seed=seed, stall=self.stall, progress=progress
            )
        else:
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
        if lag is not None:
            info["lagrangian"] = {
                "bound": lag.bound,
                "iterations": lag.iterations,
                "seconds": round(lag.seconds, 3),
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
