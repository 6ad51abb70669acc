"""Certify a solver's claim by an independent SAT call, as a MaxSAT Evaluation organiser would.

A claim of optimality at cost ``c`` is true exactly when no assignment satisfies the hard clauses
with cost at most ``c - 1``; a claim of unsatisfiability exactly when the hard clauses alone have
no model. :func:`certify_claim` asks one SAT oracle that question on **illuknit's own clauses**
of the model -- every soft clause gets a relaxation literal (a unit soft clause ``[l]`` is
violated exactly when ``-l`` holds, so it needs none), and ``sum(weight * relaxation) <= c - 1 -
offset`` is encoded as CNF by python-sat's pseudo-Boolean encodings (:mod:`pysat.pb`, which
needs the ``pindakaas`` package; without it a totalizer over the weights expanded into repeated
literals, :class:`pysat.card.ITotalizer`, when the total weight is small enough). The oracle
(Glucose 4, which python-sat can interrupt) runs in a child process under its own time and
memory limits (:func:`illuknit.solvers.isolate.run_in_child`), so a large encoding costs one
"unchecked" answer, never the benchmark.

A knit-aware illusion model is first given its own proof: its Lagrangian lower bound
(:mod:`illuknit.solvers.lagrangian`, at most :data:`BOUND_SECONDS`) certifies a claim it meets,
and a pattern it met that is cheaper than the claim refutes it; only when it settles nothing
does the SAT call run. (Measured on 3-yarn photo crops, benchmarks/certify_knit_aware.py: the
SAT call certified none of the 8 x 8, 10 x 10 and 12 x 12 claims within 60 s; the bound
certified the 8 x 8 and 10 x 10 optima in 0.1 s.)

The answer is one of

* ``certified`` -- UNSAT: the claim is true;
* ``refuted`` -- SAT: the oracle's assignment (checked on the model, its cost recomputed) is
  cheaper than the claimed optimum, or satisfies the hard clauses of a model claimed
  unsatisfiable; ``cost`` gives its verified cost;
* ``unchecked (time)``, ``unchecked (memory)``, ``unchecked (REASON)`` -- the check did not
  finish within its limits, or could not be made.
"""

from __future__ import annotations

import importlib.util
from dataclasses import dataclass
from typing import Any

import numpy as np

from illuknit.design.models.model import Model
from illuknit.solvers.base import assignment_from_lits
from illuknit.solvers.isolate import run_in_child

__all__ = ["Certificate", "certify_claim", "certify_rows", "pb_encoder"]

#: Most seconds the Lagrangian bound of a knit-aware model gets before the SAT call.
BOUND_SECONDS = 10.0

#: Largest total weight the fallback (weights expanded into a totalizer) accepts.
MAX_EXPANDED_WEIGHT = 20_000


@dataclass(frozen=True)
class Certificate:
    """The outcome of one check (see the module docstring)."""

    result: str
    seconds: float
    cost: int | None = None
    method: str = ""

    @property
    def refuted(self) -> bool:
        return self.result == "refuted"


def pb_encoder() -> str:
    """The pseudo-Boolean encoding :func:`certify_claim` uses here: ``pysat.pb`` or
    ``totalizer`` (weights expanded; needs no extra package)."""
    return "pysat.pb" if importlib.util.find_spec("pindakaas") is not None else "totalizer"


def _relaxed(
    hard: list[list[int]], soft: list[list[int]], weights: list[int], top: int
) -> tuple[list[list[int]], list[int], list[int], int]:
    """(hard clauses with relaxed soft clauses, cost literals, their weights, top variable)."""
    out = [list(map(int, c)) for c in hard]
    weight: dict[int, int] = {}
    for clause, w in zip(soft, weights, strict=True):
        if len(clause) == 1:
            lit = -int(clause[0])
        else:
            top += 1
            out.append([*map(int, clause), top])
            lit = top
        weight[lit] = weight.get(lit, 0) + int(w)
    lits = [x for x in weight if weight[x] > 0]
    return out, lits, [weight[x] for x in lits], top


def _encode_at_most(
    lits: list[int], weights: list[int], bound: int, top: int
) -> tuple[list[list[int]], str]:
    if pb_encoder() == "pysat.pb":
        from pysat.pb import PBEnc

        enc = PBEnc.leq(lits=lits, weights=weights, bound=bound, top_id=top)
        return [list(c) for c in enc.clauses], "pysat.pb"
    if sum(weights) > MAX_EXPANDED_WEIGHT:
        raise ValueError(
            f"total weight {sum(weights)} too large to expand without pysat.pb "
            "(pip install pindakaas)"
        )
    from pysat.card import ITotalizer

    expanded = [x for x, w in zip(lits, weights, strict=True) for _ in range(w)]
    tot = ITotalizer(lits=expanded, ubound=bound + 1, top_id=top)
    clauses = [list(c) for c in tot.cnf.clauses]
    if bound + 1 <= len(tot.rhs) - 1:
        clauses.append([-tot.rhs[bound]])  # at most `bound` of the expanded literals
    tot.delete()
    return clauses, "totalizer"


