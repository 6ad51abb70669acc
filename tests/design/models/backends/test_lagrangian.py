"""The Lagrangian bound of the knit-aware model: never above the optimum (brute force over every
pattern of tiny grids, machine passes and extra carriers included), at least the DP and additive
bounds, and reported by the descent backend."""

from __future__ import annotations

import itertools

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.design.models.backends.descent_blocks import pattern_cost
from illuknit.design.models.backends.dp import solve_dp
from illuknit.design.models.backends.lagrangian import additive_bound, lagrangian_bound
from illuknit.design.models.illusion_models import KnitWeights, build_model, make_problem
from illuknit.solvers import solve


def _brute_force(problem) -> int:
    n, m = problem.shape
    k = problem.n_yarns
    best = None
    for states in itertools.product(range(2 * k), repeat=n * m):
        s = np.asarray(states).reshape(n, m)
        c = pattern_cost(problem, s // 2, (s % 2).astype(bool))
        best = c if best is None else min(best, c)
    assert best is not None
    return best


@settings(max_examples=25, deadline=None)
@given(
    shape=st.sampled_from([(1, 2), (2, 1), (2, 2), (1, 3), (3, 1), (2, 3), (3, 2), (1, 4)]),
    k=st.integers(2, 3),
    view=st.integers(1, 4),
    color=st.integers(0, 2),
    transfer=st.integers(0, 2),
    passes=st.integers(1, 6),
    gap=st.integers(1, 2),
    seed=st.integers(0, 2**31),
)
def test_the_bound_never_exceeds_the_brute_force_optimum(
    shape, k, view, color, transfer, passes, gap, seed
):
    n, m = shape
    if (2 * k) ** (n * m) > 5000:
        k = 2
    rng = np.random.default_rng(seed)
    w = KnitWeights(
        view=view, color_change=color, transfer=transfer, machine_pass=passes, float_gap=gap
    )
    problem = make_problem(
        rng.integers(0, k, (n, m)),
        rng.integers(0, k, (n, m)),
        n_yarns=k,
        kind="knit-aware",
        weights=w,
    )
    opt = _brute_force(problem)
    lag = lagrangian_bound(problem, time_limit=2.0)
    assert solve_dp(problem)[2] <= additive_bound(problem) <= lag.bound <= opt <= lag.cost
    assert lag.cost == pattern_cost(problem, lag.yarn, lag.raised)


def test_the_bound_closes_most_of_the_dp_gap_on_random_models():
    """Against CP-SAT's proven optima on 4 x 4 three-yarn models (default weights)."""
    rng = np.random.default_rng(3)
    for _ in range(4):
        problem = make_problem(
            rng.integers(0, 3, (4, 4)), rng.integers(0, 3, (4, 4)), n_yarns=3, kind="knit-aware"
        )
        sol = solve(build_model(problem), solver="cpsat", time_limit=60)
        assert sol.status.value == "optimal"
        dp = solve_dp(problem)[2]
        lag = lagrangian_bound(problem, time_limit=3.0)
        assert lag.bound <= sol.objective
        assert sol.objective - lag.bound <= 0.25 * (sol.objective - dp)


def test_the_descent_backend_reports_the_better_bound():
    rng = np.random.default_rng(1)
    problem = make_problem(
        rng.integers(0, 3, (12, 10)), rng.integers(0, 3, (12, 10)), n_yarns=3, kind="knit-aware"
    )
    model = build_model(problem)
    sol = solve(model, solver="descent", time_limit=4)
    assert model.evaluate(sol.values) == (True, sol.objective)
    lag = sol.stats["lagrangian"]
    assert sol.bound == lag["bound"] > additive_bound(problem) > solve_dp(problem)[2]
    assert sol.bound <= sol.objective
