"""Certify a solver's claim as a MaxSAT Evaluation organiser would: by solving the formula
again, exactly, with an engine independent of the solver that made the claim.

The formula falls apart into **components**: sets of clauses whose variables never meet a
clause of another set. They are found from the clauses themselves (union-find over the
variables that co-occur in a hard or a soft clause, :func:`formula_components`), not from the
model builder that wrote them, so a WCNF file from anywhere is split the same way; the logical
illusion models fall apart into one component per wale. The optimum of the formula is the sum
of the components' optima, so each component is solved exactly on its own by the certifying
engine (:func:`certifying_engine`: python-sat's RC2, or OR-Tools CP-SAT when the claimant is
RC2) and the sum compared with the claim:

* ``certified`` -- the sum (plus the model's constant offset) equals the claimed optimum; for a
  claim of unsatisfiability, a component's hard clauses have no model;
* ``refuted`` -- the engine found an assignment cheaper than the claim (``cost``, verified on the
  model: it is the claimant's assignment with the cheaper components spliced in, or the engine's
  own assignment), or no assignment reaches a claimed cost below the optimum, or the hard clauses
  of a model claimed unsatisfiable have a model;
* ``unchecked (REASON)`` -- the engine did not finish every component within the time limit
  (``unchecked (time: K of N components)``), ran out of memory, is not installed, or disagreed
  with a verified assignment (then nothing is said of the claim).

With the claimed assignment in hand a component where it already costs nothing is skipped, and
the first component where the engine does better refutes the claim at once. The engine runs in
a child process under its own time and memory limits
(:func:`illuknit.solvers.isolate.run_in_child`), so a large formula costs one "unchecked"
answer, never the benchmark.

A knit-aware illusion model is first given its own proof: its Lagrangian lower bound
(:mod:`illuknit.design.models.backends.lagrangian`, at most :data:`BOUND_SECONDS`) certifies a claim it meets,
and a pattern it met that is cheaper than the claim refutes it.
"""

from __future__ import annotations

import importlib.util
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from illuknit.solvers.isolate import run_in_child
from illuknit.solvers.model import Model

__all__ = [
    "ENGINES",
    "Certificate",
    "FlatFormula",
    "certify_claim",
    "certify_rows",
    "certifying_engine",
    "formula_components",
    "solve_component",
]

#: Most seconds the Lagrangian bound of a knit-aware model gets before the exact engine.
BOUND_SECONDS = 10.0

#: The suffix of a row whose solver got the formula split into components first (``rc2+split``).
SPLIT_SUFFIX = "+split"

#: The exact engines a claim can be certified with (each on one component at a time).
ENGINES = ("cpsat", "rc2")


@dataclass(frozen=True)
class Certificate:
    """The outcome of one check (see the module docstring). ``components`` is how many
    components the formula has and ``solved`` how many the engine settled."""

    result: str
    seconds: float
    cost: int | None = None
    method: str = ""
    components: int = 0
    solved: int = 0

    @property
    def refuted(self) -> bool:
        return self.result == "refuted"

    @property
    def certified(self) -> bool:
        return self.result == "certified"


def certifying_engine(solver: str) -> str | None:
    """The engine that certifies a claim of ``solver`` independently of it: python-sat's RC2
    (the faster on the small components: 1.3 s against CP-SAT's 4.4 s for the 40 wales of a
    57 x 40 logical model, docs/solvers-bench.md), unless the claimant is RC2 itself in any
    form (``rc2``, ``rc2:ORACLE``, ``rc2+split``): then OR-Tools CP-SAT. None when that engine
    is not installed."""
    from illuknit.solvers import parse_solver_name

    name = solver.removesuffix(SPLIT_SUFFIX)
    base = parse_solver_name(name).base if name else ""
    engine = "cpsat" if base == "rc2" else "rc2"
    module = "ortools" if engine == "cpsat" else "pysat"
    return engine if importlib.util.find_spec(module) is not None else None


