"""Every available backend on the same cases (cvxpy-style conformance suite).

Backends that are not installed are skipped; the external-binary backend runs through the fake
solver script in ``tests/solvers/fake``.
"""

from __future__ import annotations

import itertools
import sys
from pathlib import Path

import numpy as np
import pytest

from illuknit.core.views import can_see
from illuknit.design.models.illusion_models import (
    KnitWeights,
    build_model,
    color_changes_per_course,
    knit_purl_changes,
    make_problem,
)
from illuknit.design.models.illusion_problem import row_passes
from illuknit.solvers import (
    HERMAX_NAMES,
    available_backends,
    backend_names,
    get_backend,
    solve,
)
from illuknit.solvers.model import Model

FAKE = Path(__file__).parent / "fake" / "fake_maxsat.py"
EXTERNAL = f"wcnf:{sys.executable} {FAKE} {{}}"


def _exact(name: str) -> bool:
    try:
        return bool(getattr(get_backend(name, check_available=False), "exact", True))
    except Exception:
        return False


# exact backends for every model (the DP only for per-wale illusion models)
GENERIC = [n for n in backend_names() if n != "dp" and _exact(n)] + [EXTERNAL]
HEURISTIC = [n for n in backend_names() if not _exact(n)]


#: backends that run in a child process (a fork each); the brute-force sweep gives them a few cases
CHILD = {"fm", *HERMAX_NAMES}


def _backend_or_skip(name: str):
    if name != EXTERNAL and name not in available_backends():
        pytest.skip(f"backend {name} not installed")
    return get_backend(name)


def _brute_force_cost(problem) -> int | None:
    """Optimum of an illusion problem by enumerating every pattern, scored with can_see."""
    n, m = problem.shape
    k = problem.n_yarns
    best = None
    cells = n * m
    for ys in itertools.product(range(k), repeat=cells):
        yarn = np.array(ys).reshape(n, m)
        if problem.pinned is not None and np.any((problem.pinned >= 0) & (problem.pinned != yarn)):
            continue
        if problem.rows_tied and np.any(yarn != yarn[:, :1]):
            continue  # the single-view model: one yarn per course
        if problem.alternate_rows and np.any(yarn[1:, 0] == yarn[:-1, 0]):
            continue
        cc = color_changes_per_course(yarn)
        if problem.color_cap is not None and cc.max(initial=0) > problem.color_cap:
            continue
        for rs in itertools.product((False, True), repeat=cells):
            raised = np.array(rs).reshape(n, m)
            err = int((can_see(yarn, "A", raised) != problem.target_a).sum())
            err += int((can_see(yarn, "B", raised) != problem.target_b).sum())
            cost = problem.view_weight * err
            cost += problem.transfer_weight * knit_purl_changes(raised)
            cost += problem.color_weight * int(cc.sum())
            if problem.pass_weight:
                passes = row_passes(yarn, raised, k, problem.weights.float_gap)
                cost += problem.pass_weight * int(passes.sum())
            if best is None or cost < best:
                best = cost
    return best


def _tiny_cases():
    rng = np.random.default_rng(11)
    cases = []
    for shape, k in [((2, 2), 2), ((3, 1), 3), ((3, 2), 2), ((1, 3), 2), ((4, 1), 2)]:
        a = rng.integers(0, k, shape)
        b = rng.integers(0, k, shape)
        cases.append(make_problem(a, b, n_yarns=k, kind="logical"))
        cases.append(make_problem(a, None, n_yarns=k, kind="single"))
        cases.append(make_problem(a, None, n_yarns=k, kind="single", alternate_rows=True))
        w = KnitWeights(view=3, color_change=int(rng.integers(1, 3)), transfer=1)
        cases.append(make_problem(a, b, n_yarns=k, kind="knit-aware", weights=w))
    w = KnitWeights(view=2, color_change=1, transfer=1, max_color_changes=0)
    cases.append(
        make_problem(
            np.array([[0, 1], [1, 0]]), np.array([[1, 1], [0, 1]]), kind="knit-aware", weights=w
        )
    )
    return cases


TINY = _tiny_cases()


@pytest.mark.parametrize("case", range(len(TINY)))
def test_brute_force_confirms_every_backend(case):
    problem = TINY[case]
    want = _brute_force_cost(problem)
    model = build_model(problem)
    for name in ["dp", *GENERIC]:
        if name != EXTERNAL and name not in available_backends():
            continue
        if name in CHILD and case % 4:
            continue
        backend = get_backend(name)
        if not backend.handles(model):
            assert name == "dp" and not (problem.per_wale or problem.rows_tied)
            continue
        sol = solve(model, solver=name)
        assert sol.status.value == "optimal", (name, sol)
        assert sol.objective == want, (name, problem.kind)
        assert sol.bound == want
        assert model.evaluate(sol.values) == (True, want)


def _random_instance(seed: int, shape=(6, 5), k=2, kind="logical"):
    rng = np.random.default_rng(seed)
    a = rng.integers(0, k, shape)
    b = rng.integers(0, k, shape)
    return make_problem(
        a, b, n_yarns=k, kind=kind, weights=KnitWeights(view=3, color_change=1, transfer=1)
    )


