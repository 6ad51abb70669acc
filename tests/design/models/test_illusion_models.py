"""Illusion models (a) logical, (b) knit-aware, (c) single-view; the exact DP; reports."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.core.errors import (
    ImageInputError,
    InfeasibleError,
    OptionError,
    SolverError,
    UnknownNameError,
)
from illuknit.core.pattern import LogicalPattern, Yarn
from illuknit.core.views import can_see
from illuknit.design.models.backends.dp import solve_dp, values_from_pattern
from illuknit.design.models.illusion_models import (
    KnitWeights,
    build_model,
    color_changes_per_course,
    knit_purl_changes,
    make_problem,
    parse_weights,
    report_pattern,
    solve_illusion,
)
from illuknit.solvers import solve


def _wale_brute_force(problem) -> int:
    """Optimum by enumerating every (yarn, raised) column independently (per-wale problems)."""
    n, m = problem.shape
    k = problem.n_yarns
    total = 0
    for j in range(m):
        a = problem.target_a[:, j : j + 1]
        b = problem.target_b[:, j : j + 1]
        best = None
        for ys in itertools.product(range(k), repeat=n):
            yarn = np.array(ys).reshape(n, 1)
            if problem.pinned is not None:
                p = problem.pinned[:, j : j + 1]
                if np.any((p >= 0) & (p != yarn)):
                    continue
            for rs in itertools.product((False, True), repeat=n):
                raised = np.array(rs).reshape(n, 1)
                err = int(
                    (can_see(yarn, "A", raised) != a).sum()
                    + (can_see(yarn, "B", raised) != b).sum()
                )
                cost = problem.view_weight * err + problem.transfer_weight * knit_purl_changes(
                    raised
                )
                best = cost if best is None else min(best, cost)
        total += best
    return total


@settings(max_examples=60, deadline=None)
@given(
    n=st.integers(1, 5),
    m=st.integers(1, 3),
    k=st.integers(1, 3),
    kind=st.sampled_from(["logical", "knit-aware"]),
    seed=st.integers(0, 2**31),
    pin=st.booleans(),
)
def test_dp_equals_brute_force_on_tiny_grids(n, m, k, kind, seed, pin):
    rng = np.random.default_rng(seed)
    a = rng.integers(0, k, (n, m))
    b = rng.integers(0, k, (n, m))
    pinned = np.where(rng.random((n, m)) < 0.3, rng.integers(0, k, (n, m)), -1) if pin else None
    w = KnitWeights(
        view=int(rng.integers(1, 4)),
        color_change=0,
        transfer=int(rng.integers(0, 3)),
        machine_pass=0,
    )
    problem = make_problem(a, b, n_yarns=k, kind=kind, weights=w, pinned=pinned)
    yarn, raised, cost = solve_dp(problem)
    assert cost == _wale_brute_force(problem)
    # the DP's pattern really has that cost in the clause model
    model = build_model(problem)
    assert model.evaluate(values_from_pattern(model, yarn, raised)) == (True, cost)


def test_dp_optimum_is_zero_when_the_targets_are_a_perfect_illusion():
    # any pattern's views are perfect targets for it
    rng = np.random.default_rng(3)
    yarn = rng.integers(0, 3, (12, 9))
    raised = rng.random((12, 9)) < 0.4
    ta, tb = can_see(yarn, "A", raised), can_see(yarn, "B", raised)
    res = solve_illusion(ta, tb, n_yarns=3, solver="dp")
    assert res.solution.objective == 0
    assert np.array_equal(can_see(res.pattern, "A"), ta)
    assert np.array_equal(can_see(res.pattern, "B"), tb)


def _single_brute_force(problem) -> int | None:
    """Optimum with one yarn per row: every row colouring x every raised grid (numpy)."""
    n, m = problem.shape
    k = problem.n_yarns
    rs = np.array(list(itertools.product((False, True), repeat=n * m))).reshape(-1, n, m)
    best = None
    for rows in itertools.product(range(k), repeat=n):
        if problem.alternate_rows and any(x == y for x, y in itertools.pairwise(rows)):
            continue
        yarn = np.repeat(np.array(rows)[:, None], m, axis=1)
        if problem.pinned is not None and np.any((problem.pinned >= 0) & (problem.pinned != yarn)):
            continue
        c = np.broadcast_to(yarn, rs.shape)
        va, vb = c.copy(), c.copy()
        va[:, 1:] = np.where(rs[:, :-1], c[:, :-1], c[:, 1:])
        vb[:, :-1] = np.where(rs[:, 1:], c[:, 1:], c[:, :-1])
        err = (va != problem.target_a).sum((1, 2)) + (vb != problem.target_b).sum((1, 2))
        cost = int(err.min())
        best = cost if best is None else min(best, cost)
    return best


@settings(max_examples=40, deadline=None)
@given(
    n=st.integers(1, 4),
    m=st.integers(1, 3),
    k=st.integers(1, 3),
    alternate=st.booleans(),
    seed=st.integers(0, 2**31),
    pin=st.booleans(),
)
def test_single_view_dp_equals_brute_force_with_one_yarn_per_row(n, m, k, alternate, seed, pin):
    rng = np.random.default_rng(seed)
    target = rng.integers(0, k, (n, m))
    pinned = np.where(rng.random((n, m)) < 0.15, rng.integers(0, k, (n, m)), -1) if pin else None
    problem = make_problem(
        target, None, n_yarns=k, kind="single", alternate_rows=alternate, pinned=pinned
    )
    want = _single_brute_force(problem)
    yarn, raised, cost = solve_dp(problem)
    if want is None:  # pins in two yarns on one row, or alternation with one yarn
        assert cost >= 2**40
        assert solve(build_model(problem), solver="dp").status.value == "infeasible"
        return
    assert cost == want
    assert np.all(yarn == yarn[:, :1])  # a plain stripe head-on
    model = build_model(problem)
    assert model.evaluate(values_from_pattern(model, yarn, raised)) == (True, cost)


@settings(max_examples=30, deadline=None)
@given(
    n=st.integers(2, 16),
    m=st.integers(1, 12),
    k=st.sampled_from([2, 3]),
    first=st.sampled_from(["dark", "light"]),
    seed=st.integers(0, 2**31),
)
def test_single_view_model_contains_and_beats_the_push_button_compiler(n, m, k, first, seed):
    from illuknit.design.single_view import compile_single_view, single_view_roles

    rng = np.random.default_rng(seed)
    target = rng.integers(0, k, (n, m)).astype(np.int16)
    yarns = (Yarn("dark", (20, 20, 20)), Yarn("light", (240, 240, 240)), Yarn("mid", (128,) * 3))
    yarns = yarns[:k]
    compiled = compile_single_view(target, yarns=yarns, first=first)
    c1, c2, _ = single_view_roles(yarns, first=first)
    used = np.array(sorted((c1, c2)))
    comp_yarn = used[compiled.yarn]  # back to the picture's yarn indices
    for alternate in (False, True):
        problem = make_problem(target, None, n_yarns=k, kind="single", alternate_rows=alternate)
        model = build_model(problem)
        ok, comp_cost = model.evaluate(values_from_pattern(model, comp_yarn, compiled.raised))
        assert ok  # the compiler's pattern is feasible in model (c)
        res = solve_illusion(
            target, model="single", yarns=yarns, solver="dp", alternate_rows=alternate
        )
        assert res.solution.status.value == "optimal"
        assert res.solution.objective <= comp_cost
        assert np.all(res.pattern.yarn == res.pattern.yarn[:, :1])


def test_report_fields_are_hand_checkable():
    yarn = np.array([[0, 1, 1], [0, 0, 1]])
    raised = np.array([[True, False, False], [False, True, False]])
    yarns = (Yarn("a", (0, 0, 0)), Yarn("b", (255, 255, 255)))
    pat = LogicalPattern(yarn, raised, yarns)
    problem = make_problem(can_see(pat, "A"), np.zeros((2, 3), int), n_yarns=2)
    rep = report_pattern(pat, problem)
    assert rep["logical_error"]["A"]["cells"] == 0
    assert rep["logical_error"]["B"]["cells"] == int((can_see(pat, "B") != 0).sum())
    assert rep["color_changes_per_course"] == {"mean": 1.0, "max": 1, "total": 2}
    assert rep["raised_units"] == 2
    assert rep["knit_purl_changes"] == 1 + 2  # top-row bump 1, lower bump 2
    assert list(color_changes_per_course(yarn)) == [1, 1]


def test_knit_aware_model_trades_error_for_fewer_changes():
    rng = np.random.default_rng(2)
    a = rng.integers(0, 2, (10, 10))
    b = rng.integers(0, 2, (10, 10))
    base = solve_illusion(a, b, model="logical", solver="dp")
    knit = solve_illusion(
        a,
        b,
        model="knit-aware",
        solver="cpsat",
        time_limit=20,
        weights=KnitWeights(view=1, color_change=3, transfer=2),
    )
    assert (
        knit.report["color_changes_per_course"]["total"]
        < base.report["color_changes_per_course"]["total"]
    )
    assert knit.report["knit_purl_changes"] <= base.report["knit_purl_changes"]


def test_color_change_cap_is_respected():
    rng = np.random.default_rng(4)
    a = rng.integers(0, 2, (6, 8))
    b = rng.integers(0, 2, (6, 8))
    res = solve_illusion(
        a,
        b,
        model="knit-aware",
        solver="cpsat",
        time_limit=20,
        weights=KnitWeights(view=2, color_change=0, transfer=0, max_color_changes=1),
    )
    assert res.report["color_changes_per_course"]["max"] <= 1


def test_dp_refuses_cross_wale_models_with_a_reason():
    problem = make_problem(
        np.zeros((2, 2), int), np.zeros((2, 2), int), n_yarns=2, kind="knit-aware"
    )
    with pytest.raises(SolverError, match="couple the wales"):
        solve(build_model(problem), solver="dp")


def test_targets_of_different_sizes_are_a_clear_error():
    with pytest.raises(ImageInputError, match=r"same size.*--resize"):
        make_problem(np.zeros((3, 4), int), np.zeros((4, 3), int))


def test_yarn_index_outside_the_palette_is_a_clear_error():
    with pytest.raises(
        ImageInputError, match="`target_b` holds yarn index 3, outside the palette of 2"
    ):
        make_problem(np.zeros((3, 3), int), np.full((3, 3), 3), n_yarns=2)
    with pytest.raises(ImageInputError, match="index -1"):
        make_problem(np.full((3, 3), -1), None, n_yarns=2)
    yarns = (Yarn("a", (0, 0, 0)), Yarn("b", (255, 255, 255)))
    with pytest.raises(ImageInputError, match="outside the palette"):
        solve_illusion(np.zeros((2, 2), int), np.full((2, 2), 2), yarns=yarns)


def test_infeasible_hard_constraints_name_the_families():
    w = KnitWeights(view=1, color_change=0, transfer=0, max_color_changes=1)
    pinned = np.array([[0, 1, 0], [-1, -1, -1]])
    with pytest.raises(
        InfeasibleError,
        match=r"colour-change cap per course.*pinned units|pinned units.*colour-change cap",
    ):
        solve_illusion(
            np.zeros((2, 3), int),
            np.zeros((2, 3), int),
            model="knit-aware",
            n_yarns=2,
            weights=w,
            pinned=pinned,
            solver="rc2",
        )


def test_unknown_model_and_weights_names_list_the_valid_ones():
    with pytest.raises(UnknownNameError, match="logical, knit-aware, single"):
        solve_illusion(np.zeros((2, 2), int), model="fancy")
    with pytest.raises(UnknownNameError, match="view=N"):
        parse_weights("speed=3")
    assert parse_weights("view=5,colour=2,cap=3") == KnitWeights(5, 2, 0, 3)
    with pytest.raises(OptionError, match="integer"):
        parse_weights("view=abc")
    with pytest.raises(OptionError, match="view"):
        KnitWeights(view=-1)


def test_machine_pass_terms_match_brute_force_and_the_descent_objective():
    """Yarns per row, bump rows and extra carriers (regions beyond the float gap), encoded as
    clauses, against a brute force over every pattern of a 1 x 5 strip and a 2 x 2 grid."""
    import itertools

    from illuknit.design.models.backends.descent_blocks import pattern_cost
    from illuknit.design.models.backends.dp import values_from_pattern
    from illuknit.design.models.illusion_problem import pass_events

    rng = np.random.default_rng(3)
    for shape, gap in (((1, 5), 1), ((2, 2), 1), ((1, 5), 2)):
        a = rng.integers(0, 2, shape)
        b = rng.integers(0, 2, shape)
        w = KnitWeights(view=3, color_change=1, transfer=1, machine_pass=1, float_gap=gap)
        problem = make_problem(a, b, n_yarns=2, kind="knit-aware", weights=w)
        model = build_model(problem)
        best = None
        cells = shape[0] * shape[1]
        for ys in itertools.product((0, 1), repeat=cells):
            yarn = np.array(ys).reshape(shape)
            for rs in itertools.product((False, True), repeat=cells):
                raised = np.array(rs).reshape(shape)
                ok, cost = model.evaluate(values_from_pattern(model, yarn, raised))
                assert ok and cost == pattern_cost(problem, yarn, raised)
                used, _, _ = pass_events(yarn, raised, 2, gap)
                assert used.sum() == sum(len(set(row)) for row in yarn.tolist())
                best = cost if best is None else min(best, cost)
        for name in ("rc2", "cpsat", "descent"):
            sol = solve(build_model(problem), solver=name, time_limit=20)
            assert sol.objective >= best
            if name != "descent":
                assert sol.status.value == "optimal" and sol.objective == best, name


def test_extra_carriers_count_regions_beyond_the_float_gap():
    from illuknit.design.models.illusion_problem import pass_events

    yarn = np.array([[0, 1, 1, 1, 0, 1, 0, 0]])
    used, bumps, extra = pass_events(yarn, np.zeros_like(yarn, bool), 2, 2)
    # yarn 0 jumps 3 units (1..3) -> a new carrier at column 4; yarn 1's gaps are 1 and 0
    assert used.tolist() == [2] and bumps.tolist() == [False] and extra.tolist() == [1]


def _scheduler_row_passes(yarn: np.ndarray, raised: np.ndarray, gap: int) -> np.ndarray:
    """Passes per unit row counted on the scheduler's own carrier plan: the carrier segments
    :func:`~illuknit.knit.color_runs.plan_color_runs` gives each of the row's two courses (float
    limit ``2 gap`` stitches = ``gap`` units), plus ``S + 1`` transfer passes for a row with a
    bump (docs/solvers.md, "Machine passes")."""
    from illuknit.knit.color_runs import plan_color_runs
    from illuknit.knit.stitches import lower_to_stitches

    pat = LogicalPattern(yarn, raised, tuple(Yarn(f"y{i}", (i, i, i)) for i in range(3)))
    st_yarn = lower_to_stitches(pat, cast_on_courses=0).yarn
    plan = plan_color_runs(st_yarn, carriers=[str(c) for c in range(40)], float_limit=2 * gap)
    n = yarn.shape[0]
    out = np.zeros(n, dtype=np.int64)
    for c, cp in enumerate(plan.courses):
        out[n - 1 - c // 2] += len(cp.segments)
    segments = out // 2
    return out + raised.any(axis=1) * (segments + 1)


@settings(max_examples=25, deadline=None)
@given(
    n=st.integers(1, 3),
    m=st.integers(1, 9),
    k=st.integers(2, 3),
    gap=st.integers(1, 3),
    seed=st.integers(0, 2**16),
)
def test_pass_term_equals_a_count_on_the_scheduler_plan(n, m, k, gap, seed):
    """With a pattern pinned, the knit-aware model's optimum (CP-SAT over its auxiliary pass
    variables) is its view, colour and transfer cost plus ``machine_pass`` times the passes
    counted on the scheduler's carrier plan of the decoded pattern."""
    from illuknit.design.models.backends.descent import pattern_cost
    from illuknit.design.models.illusion_problem import row_passes

    rng = np.random.default_rng(seed)
    yarn = rng.integers(0, k, (n, m))
    raised = rng.random((n, m)) < 0.3
    w = KnitWeights(view=2, color_change=1, transfer=1, machine_pass=3, float_gap=gap)
    problem = make_problem(
        rng.integers(0, k, (n, m)),
        rng.integers(0, k, (n, m)),
        n_yarns=k,
        kind="knit-aware",
        weights=w,
    )
    model = build_model(problem)
    x = model.pool.block_ids("yarn")
    r = model.pool.block_ids("raised")
    for (i, j), v in np.ndenumerate(yarn):
        model.add_hard([int(x[i, j, v])], family="test pin")
        model.add_hard([int(r[i, j]) if raised[i, j] else -int(r[i, j])], family="test pin")
    sol = solve(model, solver="cpsat", time_limit=30)
    assert sol.status.value == "optimal"
    assert np.array_equal(sol.block("yarn").argmax(axis=-1), yarn)
    direct = _scheduler_row_passes(yarn, raised, gap)
    assert np.array_equal(row_passes(yarn, raised, k, gap), direct)
    no_pass = make_problem(
        problem.target_a,
        problem.target_b,
        n_yarns=k,
        kind="knit-aware",
        weights=KnitWeights(view=2, color_change=1, transfer=1, machine_pass=0, float_gap=gap),
    )
    expected = pattern_cost(no_pass, yarn, raised) + 3 * int(direct.sum())
    assert sol.objective == expected == pattern_cost(problem, yarn, raised)


