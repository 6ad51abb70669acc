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

from illuknit.model import Model
from illuknit.solvers.base import assignment_from_lits
from illuknit.solvers.isolate import run_in_child

__all__ = ["Certificate", "certify_claim", "certify_rows", "pb_encoder"]

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


def _cost_literals(model: Model) -> tuple[list[list[int]], list[int], list[int], int]:
    """(hard clauses with relaxed soft clauses, cost literals, their weights, top variable)."""
    cs = model.to_clauses()
    top = cs.nv
    hard = [list(map(int, c)) for c in cs.hard]
    weight: dict[int, int] = {}
    for clause, w in zip(cs.soft, cs.weights, strict=True):
        if len(clause) == 1:
            lit = -int(clause[0])
        else:
            top += 1
            hard.append([*map(int, clause), top])
            lit = top
        weight[lit] = weight.get(lit, 0) + int(w)
    lits = list(weight)
    return hard, lits, [weight[x] for x in lits], top


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


def _check(model: Model, claimed: int | None, seconds: float) -> dict[str, Any]:
    """In the child: the SAT call (see the module docstring); plain data back."""
    from threading import Timer

    from pysat.solvers import Solver

    hard, lits, weights, top = _cost_literals(model)
    method = "sat (hard clauses)"
    clauses = hard
    if claimed is not None:
        bound = int(claimed) - 1 - int(model.offset)
        if bound < 0:
            return {"sat": False, "method": "cost below the model's offset"}
        live = [(x, w) for x, w in zip(lits, weights, strict=True) if w > 0]
        if sum(w for _, w in live) > bound:
            extra, method = _encode_at_most([x for x, _ in live], [w for _, w in live], bound, top)
            clauses = hard + extra
    with Solver(name="g4", bootstrap_with=clauses) as s:
        timer = Timer(max(0.05, seconds), s.interrupt)
        timer.start()
        try:
            res = s.solve_limited(expect_interrupt=True)
        finally:
            timer.cancel()
        if res is None:
            return {"sat": None, "method": method}
        lits_out = s.get_model() if res else None
    out: dict[str, Any] = {"sat": bool(res), "method": method}
    if lits_out is not None:
        out["values"] = assignment_from_lits(lits_out, model.pool.top)
    return out


def certify_claim(
    model: Model,
    claimed_cost: int | None,
    *,
    time_limit: float = 60.0,
    memory_mb: float | None = 4096.0,
) -> Certificate:
    """Check that ``claimed_cost`` is the optimum of ``model`` (``None``: that the model is
    unsatisfiable) by one independent SAT call; see the module docstring."""
    res = run_in_child(
        lambda _p: _check(model, claimed_cost, time_limit),
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
) -> list[dict[str, Any]]:
    """Certify the claims of the benchmark's rows that nothing else settles (updated copies).

    Per (instance, model) without a reference optimum: every distinct claimed optimum (an
    unflagged ``optimal`` row's verified cost) and a claim of UNSATISFIABLE are checked once by
    :func:`certify_claim`; each row gets ``certificate`` (``certified``, ``refuted``,
    ``unchecked (...)``), and a refuted claim is flagged and no longer counts as solved.
    ``models(instance, model)`` returns the parent's copy of that model.
    """
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
            cert = certify_claim(model, claimed, time_limit=time_limit, memory_mb=memory_mb)
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
