"""The one orchestration: warm-start policies, found_by, the trace, one DP run for "auto"."""

from __future__ import annotations

from typing import ClassVar

import numpy as np
import pytest

import illuknit.design.models.backends.dp as dp_mod
from illuknit.core.errors import SolverError, UnknownNameError
from illuknit.design.models.backends.dp import solve_dp
from illuknit.design.models.illusion_models import (
    KnitWeights,
    build_model,
    make_problem,
    solve_illusion,
)
from illuknit.pictures.drawings import draw_ecg, draw_heart
from illuknit.solvers import BackendBase, Solution, Status, solve
from illuknit.solvers.model import Model


def _pair(n: int = 12, m: int = 10) -> tuple[np.ndarray, np.ndarray]:
    return draw_heart((n, m)).astype(np.int16), draw_ecg((n, m)).astype(np.int16)


def test_auto_solver_runs_the_dp_once(monkeypatch):
    calls = []

    def counted(problem):
        calls.append(1)
        return solve_dp(problem)

    monkeypatch.setattr(dp_mod, "solve_dp", counted)
    a, b = _pair()
    res = solve_illusion(a, b, solver="auto", warm_start="auto")
    assert res.solution.backend == "dp" and res.solution.found_by == "dp"
    assert len(calls) == 1


def test_no_warm_start_means_the_backend_found_it():
    a, b = _pair()
    model = build_model(make_problem(a, b))
    sol = solve(model, solver="rc2", warm_start="none")
    assert model.hint is None
    assert sol.found_by == "rc2" and sol.stats["warm_start"] == {"method": "none"}
    assert sol.objective == solve_dp(make_problem(a, b))[2]
    assert sol.found_at is not None and 0 <= sol.found_at <= sol.wall_time
    assert sol.finished_at.endswith("+00:00")


class _Nothing(BackendBase):
    """Gives up at once with nothing: whatever the solution holds came from the warm start."""

    name = "nothing"

    def solve(self, model, *, time_limit=None, seed=0, progress=None):
        return Solution(Status.TIMEOUT, None, None, None, 0.01, {}, self.name, model.pool)


def test_a_kept_warm_start_is_credited_to_the_warm_start(monkeypatch):
    import illuknit.solvers as reg

    monkeypatch.setitem(reg._registered, "nothing", _Nothing)
    a, b = _pair()
    problem = make_problem(a, b)
    sol = solve(build_model(problem), solver="nothing", warm_start="dp")
    assert sol.backend == "nothing" and sol.found_by == "dp"
    assert sol.stats["kept_warm_start"] and sol.objective == solve_dp(problem)[2]
    assert sol.trace and sol.trace[0][1] == sol.objective


def test_descent_warm_start_on_the_knit_aware_model_is_named():
    a, b = _pair()
    model = build_model(make_problem(a, b, kind="knit-aware", weights=KnitWeights(4, 1, 1)))
    sol = solve(model, solver="rc2", warm_start="descent", time_limit=4)
    assert sol.stats["warm_start"]["method"] == "descent"
    assert sol.found_by in ("rc2", "descent")
    ok, cost = model.evaluate(sol.values)
    assert ok and cost == sol.objective


def test_bad_policies_are_refused():
    m = Model("plain")
    m.add_soft([m.var("a")], 1)
    with pytest.raises(UnknownNameError, match="warm start"):
        solve(m, solver="rc2", warm_start="magic")
    with pytest.raises(SolverError, match="needs an illusion model"):
        solve(m, solver="rc2", warm_start="dp")
    assert solve(m, solver="rc2", warm_start="auto").found_by == "rc2"


class _Echo(BackendBase):
    """Times out and hands back its hint unchanged, as RC2's timeout fallback does."""

    name = "echo"

    def solve(self, model, *, time_limit=None, seed=0, progress=None):
        _, cost = model.evaluate(model.hint)
        return Solution(Status.TIMEOUT, model.hint, cost, None, 0.01, {}, self.name, model.pool)


def test_a_backend_echoing_its_warm_start_does_not_get_the_credit(monkeypatch):
    import illuknit.solvers as reg

    monkeypatch.setitem(reg._registered, "echo", _Echo)
    a, b = _pair()
    sol = solve(build_model(make_problem(a, b)), solver="echo", warm_start="dp")
    assert sol.backend == "echo" and sol.found_by == "dp"


class _Bounded(BackendBase):
    """Records the lower bound it is handed (it accepts one) and answers nothing."""

    name = "bounded"
    accepts_lower_bound = True
    seen: ClassVar[list] = []

    def solve(self, model, *, time_limit=None, seed=0, progress=None, lower_bound=None):
        _Bounded.seen.append(lower_bound)
        return Solution(Status.TIMEOUT, None, None, None, 0.01, {}, self.name, model.pool)


def test_the_warm_starts_bound_reaches_backends_that_accept_one(monkeypatch):
    """The descent warm start's Lagrangian bound is handed to a backend that takes a lower
    bound, not to one that does not (the echo), and is the solution's bound either way."""
    import illuknit.solvers as reg

    monkeypatch.setitem(reg._registered, "bounded", _Bounded)
    monkeypatch.setitem(reg._registered, "echo", _Echo)
    a, b = _pair(8, 6)
    model = build_model(make_problem(a, b, kind="knit-aware"))
    sol = solve(model, solver="bounded", warm_start="descent", time_limit=2)
    bound = sol.stats["warm_start"]["bound"]
    assert _Bounded.seen == [bound] and sol.bound == bound
    assert bound > solve_dp(model.problem)[2]  # the pass terms: the Lagrangian's, not the DP's
    assert solve(model, solver="echo", warm_start="descent", time_limit=2).bound == bound


def test_cpsat_and_lsu_stop_at_a_lower_bound_they_meet():
    """Handed the optimum as a lower bound, both prove it with the first model that meets it."""
    from illuknit.solvers import get_backend

    a, b = _pair(6, 5)
    model = build_model(make_problem(a, b, kind="knit-aware"))
    opt = solve(model, solver="cpsat", time_limit=20)
    assert opt.status is Status.OPTIMAL
    for name in ("cpsat", "lsu"):
        sol = get_backend(name).solve(model, time_limit=20, lower_bound=int(opt.objective))
        assert sol.status is Status.OPTIMAL and sol.objective == opt.objective == sol.bound
