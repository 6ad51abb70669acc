"""Block coordinate descent for the knit-aware model (b): exact block updates, never worse,
brute-force optima on tiny grids, the backend contract, and its use as a warm start."""

from __future__ import annotations

import itertools

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.design.models.backends.descent import optimise_descent
from illuknit.design.models.backends.descent_blocks import (
    pattern_cost,
    update_rows,
    update_units,
    update_wales,
)
from illuknit.design.models.backends.dp import solve_dp, values_from_pattern
from illuknit.design.models.illusion_models import (
    KnitWeights,
    build_model,
    make_problem,
    solve_illusion,
)
from illuknit.solvers import solve


def _problem(rng, n, m, k, *, pin=False):
    a = rng.integers(0, k, (n, m))
    b = rng.integers(0, k, (n, m))
    w = KnitWeights(
        view=int(rng.integers(1, 5)),
        color_change=int(rng.integers(0, 5)),
        transfer=int(rng.integers(0, 3)),
        machine_pass=0,  # the pass terms: tests/design/models/test_illusion_models.py
    )
    pinned = np.where(rng.random((n, m)) < 0.2, rng.integers(0, k, (n, m)), -1) if pin else None
    return make_problem(a, b, n_yarns=k, kind="knit-aware", weights=w, pinned=pinned)


def _random_pattern(rng, problem):
    n, m = problem.shape
    y = rng.integers(0, problem.n_yarns, (n, m))
    if problem.pinned is not None:
        y = np.where(problem.pinned >= 0, problem.pinned, y)
    return y, rng.random((n, m)) < 0.4


@settings(max_examples=40, deadline=None)
@given(
    n=st.integers(1, 7),
    m=st.integers(1, 7),
    k=st.integers(1, 3),
    seed=st.integers(0, 2**31),
    pin=st.booleans(),
)
def test_block_updates_never_increase_the_objective_and_agree_with_the_model(n, m, k, seed, pin):
    rng = np.random.default_rng(seed)
    problem = _problem(rng, n, m, k, pin=pin)
    model = build_model(problem)
    y, r = _random_pattern(rng, problem)
    cost = pattern_cost(problem, y, r)
    assert model.evaluate(values_from_pattern(model, y, r)) == (True, cost)
    for fn, size in ((update_wales, m), (update_rows, n)):
        for parity in (0, 1):
            idx = np.arange(parity, size, 2)
            if idx.size == 0:
                continue
            y, r = fn(problem, y, r, idx)
            new = pattern_cost(problem, y, r)
            assert new <= cost
            cost = new
    assert model.evaluate(values_from_pattern(model, y, r)) == (True, cost)


def _block_brute_force(problem, y, r, *, wale=None, row=None):
    """Best cost over every (yarn, raised) of one wale or one row, the rest fixed."""
    k = problem.n_yarns
    cells = problem.shape[0] if wale is not None else problem.shape[1]
    best = None
    for states in itertools.product(range(2 * k), repeat=cells):
        s = np.array(states)
        yy, rr = y.copy(), r.copy()
        if wale is not None:
            yy[:, wale], rr[:, wale] = s // 2, s % 2 == 1
        else:
            yy[row], rr[row] = s // 2, s % 2 == 1
        c = pattern_cost(problem, yy, rr)
        best = c if best is None else min(best, c)
    return best


@settings(max_examples=30, deadline=None)
@given(n=st.integers(1, 4), m=st.integers(1, 4), k=st.integers(1, 2), seed=st.integers(0, 2**31))
def test_one_wale_or_row_is_reoptimised_exactly(n, m, k, seed):
    rng = np.random.default_rng(seed)
    problem = _problem(rng, n, m, k)
    y, r = _random_pattern(rng, problem)
    j = int(rng.integers(0, m))
    y2, r2 = update_wales(problem, y, r, np.array([j]))
    assert pattern_cost(problem, y2, r2) == _block_brute_force(problem, y, r, wale=j)
    assert np.array_equal(np.delete(y2, j, axis=1), np.delete(y, j, axis=1))
    i = int(rng.integers(0, n))
    y3, r3 = update_rows(problem, y, r, np.array([i]))
    assert pattern_cost(problem, y3, r3) == _block_brute_force(problem, y, r, row=i)
    assert np.array_equal(np.delete(r3, i, axis=0), np.delete(r, i, axis=0))