def _sat(clauses: list[list[int]], seconds: float) -> tuple[bool | None, list[int] | None]:
    """One interruptible SAT call: (True/False, or None when interrupted; its model)."""
    from threading import Timer

    from pysat.solvers import Solver

    with Solver(name="g4", bootstrap_with=clauses) as s:
        timer = Timer(max(0.05, seconds), s.interrupt)
        timer.start()
        try:
            res = s.solve_limited(expect_interrupt=True)
        finally:
            timer.cancel()
        return res, (s.get_model() if res else None)


def _check(model: Model, claimed: int | None, values: Any, seconds: float) -> dict[str, Any]:
    """In the child: the SAT calls (see :func:`certify_claim`); plain data back."""
    import time

    from illuknit.solvers.rc2 import split_components

    end = time.monotonic() + seconds
    cs = model.to_clauses()
    if claimed is None:
        res, lits = _sat([list(map(int, c)) for c in cs.hard], seconds)
        out: dict[str, Any] = {"sat": res, "method": "sat (hard clauses)"}
        if lits is not None:
            out["values"] = assignment_from_lits(lits, model.pool.top)
        return out
    if int(claimed) - int(model.offset) <= 0:
        return {"sat": False, "method": "cost of the model's offset"}
    current = np.asarray(values, dtype=bool).copy() if values is not None else None
    # one check per independent component, at the claimed assignment's cost there (an
    # assignment is optimal iff it is optimal on every component); without the assignment,
    # one check of the whole model
    comps = (
        split_components(cs)
        if current is not None
        else [(list(range(len(cs.hard))), list(range(len(cs.soft))))]
    )
    method = ""
    for hard_idx, soft_idx in comps:
        soft = [cs.soft[i] for i in soft_idx]
        weights = [int(cs.weights[i]) for i in soft_idx]
        if current is None:
            bound = int(claimed) - 1 - int(model.offset)
        else:
            here = sum(
                w
                for c, w in zip(soft, weights, strict=True)
                if not any(current[abs(x)] == (x > 0) for x in c)
            )
            if here == 0:
                continue  # nothing cheaper than zero
            bound = here - 1
        hard, lits, wts, top = _relaxed([cs.hard[i] for i in hard_idx], soft, weights, cs.nv)
        clauses = hard
        if sum(wts) > bound:
            extra, method = _encode_at_most(lits, wts, bound, top)
            clauses = hard + extra
        res, found = _sat(clauses, end - time.monotonic())
        if res is None:
            return {"sat": None, "method": method}
        if res:
            assert found is not None
            better = assignment_from_lits(found, model.pool.top)
            if current is None:
                return {"sat": True, "method": method, "values": better}
            vars_here = {abs(x) for i in hard_idx for x in cs.hard[i]}
            vars_here |= {abs(x) for c in soft for x in c}
            idx = np.fromiter((v for v in vars_here if v <= model.pool.top), dtype=np.int64)
            current[idx] = better[idx]
            return {"sat": True, "method": method, "values": current}
    return {"sat": False, "method": f"{method or 'sat'} per component ({len(comps)})"}


def _bound_certificate(model: Model, claimed: int, seconds: float) -> Certificate | None:
    """The knit-aware model's own proof, before any SAT call: its Lagrangian lower bound
    (:mod:`illuknit.solvers.lagrangian`) meeting the claim certifies it, and a pattern the bound
    met that is cheaper than the claim (its cost verified on the model) refutes it; None when
    the bound settles nothing or the model is not a knit-aware illusion model."""
    import time

    from illuknit.design.models.illusion_problem import IllusionProblem
    from illuknit.solvers.dp import values_from_pattern
    from illuknit.solvers.lagrangian import lagrangian_bound

    problem = model.problem
    if not isinstance(problem, IllusionProblem) or not problem.pass_weight:
        return None
    if problem.color_cap is not None:
        return None  # a hard cap the bound's patterns may break: leave it to the SAT call
    t0 = time.perf_counter()
    lag = lagrangian_bound(problem, time_limit=seconds, upper=claimed)
    wall = time.perf_counter() - t0
    if lag.bound >= claimed:
        return Certificate("certified", wall, method="Lagrangian lower bound")
    if lag.cost < claimed:
        ok, cost = model.evaluate(values_from_pattern(model, lag.yarn, lag.raised))
        if ok and cost < claimed:
            return Certificate("refuted", wall, int(cost), "Lagrangian bound's pattern")
    return None


