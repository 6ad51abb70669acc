"""The warm starts of the illusion models, registered with the solver layer
(:func:`illuknit.solvers.warm_start.register_warm_start`) for :class:`IllusionProblem` payloads.

=========  ==========================================================================
policy     what the backend is handed as ``model.hint``
=========  ==========================================================================
none       nothing: the backend's answer is its own (the benchmark's default)
dp         the DP optimum of the model's per-wale part (for the logical and single-view
           models the exact optimum; for the knit-aware model an assignment whose
           colour-change terms are ignored, which may break a colour-change cap)
descent    the block descent of :mod:`illuknit.design.models.backends.descent`, started from the DP
           optimum, given ``WARM_START_SHARE`` of the time limit (knit-aware model
           without a cap; elsewhere the DP is already exact and is used instead); with
           machine-pass terms the Lagrangian bound first, whose pattern is one more start
           and whose bound is handed to backends that accept a lower bound
hand       a model made for hands (``problem.for_hands``): the DP optimum, then
           :func:`~illuknit.design.models.backends.hand_rows.hand_row_descent` (every row
           re-optimised exactly under the hand knitter's row rule) for up to
           ``WARM_START_SHARE`` of the time limit -- the only start that keeps the rows
           knittable; ``dp`` and ``descent`` mean it for such a model
auto       ``hand`` for a model made for hands, ``descent`` for the knit-aware model with
           colour terms and no cap, else ``dp``
=========  ==========================================================================

After the backend returns, :func:`illuknit.solvers.warm_start.keep_warm_start` keeps the warm
start's assignment when the backend came back worse or with nothing, and says so: the solution's
``found_by`` names the warm start, not the backend.
"""

from __future__ import annotations

import time

import numpy as np
from numpy.typing import NDArray

from illuknit.core.errors import SolverError
from illuknit.design.models.illusion_problem import IllusionProblem, problem_of
from illuknit.solvers.model import Model
from illuknit.solvers.warm_start import WarmStartInfo

__all__ = [
    "WARM_STARTS",
    "WARM_START_SECONDS",
    "WARM_START_SHARE",
    "IllusionWarmStarter",
]

WARM_STARTS: tuple[str, ...] = ("none", "dp", "descent", "hand", "auto")

#: Share of the time limit a warm-start descent may take before an exact backend (model (b)).
#: The descent stops by itself when it stalls (seconds on small models); at paper scale it
#: improves faster than CP-SAT does from its result, so it gets half.
WARM_START_SHARE = 0.5
#: Most seconds of warm-start descent (also without a time limit).
WARM_START_SECONDS = 60.0


class IllusionWarmStarter:
    """The ``dp`` and ``descent`` warm starts of models built from an :class:`IllusionProblem`."""

    payload = IllusionProblem
    policies: tuple[str, ...] = ("dp", "descent", "hand")
    needs = "an illusion model"

    def resolve(self, policy: str, model: Model) -> str:
        """The concrete policy (``dp`` or ``descent``) ``policy`` means for ``model``."""
        problem = problem_of(model)
        if problem.for_hands:  # the only start that keeps every row knittable
            return "hand"
        if policy == "hand":
            return "dp"  # nothing to keep knittable: the hand descent starts from the DP
        exact_dp = problem.per_wale or problem.rows_tied
        if policy == "auto":
            return "dp" if exact_dp or problem.color_cap is not None else "descent"
        if policy == "descent" and (exact_dp or problem.color_cap is not None):
            # the DP is already exact there; the descent cannot keep a hard cap
            return "dp"
        return policy

    def make(
        self, model: Model, policy: str, *, time_limit: float | None = None, seed: int = 0
    ) -> tuple[NDArray[np.bool_], WarmStartInfo]:
        """The warm start ``policy`` (``dp`` or ``descent``) of ``model``.

        For ``descent`` the info also holds a proven lower bound of the knit-aware model (the
        better of the DP optimum of the per-wale part and, with machine-pass terms, the
        Lagrangian bound of :mod:`illuknit.design.models.backends.lagrangian`), which
        :func:`illuknit.solvers.solve` hands to backends that accept one (CP-SAT, LSU).
        """
        from illuknit.design.models.backends.descent import bound_then_search, optimise_descent
        from illuknit.design.models.backends.dp import hint_values, values_from_pattern

        problem = model.problem
        if not isinstance(problem, IllusionProblem) or policy not in self.policies:
            raise SolverError(f"no warm start {policy!r} for model {model.name!r}")
        t0 = time.perf_counter()
        bound = None
        if policy == "dp":
            vals = hint_values(problem, model)
        elif policy == "hand":
            budget = (
                WARM_START_SECONDS
                if time_limit is None
                else min(WARM_START_SECONDS, WARM_START_SHARE * time_limit)
            )
            yarn, raised = _hand_start(problem, budget, seed)
            vals = values_from_pattern(model, yarn, raised)
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
            bound = res.bound
        _, cost = model.evaluate(vals)
        seconds = round(time.perf_counter() - t0, 3)
        return vals, WarmStartInfo(
            policy, int(cost), seconds, bound, proves_bound=policy == "descent"
        )


def _hand_start(
    problem: IllusionProblem, budget: float, seed: int
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """The ``hand`` warm start: the better of two row descents
    (:func:`~illuknit.design.models.backends.hand_rows.hand_row_descent`), one from the DP
    optimum (which ignores the rows: pictures of many small shapes, worked stranded), one from
    the intarsia restriction solved by CP-SAT in what is left of ``budget`` (the same views
    with at most ``MAX_HAND_BLOCKS - 1`` colour changes a row, a cardinality model CP-SAT
    solves well, unlike the stranded rule's clauses: pictures of a few large shapes)."""
    from dataclasses import replace

    from illuknit.design.hand_cost import MAX_HAND_BLOCKS
    from illuknit.design.models.backends.dp import solve_dp
    from illuknit.design.models.backends.hand_rows import hand_row_descent
    from illuknit.design.models.illusion_models import build_model, pattern_from_solution
    from illuknit.design.models.illusion_problem import KnitWeights
    from illuknit.solvers import solve

    t0 = time.perf_counter()
    yarn, raised, _ = solve_dp(problem)
    best = hand_row_descent(problem, yarn, raised, time_limit=budget / 4)
    left = budget - (time.perf_counter() - t0)
    if left > 1.0 and problem.shape[1] > MAX_HAND_BLOCKS:
        intarsia = replace(
            problem,
            kind="knit-aware",
            for_hands=False,
            weights=KnitWeights(
                view=1, color_change=0, transfer=0, machine_pass=0,
                max_color_changes=MAX_HAND_BLOCKS - 1,
            ),
        )  # fmt: skip
        sol = solve(
            build_model(intarsia), solver="cpsat", warm_start="none", time_limit=left, seed=seed
        )
        if sol.has_values:
            pat = pattern_from_solution(intarsia, sol)
            other = hand_row_descent(problem, pat.yarn, pat.raised, time_limit=budget / 4)
            if other[2] < best[2]:
                best = other
    return best[0], best[1]