def test_knit_aware_pattern_knits_in_fewer_machine_passes_than_the_maxsat_optimum():
    """On a small two-picture instance, counted on the SWG machine's passes for the emitted
    knitout (:func:`illuknit.formats.machine_passes`)."""
    from illuknit.bench.instances import instance_targets, load_manifest
    from illuknit.formats import machine_passes
    from illuknit.knitting import knit_pattern

    inst = next(i for i in load_manifest().instances if i.name == "heart-ecg")
    t = instance_targets(inst)
    passes = {}
    for model, solver in (("logical", "dp"), ("knit-aware", "descent")):
        res = solve_illusion(t.a, t.b, model=model, solver=solver, yarns=inst.yarns, time_limit=30)
        passes[model] = len(machine_passes(knit_pattern(res.pattern).text))
    assert passes["knit-aware"] < passes["logical"], passes


def test_solve_options_and_their_keywords_solve_alike():
    from illuknit.design.options import SolveOptions

    ta = np.array([[0, 1, 1], [1, 0, 2], [2, 2, 0]])
    tb = np.array([[1, 1, 0], [0, 2, 2], [2, 0, 1]])
    options = SolveOptions(model="knit-aware", solver="rc2", warm_start="none", time_limit=None)
    by_options = solve_illusion(ta, tb, n_yarns=3, options=options)
    by_keywords = solve_illusion(
        ta, tb, n_yarns=3, model="knit-aware", solver="rc2", warm_start="none"
    )
    assert by_options.solution.objective == by_keywords.solution.objective
    assert np.array_equal(by_options.pattern.yarn, by_keywords.pattern.yarn)
    # a keyword takes the place of the option's field
    assert solve_illusion(ta, tb, n_yarns=3, options=options, solver="dp", model="logical")
    with pytest.raises(OptionError, match="unknown solve option 'solvr'"):
        solve_illusion(ta, tb, n_yarns=3, solvr="dp")