def _brute_force_optimum(problem) -> int:
    """Optimum over every pattern, all scored at once (numpy over the enumeration)."""
    n, m = problem.shape
    k = problem.n_yarns
    cells = n * m
    ys = np.array(list(itertools.product(range(k), repeat=cells))).reshape(-1, 1, n, m)
    rs = np.array(list(itertools.product((False, True), repeat=cells))).reshape(1, -1, n, m)
    c = np.broadcast_to(ys, (ys.shape[0], rs.shape[1], n, m))
    r = np.broadcast_to(rs, c.shape)
    va, vb = c.copy(), c.copy()
    va[..., 1:, :] = np.where(r[..., :-1, :], c[..., :-1, :], c[..., 1:, :])
    vb[..., :-1, :] = np.where(r[..., 1:, :], c[..., 1:, :], c[..., :-1, :])
    mis = (va != problem.target_a).sum((-2, -1)) + (vb != problem.target_b).sum((-2, -1))
    bumps = 2 * r[..., 1:, :].sum((-2, -1)) + r[..., :1, :].sum((-2, -1))
    changes = (c[..., :, 1:] != c[..., :, :-1]).sum((-2, -1))
    cost = (
        problem.view_weight * mis + problem.transfer_weight * bumps + problem.color_weight * changes
    )
    return int(cost.min())


def test_descent_reaches_the_brute_force_optimum_on_tiny_grids():
    rng = np.random.default_rng(7)
    hits = trials = 0
    for _ in range(30):
        n, m = [(2, 2), (2, 3), (3, 2), (2, 4), (4, 2)][int(rng.integers(0, 5))]
        problem = _problem(rng, n, m, 2)
        want = _brute_force_optimum(problem)
        res = optimise_descent(problem, seed=int(rng.integers(0, 1000)), stall=15)
        assert res.cost == pattern_cost(problem, res.yarn, res.raised)
        assert res.bound <= want <= res.cost  # never below the optimum; the DP bound is valid
        hits += res.cost == want
        trials += 1
    # a local search, but on grids this small it nearly always finds the optimum
    assert hits >= 0.8 * trials, (hits, trials)


def test_backend_objective_equals_the_model_and_bound_is_at_least_the_dp():
    rng = np.random.default_rng(1)
    problem = make_problem(
        rng.integers(0, 3, (12, 10)),
        rng.integers(0, 3, (12, 10)),
        n_yarns=3,
        kind="knit-aware",
        weights=KnitWeights(view=4, color_change=2, transfer=1),
    )
    model = build_model(problem)
    sol = solve(model, solver="descent", time_limit=3)
    assert sol.status.value in ("feasible", "timeout", "optimal")
    assert model.evaluate(sol.values) == (True, sol.objective)
    # with machine-pass terms the Lagrangian bound (test_lagrangian.py beside this) is better
    assert solve_dp(problem)[2] <= sol.bound <= sol.objective
    dp_start = pattern_cost(problem, *solve_dp(problem)[:2])
    assert sol.objective <= dp_start


def test_descent_solves_per_wale_models_exactly():
    rng = np.random.default_rng(2)
    a, b = rng.integers(0, 2, (8, 6)), rng.integers(0, 2, (8, 6))
    model = build_model(make_problem(a, b, n_yarns=2))
    sol = solve(model, solver="descent")
    assert sol.status.value == "optimal"
    assert sol.objective == solve(model, solver="dp").objective


def test_knit_aware_solve_is_never_worse_than_its_descent_warm_start():
    rng = np.random.default_rng(3)
    a, b = rng.integers(0, 2, (14, 14)), rng.integers(0, 2, (14, 14))
    w = KnitWeights(view=4, color_change=2, transfer=1)
    res = solve_illusion(a, b, model="knit-aware", solver="cpsat", weights=w, time_limit=4)
    ws = res.solution.stats["warm_start"]
    assert ws["method"] == "descent"
    assert res.solution.objective <= ws["objective"]
    model = build_model(res.problem)
    assert model.evaluate(res.solution.values) == (True, res.solution.objective)