class FlatFormula:
    """The formula as flat arrays (hard clauses, then soft ones): every literal in ``lits``,
    clause ``i`` is ``lits[start[i]:start[i] + length[i]]``; ``weight`` is 0 for a hard clause."""

    def __init__(self, hard: list[list[int]], soft: list[list[int]], weights: list[int]) -> None:
        clauses = [*hard, *soft]
        self.n_hard = len(hard)
        self.length = np.fromiter((len(c) for c in clauses), dtype=np.int64, count=len(clauses))
        self.start = np.concatenate(([0], np.cumsum(self.length)[:-1])).astype(np.int64)
        total = int(self.length.sum())
        self.lits = np.fromiter((x for c in clauses for x in c), dtype=np.int64, count=total)
        self.weight = np.concatenate(
            (np.zeros(len(hard), dtype=np.int64), np.asarray(weights, dtype=np.int64))
        )

    def labels(self) -> NDArray[np.int64]:
        """The component of each clause: union-find over the variables that share a clause
        (vectorised: each literal's variable joined to its clause's first variable, then the
        connected components of that graph); an empty clause is a component of its own."""
        from scipy.sparse import coo_matrix
        from scipy.sparse.csgraph import connected_components

        var = np.abs(self.lits)
        n = int(var.max(initial=0)) + 1
        first = np.repeat(var[self.start[self.length > 0]], self.length[self.length > 0])
        graph = coo_matrix((np.ones(var.size, dtype=np.int8), (first, var)), shape=(n, n))
        _, label = connected_components(graph, directed=False)
        out = np.full(self.length.size, -1, dtype=np.int64)
        has = self.length > 0
        out[has] = label[var[self.start[has]]]
        empty = np.flatnonzero(~has)
        out[empty] = n + np.arange(empty.size)  # each empty clause alone
        return out

    def violated(self, values: NDArray[np.bool_]) -> NDArray[np.bool_]:
        """Per clause: no literal of it holds under ``values``."""
        var = np.abs(self.lits)
        ok = np.zeros(var.size, dtype=bool)
        inside = var < values.size
        ok[inside] = values[var[inside]] == (self.lits[inside] > 0)
        sat = np.zeros(self.length.size, dtype=bool)
        has = self.length > 0
        sat[has] = np.logical_or.reduceat(ok, self.start[has]) if ok.size else False
        return ~sat

    def component(
        self, idx: NDArray[np.int64]
    ) -> tuple[list[list[int]], list[list[int]], list[int], NDArray[np.int64]]:
        """(hard clauses, soft clauses, weights, variable ids) of the clauses ``idx``, with
        the variables renumbered 1..k (local ``j`` is variable ``ids[j - 1]``): the engines
        size their tables by the largest id."""
        lengths = self.length[idx]
        before = np.concatenate(([0], np.cumsum(lengths)[:-1])).astype(np.int64)
        pos = np.repeat(self.start[idx] - before, lengths) + np.arange(int(lengths.sum()))
        lits = self.lits[pos]
        ids, local = np.unique(np.abs(lits), return_inverse=True)
        flat = (np.sign(lits) * (local.reshape(-1) + 1)).tolist()
        hard, soft, weights = [], [], []
        at = 0
        for i in idx.tolist():
            n = int(self.length[i])
            if i < self.n_hard:
                hard.append(flat[at : at + n])
            else:
                soft.append(flat[at : at + n])
                weights.append(int(self.weight[i]))
            at += n
        return hard, soft, weights, ids


def formula_components(
    hard: list[list[int]], soft: list[list[int]]
) -> list[tuple[list[int], list[int]]]:
    """(hard clause indices, soft clause indices) of each component of the formula: the
    clauses whose variables are joined through shared clauses (see :meth:`FlatFormula.labels`). An
    empty clause is a component of its own."""
    flat = FlatFormula(hard, soft, [1] * len(soft))
    label = flat.labels()
    order = np.argsort(label, kind="stable")
    cuts = np.flatnonzero(np.diff(label[order])) + 1
    nh = len(hard)
    return [
        ([int(i) for i in g if i < nh], [int(i) - nh for i in g if i >= nh])
        for g in np.split(order, cuts)
        if g.size
    ]