@pytest.mark.parametrize("name", ["cpsat", "rc2", "lsu", EXTERNAL])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_small_logical_instances_reach_the_dp_optimum(name, seed):
    _backend_or_skip(name)
    problem = _random_instance(seed, shape=(6, 5), k=2 + seed % 2)
    model = build_model(problem)
    ref = solve(model, solver="dp")
    sol = solve(model, solver=name)
    assert sol.status.value == "optimal"
    assert sol.objective == ref.objective


@pytest.mark.parametrize("name", ["rc2", "lsu", EXTERNAL])
@pytest.mark.parametrize("seed", [3, 4])
def test_knit_aware_backends_agree_with_cpsat(name, seed):
    _backend_or_skip(name)
    _backend_or_skip("cpsat")
    problem = _random_instance(seed, shape=(5, 4), kind="knit-aware")
    model = build_model(problem)
    ref = solve(model, solver="cpsat")
    sol = solve(model, solver=name)
    assert ref.status.value == sol.status.value == "optimal"
    assert sol.objective == ref.objective


def _generic_model(seed: int) -> Model:
    rng = np.random.default_rng(seed)
    m = Model("generic")
    ids = m.pool.block("v", (7,))
    for _ in range(5):
        lits = rng.choice(ids, size=3, replace=False) * rng.choice([-1, 1], size=3)
        m.add_hard(lits.tolist())
    for _ in range(9):
        w = int(rng.integers(1, 3))
        lits = rng.choice(ids, size=w, replace=False) * rng.choice([-1, 1], size=w)
        m.add_soft(lits.tolist(), int(rng.integers(1, 6)))
    m.add_at_most_k(ids[:5].tolist(), 2)
    m.add_linear_le(ids[2:].tolist(), [2, -1, 3, 1, 2], 4)
    return m


def _generic_optimum(m: Model) -> int | None:
    best = None
    for bits in itertools.product((False, True), repeat=m.pool.top):
        ok, cost = m.evaluate(np.array([False, *bits]))
        if ok and (best is None or cost < best):
            best = cost
    return best


@pytest.mark.parametrize("name", GENERIC)
@pytest.mark.parametrize("seed", range(4))
def test_generic_weighted_models_with_native_constraints(name, seed):
    _backend_or_skip(name)
    m = _generic_model(seed)
    want = _generic_optimum(m)
    sol = solve(m, solver=name)
    if want is None:
        assert sol.status.value == "infeasible"
    else:
        assert sol.status.value == "optimal"
        assert sol.objective == want


@pytest.mark.parametrize("name", GENERIC)
def test_infeasible_hard_constraints_give_status_infeasible(name):
    # (the DP's per-wale models are always feasible: pins alone never conflict)
    backend = _backend_or_skip(name)
    w = KnitWeights(view=1, color_change=1, transfer=0, max_color_changes=0)
    pinned = np.array([[0, 1], [-1, -1]])
    problem = make_problem(
        np.zeros((2, 2), int), None, n_yarns=2, kind="knit-aware", weights=w, pinned=pinned
    )
    model = build_model(problem)
    if not backend.handles(model):
        pytest.skip("backend does not handle cross-wale models")
    sol = solve(model, solver=name)
    assert sol.status.value == "infeasible"
    assert not sol.has_values
    assert "colour-change cap per course" in sol.stats["infeasible_families"]
    assert "pinned units" in sol.stats["infeasible_families"]


@pytest.mark.parametrize("name", ["cpsat", "rc2", "lsu"])
def test_time_limit_returns_the_best_found_with_a_bound(name):
    _backend_or_skip(name)
    problem = _random_instance(5, shape=(40, 40), kind="knit-aware")
    model = build_model(problem)
    from illuknit.design.models.backends.dp import hint_values

    model.hint = hint_values(problem, model)
    sol = solve(model, solver=name, time_limit=0.5)
    # LSU may give up early (status feasible) when its bound encoding would be too large
    assert sol.status.value in ("timeout", "optimal", "feasible")
    assert sol.has_values
    ok, cost = model.evaluate(sol.values)
    assert ok and cost == sol.objective
    assert cost <= model.evaluate(model.hint)[1]  # never worse than the warm start
    if sol.bound is not None:
        assert sol.bound <= sol.objective


@pytest.mark.parametrize("name", HEURISTIC or ["(none)"])
def test_heuristic_backends_keep_the_solution_contract(name):
    if name == "(none)":
        pytest.skip("no heuristic backend registered")
    backend = _backend_or_skip(name)
    problem = _random_instance(6, shape=(6, 5), kind="logical")
    model = build_model(problem)
    if not backend.handles(model):
        pytest.skip(f"{name} does not handle the logical model")
    ref = solve(model, solver="dp")
    sol = solve(model, solver=name, time_limit=5)
    assert sol.status.value in ("feasible", "timeout", "optimal")
    assert sol.has_values
    ok, cost = model.evaluate(sol.values)
    assert ok and cost == sol.objective >= ref.objective
