"""An empty soft clause in a WCNF file is a constant cost (the MaxSAT Evaluation semantics: a
soft clause no assignment satisfies costs its weight under every assignment), never a hard
clause: the reader, the component split and the certifier against brute force (hypothesis)."""

from __future__ import annotations

import itertools

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from illuknit.bench.certify import certify_claim
from illuknit.bench.split import component_models
from illuknit.bench.wcnf_files import read_wcnf_text

NV = 5
lit = st.integers(1, NV).flatmap(lambda v: st.sampled_from([v, -v]))
clause = st.lists(lit, min_size=1, max_size=3)
formulas = st.tuples(
    st.lists(clause, max_size=4),
    st.lists(st.tuples(st.lists(lit, max_size=2), st.integers(1, 5)), min_size=1, max_size=6),
    st.lists(st.integers(1, 5), min_size=1, max_size=3),  # the empty soft clauses' weights
)


def _holds(c, a):
    return any(a[abs(x)] == (x > 0) for x in c)


def brute(hard, soft):
    """The optimum as the WCNF standard defines it: the least total weight of the soft clauses
    an assignment of all the hard clauses falsifies (None: no such assignment)."""
    best = None
    for bits in itertools.product((False, True), repeat=NV):
        a = dict(enumerate(bits, 1))
        if all(_holds(c, a) for c in hard):
            cost = sum(w for c, w in soft if not _holds(c, a))
            best = cost if best is None else min(best, cost)
    return best


def wcnf_text(hard, soft):
    lines = [f"c {NV} variables"]
    lines += ["h " + " ".join(map(str, [*c, 0])) for c in hard]
    lines += [" ".join(map(str, [w, *c, 0])) for c, w in soft]
    return "\n".join(lines) + "\n"


def bench_optimum(model):
    """What the bench verifies: the least objective model.evaluate gives an assignment it
    reports feasible (every assignment tried)."""
    best = None
    for bits in itertools.product((False, True), repeat=NV):
        values = np.zeros(max(model.pool.top, NV) + 1, dtype=bool)
        values[1 : NV + 1] = bits
        ok, cost = model.evaluate(values)
        if ok:
            best = cost if best is None else min(best, cost)
    return best


def test_an_empty_soft_clause_is_a_constant_not_a_hard_clause():
    model = read_wcnf_text("h 1 2 0\n3 0\n1 -1 0\n")
    assert model.num_hard == 1 and model.offset == 3
    assert model.evaluate([False, True, False]) == (True, 4)
    assert model.evaluate([False, False, True]) == (True, 3)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(formulas)
def test_the_bench_verifies_the_brute_force_optimum(formula):
    hard, soft, empty = formula
    soft = [*soft, *(([], w) for w in empty)]
    model = read_wcnf_text(wcnf_text(hard, soft))
    assert bench_optimum(model) == brute(hard, soft)
    _, constant, unsat = component_models(model)
    assert unsat is False
    assert constant + model.offset >= sum(empty)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(formulas)
def test_the_certifier_certifies_the_brute_force_optimum(formula):
    hard, soft, empty = formula
    soft = [*soft, *(([], w) for w in empty)]
    want = brute(hard, soft)
    model = read_wcnf_text(wcnf_text(hard, soft))
    cert = certify_claim(model, want, time_limit=20.0, memory_mb=None)
    assert cert.result == "certified", cert
    if want is not None:
        lower = certify_claim(model, want - 1, time_limit=20.0, memory_mb=None)
        assert lower.result != "certified"