def certify_claim(
    model: Model,
    claimed_cost: int | None,
    *,
    values: Any = None,
    time_limit: float = 60.0,
    memory_mb: float | None = 4096.0,
) -> Certificate:
    """Check that ``claimed_cost`` is the optimum of ``model`` (``None``: that the model is
    unsatisfiable) by independent SAT calls; see the module docstring.

    ``values``: the claimed optimal assignment (its verified cost is ``claimed_cost``). With it
    the check runs per independent component of the model (the logical models fall apart into
    one per wale): no component has a cheaper assignment than the claimed one there. A cheaper
    one found refutes the claim with a whole assignment. Without it, one call on the whole
    model (which a plain SAT solver rarely settles for more than a few hundred soft clauses).
    """
    if claimed_cost is not None:
        by_bound = _bound_certificate(model, int(claimed_cost), min(BOUND_SECONDS, time_limit))
        if by_bound is not None:
            return by_bound
    res = run_in_child(
        lambda _p: _check(model, claimed_cost, values, time_limit),
        time_limit=time_limit,
        memory_mb=memory_mb,
    )
    if res.status == "memout":
        return Certificate("unchecked (memory)", res.wall_time)
    if res.status == "timeout":
        return Certificate("unchecked (time)", res.wall_time)
    if res.status != "ok":
        return Certificate(f"unchecked ({res.reason})", res.wall_time)
    out = res.value
    if out["sat"] is None or res.late:
        return Certificate("unchecked (time)", res.wall_time, method=out["method"])
    if not out["sat"]:
        return Certificate("certified", res.wall_time, method=out["method"])
    ok, cost = model.evaluate(np.asarray(out["values"], dtype=bool))
    if not ok or (claimed_cost is not None and cost >= claimed_cost):
        # the encoding would be wrong: never call a claim false on such evidence
        return Certificate("unchecked (the checker's model did not verify)", res.wall_time)
    return Certificate("refuted", res.wall_time, int(cost), out["method"])


def certify_rows(
    rows: list[dict[str, Any]],
    models: Any,
    *,
    time_limit: float,
    memory_mb: float | None = 4096.0,
    values: Any = None,
) -> list[dict[str, Any]]:
    """Certify the claims of the benchmark's rows that nothing else settles (updated copies).

    Per (instance, model) without a reference optimum: every distinct claimed optimum (an
    unflagged ``optimal`` row's verified cost) and a claim of UNSATISFIABLE are checked once by
    :func:`certify_claim`; each row gets ``certificate`` (``certified``, ``refuted``,
    ``unchecked (...)``), and a refuted claim is flagged and no longer counts as solved.
    ``models(instance, model)`` returns the parent's copy of that model; ``values`` maps a row's
    (instance, model, solver, warm_start, run) to its verified assignment (the check then runs
    per independent component, see :func:`certify_claim`).
    """
    values = values or {}
    out = [dict(r) for r in rows]
    groups: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for r in out:
        groups.setdefault((r["instance"], r["model"]), []).append(r)
    for (inst, kind), rs in groups.items():
        claims: dict[int | None, list[dict[str, Any]]] = {}
        for r in rs:
            if r.get("flag") or r.get("certificate") or r.get("reference_optimum") is not None:
                continue
            if r.get("status") == "optimal" and r.get("verified_cost") is not None:
                claims.setdefault(int(r["verified_cost"]), []).append(r)
            elif r.get("status") == "infeasible":
                claims.setdefault(None, []).append(r)
        if not claims:
            continue
        model = models(inst, kind)
        for claimed, claimants in claims.items():
            keys = [
                (r["instance"], r["model"], r["solver"], r["warm_start"], r.get("run", 0))
                for r in claimants
            ]
            vals = next((values[k] for k in keys if values.get(k) is not None), None)
            cert = certify_claim(
                model, claimed, values=vals, time_limit=time_limit, memory_mb=memory_mb
            )
            for r in claimants:
                r["certificate"] = cert.result
                if cert.refuted:
                    what = "UNSATISFIABLE" if claimed is None else f"optimum {claimed}"
                    r["flag"] = "; ".join(
                        filter(
                            None,
                            [
                                r.get("flag", ""),
                                f"claimed {what} refuted: an independent SAT call found an "
                                f"assignment of cost {cert.cost}",
                            ],
                        )
                    )
                    r["time_prove"] = None
    return out
