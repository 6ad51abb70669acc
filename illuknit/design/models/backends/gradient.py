"""Gradient-descent design through the differentiable renderer (paper section 8.3) as a backend.

The backend recognises models built from an :class:`illuknit.design.models.illusion_models.IllusionProblem`
(``model.problem``) and runs :func:`illuknit.design.render.optimise.optimise_design` on its two targets:
yarn probabilities are rendered directly (``mix="yarn"``) at the elevation where a bump hides
exactly one unit, so the renders of the binarised pattern are the can_see views and the render
error counts mismatched cells. The model's weights carry over: colour changes along courses and
bumps (knit/purl transfers) become penalties relative to the view weight, and pinned units stay
fixed. The binarised pattern is mapped back to the model's variables and scored with
``model.evaluate``; the status is ``feasible`` (gradient descent proves nothing), ``timeout``
when the time limit cut the descent short.

It does not handle models with a hard colour-change cap per course (descent cannot guarantee it).
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any

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

__all__ = ["GradientBackend"]


class GradientBackend(BackendBase):
    """Soft heights and yarns optimised with Adam against renders at ±theta, then binarised."""

    name = "gradient"
    kind = BackendKind.DOMAIN
    proves_bound = False
    #: a heuristic: statuses are ``feasible``/``timeout``, never ``optimal``, and no bound
    exact = False

    def __init__(self, *, steps: int = 300, params: Any = None) -> None:
        self.steps = steps
        self.params = params

    def why_not(self, model: Model) -> str | None:
        p = model.problem
        if not isinstance(p, IllusionProblem):
            return "the gradient backend solves only illusion models built by illuknit.design.models.illusion_models.build_model"
        if p.n_yarns < 2:
            return "the gradient backend needs at least two yarns"
        if p.for_hands:
            return HANDS_SOLVERS
        if p.color_cap is not None:
            return "gradient descent cannot guarantee a hard colour-change cap; use --solver cpsat"
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
        from illuknit.design.models.backends.dp import values_from_pattern
        from illuknit.design.models.illusion_report import default_yarns
        from illuknit.design.render.optimise import optimise_design
        from illuknit.design.render.params import RenderParams

        t0 = time.perf_counter()
        if not self.handles(model):
            reason = {"message": self.why_not(model)}
            return Solution(Status.ERROR, None, None, None, 0.0, reason, self.name, model.pool)
        problem = problem_of(model)
        base = self.params or RenderParams()
        params = base.with_angle(base.exact_angle)
        k = problem.n_yarns
        wv = problem.view_weight
        # Model costs per event, converted to the optimiser's per-cell means: a wrong view cell
        # adds 2 / (N M K) to the mean squared error of one-hot renders, a colour change
        # 1 / (N (M-1)) to the change share, a bump 1 / (N M) to the raised share.
        per_mismatch = 2.0 / (k * wv)
        _, m = problem.shape
        change_w = problem.color_weight * per_mismatch * (m - 1) / m if m > 1 else 0.0
        raised_w = 2.0 * problem.transfer_weight * per_mismatch
        try:
            result = optimise_design(
                problem.target_a,
                problem.target_b,
                default_yarns(k),
                params=params,
                steps=self.steps,
                change_weight=change_w,
                raised_weight=raised_w,
                mix="yarn",
                pinned=problem.pinned,
                seed=seed,
                time_limit=None if time_limit is None else max(0.0, time_limit - 0.05),
            )
        except KeyboardInterrupt:  # pragma: no cover - interactive only
            wall = time.perf_counter() - t0
            stopped = {"interrupted": True}
            return Solution(Status.FEASIBLE, None, None, None, wall, stopped, self.name, model.pool)
        pat = result.pattern
        vals = values_from_pattern(model, pat.yarn, pat.raised)
        ok, cost = model.evaluate(vals)
        wall = time.perf_counter() - t0
        stats: dict[str, object] = {
            "steps": result.report["steps"],
            "render_error_before": result.report["before"]["render_error"],
            "render_error_after": result.report["after"]["render_error"],
            "logical_error_before": result.report["before"]["logical_error"],
            "logical_error_after": result.report["after"]["logical_error"],
            "interrupted": False,
        }
        if not ok:
            stats["message"] = "the binarised design breaks a hard constraint of the model"
            return Solution(Status.ERROR, vals, cost, None, wall, stats, self.name, model.pool)
        status = Status.TIMEOUT if result.report["steps"] < self.steps else Status.FEASIBLE
        if progress:
            progress(ProgressEvent(wall, cost, None, "gradient design binarised"))
        return Solution(status, vals, cost, None, wall, stats, self.name, model.pool)
