"""The certifier's own pieces: components found from the clauses, and both exact engines, against
brute force on random small formulas (hypothesis)."""

from __future__ import annotations

import itertools

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from illuknit.bench.certify import formula_components, solve_component

NV = 7
lit = st.integers(1, NV).flatmap(lambda v: st.sampled_from([v, -v]))
clause = st.lists(lit, min_size=1, max_size=3)
formulas = st.tuples(
    st.lists(clause, max_size=6),
    st.lists(st.tuples(clause, st.integers(1, 5)), min_size=1, max_size=8),
)


def brute(hard, soft, weights):
    best = None
    for bits in itertools.product((False, True), repeat=NV):
        a = dict(enumerate(bits, 1))
        if all(any(a[abs(x)] == (x > 0) for x in c) for c in hard):
            cost = sum(
                w
                for c, w in zip(soft, weights, strict=True)
                if not any(a[abs(x)] == (x > 0) for x in c)
            )
            best = cost if best is None else min(best, cost)
    return best


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(formulas)
def test_both_engines_find_the_brute_force_optimum(formula):
    hard, pairs = formula
    soft = [c for c, _ in pairs]
    weights = [w for _, w in pairs]
    want = brute(hard, soft, weights)
    for engine in ("rc2", "cpsat"):
        status, opt, values = solve_component(engine, hard, soft, weights, 10.0)
        if want is None:
            assert status == "infeasible"
            continue
        assert status == "optimal" and opt == want, engine
        a = {v: values.get(v, False) for v in range(1, NV + 1)}
        assert all(any(a[abs(x)] == (x > 0) for x in c) for c in hard)
        assert (
            sum(
                w
                for c, w in zip(soft, weights, strict=True)
                if not any(a[abs(x)] == (x > 0) for x in c)
            )
            == want
        )


@settings(deadline=None, suppress_health_check=[HealthCheck.too_slow])  # a loaded machine
@given(formulas)
def test_components_partition_the_clauses_and_share_no_variable(formula):
    hard, pairs = formula
    soft = [c for c, _ in pairs]
    comps = formula_components(hard, soft)
    assert sorted(i for h, _ in comps for i in h) == list(range(len(hard)))
    assert sorted(i for _, s in comps for i in s) == list(range(len(soft)))
    seen: set[int] = set()
    for h, s in comps:
        here = {abs(x) for i in h for x in hard[i]} | {abs(x) for i in s for x in soft[i]}
        assert not here & seen
        seen |= here