def _solve_cpsat(
    hard: list[list[int]], soft: list[list[int]], weights: list[int], seconds: float
) -> tuple[str, int | None, dict[int, bool]]:
    from ortools.sat.python import cp_model

    m = cp_model.CpModel()
    nv = max((abs(x) for c in (*hard, *soft) for x in c), default=0)
    var = [m.new_bool_var(f"x{i}") for i in range(nv + 1)]

    def lit(x: int) -> Any:
        return var[x] if x > 0 else var[-x].Not()

    for c in hard:
        m.add_bool_or([lit(x) for x in c])
    terms: list[Any] = []
    coefs: list[int] = []
    constant = 0
    for c, w in zip(soft, weights, strict=True):
        if not c:
            constant += w
        elif len(c) == 1 and c[0] > 0:  # violated when the variable is false: w * (1 - x)
            constant += w
            terms.append(var[c[0]])
            coefs.append(-w)
        elif len(c) == 1:  # violated when the variable is true: w * x
            terms.append(var[-c[0]])
            coefs.append(w)
        else:
            r = m.new_bool_var("")
            m.add_bool_or([*(lit(x) for x in c), r])
            terms.append(r)
            coefs.append(w)
    m.minimize(cp_model.LinearExpr.weighted_sum(terms, coefs))
    s = cp_model.CpSolver()
    s.parameters.max_time_in_seconds = max(0.01, seconds)
    s.parameters.num_workers = 1
    s.parameters.optimize_with_core = True  # core-guided, as the MaxSAT engines: proves fast
    s.parameters.core_minimization_level = 0  # 0.4 s, not 2 s, on a 4-yarn wale of 143 rows
    st = s.solve(m)
    if st == cp_model.INFEASIBLE:
        return "infeasible", None, {}
    if st != cp_model.OPTIMAL:
        return "unknown", None, {}
    values = {i: bool(s.value(var[i])) for i in range(1, nv + 1)}
    return "optimal", round(s.objective_value) + constant, values


def _solve_rc2(
    hard: list[list[int]], soft: list[list[int]], weights: list[int], seconds: float
) -> tuple[str, int | None, dict[int, bool]]:
    from pysat.examples.rc2 import RC2
    from pysat.formula import WCNF

    constant = sum(wt for c, wt in zip(soft, weights, strict=True) if not c)
    w = WCNF()  # filled directly: WCNF.append costs more than the solve on small components
    w.hard = [list(c) for c in hard]  # copies: RC2 rewrites the clauses it is handed
    w.soft = [list(c) for c in soft if c]
    w.wght = [wt for c, wt in zip(soft, weights, strict=True) if c]
    w.nv = max((abs(x) for c in (*hard, *soft) for x in c), default=0)
    w.topw = sum(w.wght) + 1
    with RC2(w, solver="g3") as rc2:  # no time limit of its own: the child's limit stops it
        found = rc2.compute()
        if found is None:
            return "infeasible", None, {}
        return "optimal", int(rc2.cost) + constant, {abs(x): x > 0 for x in found}


def solve_component(
    engine: str,
    hard: list[list[int]],
    soft: list[list[int]],
    weights: list[int],
    seconds: float,
) -> tuple[str, int | None, dict[int, bool]]:
    """Solve one component exactly with ``engine``: (``optimal``/``infeasible``/``unknown``,
    its optimum, the values of its variables)."""
    flat = FlatFormula(hard, soft, weights)
    h, s, w, ids = flat.component(np.arange(flat.length.size))
    status, opt, vals = _solve_local(engine, h, s, w, seconds)
    return status, opt, {int(ids[k - 1]): b for k, b in vals.items() if 0 < k <= ids.size}


def _solve_local(
    engine: str, hard: list[list[int]], soft: list[list[int]], weights: list[int], seconds: float
) -> tuple[str, int | None, dict[int, bool]]:
    if engine not in ENGINES:
        raise ValueError(f"unknown certifying engine {engine!r}; known: {', '.join(ENGINES)}")
    if any(not c for c in hard):
        return "infeasible", None, {}
    run = _solve_cpsat if engine == "cpsat" else _solve_rc2
    return run(hard, soft, weights, seconds)


