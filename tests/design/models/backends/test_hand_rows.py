"""The hand row descent and the model made for hands (issue #37): every row knittable by hand.

The row rule is checked against :mod:`illuknit.design.hand_cost`, the measure the pattern, the
report and the benchmark use, by brute force on every row of tiny widths; the encoding against
the same measure on random assignments; the descent's rows by that measure and by brute force of
the row it replaces."""

from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.core.pattern import LogicalPattern, Yarn
from illuknit.design.hand_cost import hand_rows
from illuknit.design.models.backends.dp import solve_dp, values_from_pattern
from illuknit.design.models.backends.hand_rows import (
    best_row,
    hand_row_descent,
    row_unit_costs,
    view_cost,
)
from illuknit.design.models.illusion_models import build_model, make_problem

YARNS = tuple(Yarn(f"y{i}", (40 * i, 40 * i, 40 * i)) for i in range(3))


def _knittable(row: tuple[int, ...]) -> bool:
    """The hand measure's verdict on one unit row (both of its hand rows)."""
    p = LogicalPattern(np.array([row]), np.zeros((1, len(row)), bool), YARNS)
    return all(r.knittable for r in hand_rows(p))


@pytest.mark.parametrize(("k", "m"), [(2, 12), (3, 9)])
def test_best_row_is_the_cheapest_knittable_row(k, m):
    rng = np.random.default_rng(k * 100 + m)
    rows = list(itertools.product(range(k), repeat=m))
    ok = [r for r in rows if _knittable(r)]
    assert len(ok) < len(rows)  # the rule bites at this width
    for _ in range(6):
        costs = rng.integers(0, 5, size=(m, k)).astype(float)
        row, cost = best_row(costs)
        assert _knittable(tuple(int(c) for c in row))
        assert cost == pytest.approx(costs[np.arange(m), row].sum())
        assert cost == min(costs[np.arange(m), list(r)].sum() for r in ok)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([2, 3]))
def test_the_encoding_admits_exactly_the_knittable_rows(seed, k):
    rng = np.random.default_rng(seed)
    n, m = 3, 11
    yarn = rng.integers(0, k, size=(n, m))
    if rng.random() < 0.5:  # long runs too: intarsia rows, and floats at the limit
        yarn = np.repeat(rng.integers(0, k, size=(n, 3)), [4, 3, 4], axis=1)
    raised = rng.random((n, m)) < 0.3
    prob = replace(make_problem(yarn, yarn, n_yarns=k), for_hands=True)
    model = build_model(prob)
    feasible, _ = model.evaluate(values_from_pattern(model, yarn, raised))
    pattern = LogicalPattern(yarn, raised, YARNS[:k])
    assert feasible == all(r.knittable for r in hand_rows(pattern))


def test_the_descent_makes_every_row_knittable_and_each_row_is_its_best():
    rng = np.random.default_rng(7)
    a = (rng.random((10, 24)) < 0.5).astype(int)
    b = (rng.random((10, 24)) < 0.5).astype(int)
    prob = replace(make_problem(a, b, n_yarns=2), for_hands=True)
    yarn, raised, _ = solve_dp(prob)
    start = LogicalPattern(yarn, raised, YARNS[:2])
    assert not all(r.knittable for r in hand_rows(start))  # the DP ignores the rows
    y, r, cost = hand_row_descent(prob, yarn, raised)
    assert all(h.knittable for h in hand_rows(LogicalPattern(y, r, YARNS[:2])))
    assert cost == view_cost(prob, y, r)
    model = build_model(prob)
    feasible, objective = model.evaluate(values_from_pattern(model, y, r))
    assert feasible and objective == cost
    # a fixed point: no single row can be replaced by a cheaper knittable one
    for i in range(y.shape[0]):
        costs, _ = row_unit_costs(prob, y, r, i)
        _, best = best_row(costs)
        assert best == pytest.approx(costs[np.arange(y.shape[1]), y[i]].sum())


def test_view_cost_is_the_model_objective():
    rng = np.random.default_rng(3)
    a = rng.integers(0, 3, size=(6, 9))
    b = rng.integers(0, 3, size=(6, 9))
    yarn = rng.integers(0, 3, size=(6, 9))
    raised = rng.random((6, 9)) < 0.4
    prob = make_problem(a, b, n_yarns=3)
    model = build_model(prob)
    _, objective = model.evaluate(values_from_pattern(model, yarn, raised))
    assert view_cost(prob, yarn, raised) == objective
