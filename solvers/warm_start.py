"""Warm starts for exact backends on illusion models, as an explicit policy.

=========  ==========================================================================
policy     what the backend is handed as ``model.hint``
=========  ==========================================================================
none       nothing: the backend's answer is its own (the benchmark's default)
dp         the DP optimum of the model's per-wale part (for the logical and single-view
           models the exact optimum; for the knit-aware model an assignment whose
           colour-change terms are ignored, which may break a colour-change cap)
descent    the block descent of :mod:`illuknit.solvers.descent`, started from the DP
           optimum, given ``WARM_START_SHARE`` of the time limit (knit-aware model
           without a cap; elsewhere the DP is already exact and is used instead); with
           machine-pass terms the Lagrangian bound first, whose pattern is one more start
           and whose bound is handed to backends that accept a lower bound
auto       ``descent`` for the knit-aware model with colour terms and no cap, else ``dp``
=========  ==========================================================================

After the backend returns, :func:`keep_warm_start` keeps the warm start's assignment when the
backend came back worse or with nothing, and says so: the solution's ``found_by`` names the warm
start, not the backend.
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from illuknit.core.errors import SolverError, UnknownNameError
from illuknit.design.models.illusion_problem import IllusionProblem
from illuknit.solvers.base import Solution, Status
from illuknit.solvers.descent import bound_then_search, optimise_descent
from illuknit.solvers.dp import hint_values, values_from_pattern
from illuknit.solvers.model import Model

__all__ = [
    "WARM_STARTS",
    "WARM_START_SECONDS",
    "WARM_START_SHARE",
    "WarmStart",
    "keep_warm_start",
    "make_warm_start",
    "resolve_policy",
]

WARM_STARTS: tuple[str, ...] = ("none", "dp", "descent", "auto")

#: Share of the time limit a warm-start descent may take before an exact backend (model (b)).
#: The descent stops by itself when it stalls (seconds on small models); at paper scale it
#: improves faster than CP-SAT does from its result, so it gets half.
WARM_START_SHARE = 0.5
#: Most seconds of warm-start descent (also without a time limit).
WARM_START_SECONDS = 60.0


#: ``{"method", "objective", "seconds"[, "bound"]}``: what a warm start did (a plain dict, so it
#: travels in ``Solution.stats`` and JSON reports unchanged).
WarmStart = dict[str, Any]


def resolve_policy(policy: str, model: Model) -> str:
    """The concrete policy (``none``, ``dp`` or ``descent``) ``policy`` means for ``model``.

    Raises
    ------
    UnknownNameError
        ``policy`` is not one of :data:`WARM_STARTS`.
    SolverError
        A ``dp``/``descent`` warm start was asked for a model that is not an illusion model.
    """
    if policy not in WARM_STARTS:
        raise UnknownNameError("warm start", policy, WARM_STARTS)
    problem = model.problem
    if policy == "none":
        return "none"
    if not isinstance(problem, IllusionProblem):
        if policy == "auto":
            return "none"
        raise SolverError(f"warm start {policy!r} needs an illusion model (model {model.name!r})")
    exact_dp = problem.per_wale or problem.rows_tied
    if policy == "auto":
        return "dp" if exact_dp or problem.color_cap is not None else "descent"
    if policy == "descent" and (exact_dp or problem.color_cap is not None):
        # the DP is already exact there; the descent cannot keep a hard cap
        return "dp"
    return policy


def make_warm_start(
    model: Model, policy: str, *, time_limit: float | None = None, seed: int = 0
) -> tuple[NDArray[np.bool_], WarmStart]:
    """The warm start ``policy`` (``dp`` or ``descent``, see :func:`resolve_policy`) of ``model``.

    Returns
    -------
    values : ndarray of bool, indexed by variable id
    info : WarmStart
        For ``descent`` also ``"bound"``: a proven lower bound of the knit-aware model (the
        better of the DP optimum of the per-wale part and, with machine-pass terms, the
        Lagrangian bound of :mod:`illuknit.solvers.lagrangian`), which
        :func:`illuknit.solvers.solve` hands to backends that accept one (CP-SAT, LSU).
    """
    problem = model.problem
    if not isinstance(problem, IllusionProblem) or policy not in ("dp", "descent"):
        raise SolverError(f"no warm start {policy!r} for model {model.name!r}")
    t0 = time.perf_counter()
    info: WarmStart = {"method": policy}
    if policy == "dp":
        vals = hint_values(problem, model)
    else:
        budget = (
            WARM_START_SECONDS
            if time_limit is None
            else min(WARM_START_SECONDS, WARM_START_SHARE * time_limit)
        )
        if problem.pass_weight:  # the Lagrangian bound too: the pass terms the DP drops
            res, _ = bound_then_search(problem, time_limit=budget, seed=seed)
        else:
            res = optimise_descent(problem, time_limit=budget, seed=seed)
        vals = values_from_pattern(model, res.yarn, res.raised)
        info["bound"] = res.bound
    _, cost = model.evaluate(vals)
    info["objective"] = int(cost)
    info["seconds"] = round(time.perf_counter() - t0, 3)
    return vals, info


def keep_warm_start(model: Model, solution: Solution, info: WarmStart) -> Solution:
    """``solution`` timed from before the warm start and, if the backend came back worse than
    its warm start (``model.hint``) or with nothing, the warm start's assignment instead
    (``found_by`` the warm start); the bound is the better of the backend's and the warm
    start's (``info["bound"]``)."""
    ws = float(info.get("seconds", 0.0))
    values, objective, status = solution.values, solution.objective, solution.status
    found_by, found_at = solution.found_by, solution.found_at
    found_at = None if found_at is None else found_at + ws
    stats = {**solution.stats, "warm_start": dict(info)}
    if model.hint is not None and status in (Status.FEASIBLE, Status.TIMEOUT):
        hint = np.asarray(model.hint, dtype=bool)
        ok, cost = model.evaluate(hint)
        if ok and (objective is None or cost < objective):
            values, objective = hint, cost
            found_by, found_at = str(info["method"]), ws
            stats["kept_warm_start"] = True
        elif values is not None and np.array_equal(values[: hint.size], hint[: values.size]):
            # the backend handed the hint back (e.g. RC2's timeout fallback): credit the hint
            found_by, found_at = str(info["method"]), ws
            stats["kept_warm_start"] = True
    bound = solution.bound
    if info.get("bound") is not None and status in (Status.FEASIBLE, Status.TIMEOUT):
        bound = max(float(info["bound"]), bound if bound is not None else float("-inf"))
        if objective is not None and objective <= bound:
            status = Status.OPTIMAL  # the warm start met a proven lower bound
    trace = [(t + ws, o, b) for t, o, b in solution.trace]
    if "objective" in info:
        trace.insert(0, (ws, float(info["objective"]), info.get("bound")))
    return replace(
        solution,
        status=status,
        values=values,
        objective=objective,
        bound=bound,
        wall_time=solution.wall_time + ws,
        stats=stats,
        found_by=found_by,
        found_at=found_at,
        trace=tuple(trace),
    )