def _check(
    model: Model, claimed: int | None, values: Any, seconds: float, engine: str
) -> dict[str, Any]:
    """In the child: every component solved exactly (see the module docstring); plain data."""
    end = time.monotonic() + seconds
    cs = model.to_clauses()
    flat = FlatFormula(cs.hard, cs.soft, cs.weights)
    label = flat.labels()
    order = np.argsort(label, kind="stable")
    comps = np.split(order, np.flatnonzero(np.diff(label[order])) + 1)
    comps = [c for c in comps if c.size]
    current = np.asarray(values, dtype=bool).copy() if values is not None else None
    here = None
    if current is not None and claimed is not None:
        cost = flat.violated(current) * flat.weight
        here = [int(cost[c].sum()) for c in comps]
    # the claimant's values stand where it costs nothing (those components are skipped)
    found = current.copy() if current is not None else np.zeros(cs.nv + 1, dtype=bool)
    total = 0
    out: dict[str, Any] = {"components": len(comps), "method": f"{engine} per component"}
    for k, idx in enumerate(comps):
        if here is not None and here[k] == 0:
            continue  # nothing is cheaper than zero
        left = end - time.monotonic()
        if left <= 0:
            return {**out, "answer": "time", "solved": k}
        hard, soft, weights, ids = flat.component(idx)
        status, opt, vals = _solve_local(engine, hard, soft, weights, left)
        if status == "unknown":
            return {**out, "answer": "time", "solved": k}
        if status == "infeasible":
            return {**out, "answer": "infeasible", "solved": k + 1}
        assert opt is not None
        local = np.array([vals.get(j + 1, False) for j in range(ids.size)], dtype=bool)
        inside = ids < found.size
        if here is not None and opt < here[k]:
            assert current is not None
            current[ids[inside]] = local[inside]
            return {**out, "answer": "better", "values": current, "solved": k + 1}
        if here is not None and opt > here[k]:
            return {**out, "answer": "disagree", "solved": k + 1, "where": (here[k], opt)}
        found[ids[inside]] = local[inside]
        total += opt
    return {
        **out,
        "answer": "optimum",
        "optimum": total + int(model.offset),
        "values": found,
        "solved": len(comps),
    }


def _bound_certificate(model: Model, claimed: int, seconds: float) -> Certificate | None:
    """The knit-aware model's own proof, before the exact engine: its Lagrangian lower bound
    (:mod:`illuknit.design.models.backends.lagrangian`) meeting the claim certifies it, and a pattern the bound
    met that is cheaper than the claim (its cost verified on the model) refutes it; None when
    the bound settles nothing or the model is not a knit-aware illusion model."""
    from illuknit.design.models.backends.dp import values_from_pattern
    from illuknit.design.models.backends.lagrangian import lagrangian_bound
    from illuknit.design.models.illusion_problem import IllusionProblem

    problem = model.problem
    if not isinstance(problem, IllusionProblem) or not problem.pass_weight:
        return None
    if problem.color_cap is not None:
        return None  # a hard cap the bound's patterns may break: leave it to the engine
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
    engine: str = "rc2",
) -> Certificate:
    """Check that ``claimed_cost`` is the optimum of ``model`` (``None``: that the model is
    unsatisfiable) by solving each component exactly with ``engine`` (see the module docstring).

    ``values``: the claimed optimal assignment (its verified cost is ``claimed_cost``), which
    lets the check skip the components where it costs nothing and splice a cheaper component
    into it. ``time_limit`` bounds the whole check (every component), ``memory_mb`` its
    resident memory.
    """
    if engine not in ENGINES:
        raise ValueError(f"unknown certifying engine {engine!r}; known: {', '.join(ENGINES)}")
    if claimed_cost is not None:
        by_bound = _bound_certificate(model, int(claimed_cost), min(BOUND_SECONDS, time_limit))
        if by_bound is not None:
            return by_bound
    # the engine is imported before the fork: the check's time is solving, not importing
    importlib.import_module(
        "ortools.sat.python.cp_model" if engine == "cpsat" else "pysat.examples.rc2"
    )
    res = run_in_child(
        lambda _p: _check(model, claimed_cost, values, time_limit, engine),
        time_limit=time_limit,
        memory_mb=memory_mb,
    )
    if res.status == "memout":
        return Certificate("unchecked (memory)", res.wall_time)
    if res.status == "timeout":
        return Certificate("unchecked (time)", res.wall_time)
    if res.status != "ok":
        return Certificate(f"unchecked ({res.reason})", res.wall_time)
    return _judge(model, claimed_cost, res.value, res.wall_time)


def _judge(model: Model, claimed: int | None, out: dict[str, Any], wall: float) -> Certificate:
    """The certificate the engine's answer (from :func:`_check`) gives the claim."""
    n, k, method = out["components"], out["solved"], out["method"]

    def cert(result: str, cost: int | None = None) -> Certificate:
        return Certificate(result, wall, cost, method, n, k)

    answer = out["answer"]
    if answer == "time":
        return cert(f"unchecked (time: {k} of {n} components)")
    if answer == "disagree":
        here, opt = out["where"]
        return cert(
            f"unchecked (the engine's optimum {opt} of a component is above the claimed "
            f"assignment's verified {here} there)"
        )
    if answer == "infeasible":
        if claimed is None:
            return cert("certified")
        return cert("unchecked (the engine found no model of a component's hard clauses)")
    ok, cost = model.evaluate(np.asarray(out["values"], dtype=bool))
    if not ok:  # the engine's own answer must verify: never call a claim false otherwise
        return cert("unchecked (the engine's assignment did not verify)")
    if answer == "better":
        if claimed is not None and cost < claimed:
            return cert("refuted", int(cost))
        return cert("unchecked (the engine's cheaper component did not verify)")
    optimum = int(out["optimum"])
    if cost != optimum:
        return cert("unchecked (the engine's optimum did not verify)")
    if claimed is None or optimum < claimed:
        return cert("refuted", optimum)
    if optimum == claimed:
        return cert("certified")
    return cert("refuted", optimum)  # no assignment reaches the claimed (too low) cost


