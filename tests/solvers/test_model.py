"""The solver-neutral model layer: variable pool, encodings of native constraints, WCNF export."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.core.errors import ModelError
from illuknit.solvers.model import Model
from illuknit.solvers.var_pool import VarPool


def test_pool_blocks_and_keys_agree():
    pool = VarPool()
    a = pool.var("a")
    x = pool.block("x", (2, 3))
    assert pool.var(("x", 1, 2)) == int(x[1, 2])
    assert pool.var("a") == a
    assert pool.key_of(int(x[1, 0])) == ("x", 1, 0)
    assert pool.var(("other", 1)) == pool.top
    with pytest.raises(KeyError):
        pool.var(("x", 2, 0))
    with pytest.raises(ModelError):
        pool.block("x", (1,))


def _sat_assignments(model: Model):
    """All assignments of the named variables satisfying the model, by brute force."""
    top = model.pool.top
    for bits in itertools.product((False, True), repeat=top):
        v = np.array([False, *bits])
        ok, cost = model.evaluate(v)
        yield v, ok, cost


def _cnf_projection(model: Model) -> set[tuple[bool, ...]]:
    """Named-variable assignments that extend to a model of the clause encoding."""
    from pysat.solvers import Solver

    cs = model.to_clauses()
    out = set()
    top = model.pool.top
    for bits in itertools.product((False, True), repeat=top):
        assum = [i + 1 if b else -(i + 1) for i, b in enumerate(bits)]
        with Solver(name="g4", bootstrap_with=cs.hard) as s:
            if s.solve(assumptions=assum):
                out.add(bits)
    return out


@settings(max_examples=40, deadline=None)
@given(
    n=st.integers(1, 5),
    op=st.sampled_from(["<=", ">=", "=="]),
    k=st.integers(-1, 6),
    neg=st.lists(st.booleans(), min_size=5, max_size=5),
)
def test_cardinality_encoding_matches_its_meaning(n, op, k, neg):
    m = Model()
    xs = [m.var(("x", i)) for i in range(n)]
    lits = [-x if neg[i] else x for i, x in enumerate(xs)]
    m.add_card(lits, op, k)
    want = {tuple(v[1:]) for v, ok, _ in _sat_assignments(m) if ok}
    assert _cnf_projection(m) == want


@settings(max_examples=40, deadline=None)
@given(
    coeffs=st.lists(st.integers(-3, 4), min_size=1, max_size=5),
    bound=st.integers(-2, 8),
    neg=st.lists(st.booleans(), min_size=5, max_size=5),
)
def test_linear_encoding_matches_its_meaning(coeffs, bound, neg):
    m = Model()
    xs = [m.var(("x", i)) for i in range(len(coeffs))]
    lits = [-x if neg[i] else x for i, x in enumerate(xs)]
    m.add_linear_le(lits, coeffs, bound)
    want = {tuple(v[1:]) for v, ok, _ in _sat_assignments(m) if ok}
    assert _cnf_projection(m) == want


def _random_model(rng: np.random.Generator, nv: int = 6) -> Model:
    m = Model("random")
    ids = m.pool.block("v", (nv,))
    for _ in range(int(rng.integers(0, 6))):
        w = int(rng.integers(1, 4))
        lits = rng.choice(ids, size=w, replace=False) * rng.choice([-1, 1], size=w)
        m.add_hard(lits.tolist())
    for _ in range(int(rng.integers(1, 10))):
        w = int(rng.integers(1, 3))
        lits = rng.choice(ids, size=w, replace=False) * rng.choice([-1, 1], size=w)
        m.add_soft(lits.tolist(), int(rng.integers(1, 5)))
    if rng.random() < 0.5:
        m.add_at_most_k(ids[:4].tolist(), int(rng.integers(0, 3)))
    return m


@pytest.mark.parametrize("style", ["new", "old"])
def test_wcnf_export_round_trips_through_pysat(style):
    from pysat.formula import WCNF

    rng = np.random.default_rng(7)
    for _ in range(10):
        m = _random_model(rng)
        text = m.to_wcnf(style=style)
        w = WCNF(from_string=text)
        cs = m.to_clauses()
        assert [list(c) for c in w.hard] == cs.hard
        assert [list(c) for c in w.soft] == cs.soft
        assert list(w.wght) == cs.weights
        assert w.nv <= cs.nv


def test_wcnf_new_format_uses_h_prefix_and_no_header():
    m = Model("t")
    a, b = m.var("a"), m.var("b")
    m.add_hard([a, -b])
    m.add_soft([b], 3)
    lines = [ln for ln in m.to_wcnf().splitlines() if not ln.startswith("c")]
    assert lines == ["h 1 -2 0", "3 2 0"]
    old = [ln for ln in m.to_wcnf(style="old").splitlines() if not ln.startswith("c")]
    assert old == ["p wcnf 2 2 4", "4 1 -2 0", "3 2 0"]


def test_soft_weights_must_be_positive_and_literals_known():
    m = Model()
    a = m.var("a")
    with pytest.raises(ModelError, match="positive"):
        m.add_soft([a], 0)
    with pytest.raises(ModelError, match="refers to no variable"):
        m.add_hard([a, 5])


def test_infeasible_families_names_the_conflict():
    m = Model()
    xs = m.pool.block("x", (3,))
    m.add_hard([int(xs[0])], family="free clause")
    m.add_at_most_k(xs.tolist(), 1, family="at most one")
    m.add_at_least_k(xs.tolist(), 2, family="at least two")
    fams = m.infeasible_families()
    assert set(fams) >= {"at most one", "at least two"}
    m2 = Model()
    m2.add_hard([m2.var("a")], family="ok")
    assert m2.infeasible_families() == []


def test_evaluate_counts_violated_soft_weight():
    m = Model()
    a, b = m.var("a"), m.var("b")
    m.add_soft_block(np.array([[a, 0], [-a, b], [-b, 0]]), np.array([1, 2, 4]))
    v = np.array([False, True, False])
    assert m.evaluate(v) == (True, 2)
    v = np.array([False, True, True])
    assert m.evaluate(v) == (True, 4)