def test_ctrl_c_keeps_the_best_pattern_found_so_far(monkeypatch):
    import illuknit.design.models.backends.descent as descent_mod

    rng = np.random.default_rng(4)
    problem = make_problem(
        rng.integers(0, 2, (10, 10)),
        rng.integers(0, 2, (10, 10)),
        n_yarns=2,
        kind="knit-aware",
        weights=KnitWeights(view=2, color_change=3, transfer=1),
    )
    real = descent_mod.descend
    calls = {"n": 0}

    def interrupted_later(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] > 3:
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    monkeypatch.setattr(descent_mod, "descend", interrupted_later)
    model = build_model(problem)
    sol = solve(model, solver="descent")
    assert sol.stats["interrupted"] is True
    assert sol.status.value in ("feasible", "optimal")
    assert model.evaluate(sol.values) == (True, sol.objective)
    # at least as good as the descended DP start, which finished before the interrupt
    assert sol.objective <= sol.stats["starts"]["dp"]


def test_cli_solves_the_knit_aware_model_with_descent(tmp_path):
    import json

    from PIL import Image

    from illuknit.cli import main

    yy, xx = np.mgrid[0:12, 0:10]
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    Image.fromarray(np.where((xx + yy) % 5 < 2, 25, 235).astype(np.uint8)).save(a)
    Image.fromarray(np.where((xx - 5) ** 2 + (yy - 6) ** 2 < 12, 25, 235).astype(np.uint8)).save(b)
    out = tmp_path / "out"
    main(
        [
            "solve",
            str(a),
            str(b),
            "--model",
            "knit-aware",
            "--solver",
            "descent",
            "--time-limit",
            "3",
            "-o",
            str(out),
        ]
    )
    rep = json.loads((out / "report.json").read_text())
    assert rep["solver"]["backend"] == "descent"
    assert rep["solver"]["bound"] <= rep["solver"]["objective"]
    w = rep["weights"]
    errs = rep["logical_error"]["A"]["cells"] + rep["logical_error"]["B"]["cells"]
    assert rep["solver"]["objective"] == (
        w["view"] * errs
        + w["color_change"] * rep["color_changes_per_course"]["total"]
        + w["transfer"] * rep["knit_purl_changes"]
        + w["machine_pass"] * rep["machine_pass_events"]["passes"]
    )


@settings(max_examples=40, deadline=None)
@given(
    n=st.integers(1, 4),
    m=st.integers(1, 12),
    k=st.integers(2, 3),
    gap=st.integers(1, 3),
    seed=st.integers(0, 2**16),
)
def test_unit_move_is_the_best_single_change_of_each_row(n, m, k, gap, seed):
    """update_units against brute force: every single-unit change of each updated row scored
    by the full objective (extra carriers and bump-row segments included)."""
    rng = np.random.default_rng(seed)
    w = KnitWeights(view=3, color_change=1, transfer=1, machine_pass=2, float_gap=gap)
    problem = make_problem(
        rng.integers(0, k, (n, m)),
        rng.integers(0, k, (n, m)),
        n_yarns=k,
        kind="knit-aware",
        weights=w,
    )
    yarn = rng.integers(0, k, (n, m))
    raised = rng.random((n, m)) < 0.3
    base = pattern_cost(problem, yarn, raised)
    rows = np.arange(seed % 2, n, 2)
    y2, r2 = update_units(problem, yarn, raised, rows)
    expected = base
    for i in rows:
        best = 0
        for j, c, rr in itertools.product(range(m), range(k), (False, True)):
            y, r = yarn.copy(), raised.copy()
            y[i, j], r[i, j] = c, rr
            best = min(best, pattern_cost(problem, y, r) - base)
        expected += best
    assert pattern_cost(problem, y2, r2) == expected
    changed = (y2 != yarn) | (r2 != raised)
    assert changed.sum() <= len(rows) and not changed[np.setdiff1d(np.arange(n), rows)].any()