def _claims(rs: list[dict[str, Any]]) -> dict[tuple[int | None, str | None], list[dict[str, Any]]]:
    """The rows of one (instance, model) with a claim to check, by (claim, certifying engine)."""
    claims: dict[tuple[int | None, str | None], list[dict[str, Any]]] = {}
    for r in rs:
        if r.get("certificate") or r.get("reference_optimum") is not None:
            continue
        if "without an assignment" in (r.get("flag") or ""):
            claim: int | None = None if r.get("claimed_cost") is None else int(r["claimed_cost"])
            if claim is None:
                continue
        elif r.get("flag"):
            continue
        elif r.get("status") == "optimal" and r.get("verified_cost") is not None:
            claim = int(r["verified_cost"])
        elif r.get("status") == "infeasible":
            claim = None
        else:
            continue
        claims.setdefault((claim, certifying_engine(str(r["solver"]))), []).append(r)
    return claims


def _apply(r: dict[str, Any], claimed: int | None, cert: Certificate, engine: str) -> None:
    r["certificate"] = cert.result
    r["certify_s"] = round(cert.seconds, 3)
    if not cert.refuted:
        return
    what = "UNSATISFIABLE" if claimed is None else f"optimum {claimed}"
    if claimed is not None and cert.cost is not None and cert.cost > claimed:
        why = f"no assignment costs {claimed}: the optimum is {cert.cost} ({engine})"
    else:
        why = f"{engine} per component found an assignment of cost {cert.cost}"
    r["certificate"] = f"refuted ({cert.cost})"
    r["flag"] = "; ".join(filter(None, [r.get("flag", ""), f"claimed {what} refuted: {why}"]))
    r["time_prove"] = None


def certify_rows(
    rows: list[dict[str, Any]],
    models: Any,
    *,
    time_limit: float,
    memory_mb: float | None = 4096.0,
    values: Any = None,
) -> list[dict[str, Any]]:
    """Certify the claims of the benchmark's rows that the DP's exact optimum does not settle
    (updated copies).

    Per (instance, model) every distinct claimed optimum (an ``optimal`` row's verified cost,
    or the claimed cost of an optimum claimed without an assignment) and every claim of
    UNSATISFIABLE is checked once per certifying engine (:func:`certifying_engine`: never the
    claimant's own) by :func:`certify_claim`; each row gets ``certificate`` (``certified``,
    ``refuted (COST)``, ``unchecked (...)``) and ``certify_s``; a refuted claim is flagged and
    no longer counts as solved -- nor does any claim that is not certified (see
    :mod:`illuknit.bench.solver_report`). ``models(instance, model)`` returns the parent's
    copy of that model; ``values`` maps a row's (instance, model, solver, warm_start, run) to
    its verified assignment.
    """
    values = values or {}
    out = [dict(r) for r in rows]
    groups: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for r in out:
        groups.setdefault((r["instance"], r["model"]), []).append(r)
    for (inst, kind), rs in groups.items():
        claims = _claims(rs)
        if not claims:
            continue
        model = models(inst, kind)
        for (claimed, engine), claimants in claims.items():
            if engine is None:
                for r in claimants:
                    r["certificate"] = "unchecked (no independent engine installed)"
                continue
            keys = [
                (r["instance"], r["model"], r["solver"], r["warm_start"], r.get("run", 0))
                for r in claimants
            ]
            vals = next((values[k] for k in keys if values.get(k) is not None), None)
            if claimed is not None and vals is not None:
                ok, cost = model.evaluate(np.asarray(vals, dtype=bool))
                vals = vals if ok and cost == claimed else None
            cert = certify_claim(
                model,
                claimed,
                values=vals,
                time_limit=time_limit,
                memory_mb=memory_mb,
                engine=engine,
            )
            for r in claimants:
                _apply(r, claimed, cert, engine)
    return out
