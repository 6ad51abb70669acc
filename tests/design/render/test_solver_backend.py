"""The ``gradient`` solver backend on illusion models."""

from __future__ import annotations

import numpy as np

from illuknit.core.views import can_see
from illuknit.design.models.backends.dp import solve_dp
from illuknit.design.models.backends.gradient import GradientBackend
from illuknit.design.models.illusion_models import KnitWeights, build_model, make_problem
from illuknit.pictures.drawings import draw_text
from illuknit.solvers.base import Backend
from illuknit.solvers.model import Model


def test_backend_contract_and_scope():
    b = GradientBackend()
    assert isinstance(b, Backend) and b.name == "gradient" and b.is_available()
    assert not b.handles(Model("generic"))
    capped = make_problem(
        np.zeros((2, 2), int),
        np.ones((2, 2), int),
        kind="knit-aware",
        weights=KnitWeights(max_color_changes=0),
    )
    assert not b.handles(build_model(capped))
    assert "cap" in b.why_not(build_model(capped))


def test_gradient_backend_on_a_text_pair_is_scored_by_the_model():
    a = draw_text("HI", shape=(12, 14)).astype(int)
    bb = draw_text("OK", shape=(12, 14)).astype(int)
    problem = make_problem(a, bb, kind="logical")
    model = build_model(problem)
    sol = GradientBackend(steps=120).solve(model, seed=1)
    assert sol.status.value == "feasible" and sol.has_values
    ok, cost = model.evaluate(sol.values)
    assert ok and cost == sol.objective
    # The objective counts can_see mismatches of the decoded pattern.
    raised = sol.block("raised")
    yarn = np.argmax(sol.block("yarn"), axis=-1)
    mism = int((can_see(yarn, "A", raised) != a).sum() + (can_see(yarn, "B", raised) != bb).sum())
    assert cost == mism
    optimum = solve_dp(problem)[2]
    blank = int(a.sum() + bb.sum())  # all background
    assert optimum <= cost < blank


def test_time_limit_stops_early():
    a = np.random.default_rng(0).integers(0, 2, (30, 30))
    model = build_model(make_problem(a, a[::-1], kind="knit-aware"))
    sol = GradientBackend(steps=100000).solve(model, time_limit=0.3)
    assert sol.status.value == "timeout" and sol.has_values and sol.wall_time < 10
