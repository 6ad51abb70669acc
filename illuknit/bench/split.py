"""The component split as a labelled pre-processing step for any solver (rows ``NAME+split``).

The formula is split into its components -- clauses whose variables never meet a clause of
another component, found from the clauses themselves (the union-find of
:mod:`illuknit.bench.certify`), not from the model builder -- and each component becomes a
formula of its own (variables renumbered 1..k, as a component WCNF file would have them). The
solver runs on every component in turn with the time that is left; the components' costs are
summed, their assignments spliced into one assignment of the whole formula, which the bench then
verifies on the whole model like any answer (:func:`illuknit.bench.solver_runs.run_solver_task`).

``rc2+split`` keeps RC2's own per-component loop (:mod:`illuknit.solvers.rc2`, the same split of
the same formula); every other ``NAME+split`` goes through :func:`solve_split`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from illuknit.bench.certify import FlatFormula
from illuknit.solvers.base import ProgressEvent, Status
from illuknit.solvers.model import Model

__all__ = ["component_models", "solve_split"]


def _clause_model(name: str, hard: list[list[int]], soft: list[list[int]], weights: list[int],
                  nv: int) -> Model:  # fmt: skip
    from illuknit.bench.wcnf_files import add_clause_groups

    model = Model(name)
    model.pool.block("x", (max(nv, 1),))
    if hard:
        add_clause_groups(model, hard, None)
    if soft:
        add_clause_groups(model, soft, weights)
    return model


def component_models(model: Model) -> tuple[list[tuple[Model, NDArray[np.int64]]], int, bool]:
    """(the components of ``model``'s formula, each as (a Model of its own, the original ids of
    its variables 1..k), the weight of empty soft clauses, whether an empty hard clause makes
    the formula unsatisfiable)."""
    cs = model.to_clauses()
    flat = FlatFormula(cs.hard, cs.soft, cs.weights)
    constant = int(flat.weight[(flat.length == 0) & (flat.weight > 0)].sum())
    unsat = bool(np.any(flat.length[: flat.n_hard] == 0))
    keep = np.flatnonzero(flat.length > 0)
    label = flat.labels()[keep]
    order = keep[np.argsort(label, kind="stable")]
    groups = np.split(order, np.flatnonzero(np.diff(np.sort(label, kind="stable"))) + 1)
    out = []
    for k, idx in enumerate(g for g in groups if g.size):
        hard, soft, weights, ids = flat.component(idx)
        out.append((_clause_model(f"{model.name}-c{k}", hard, soft, weights, ids.size), ids))
    return out, constant, unsat


def _claimed(sub: Any) -> tuple[Any, str]:
    stats = dict(sub.stats)
    cost = stats.get("claimed_cost", stats.get("reported_cost", sub.objective))
    return cost, str(stats.get("claimed_status", ""))


def solve_split(
    model: Model,
    engine: str,
    *,
    time_limit: float,
    seed: int = 0,
    progress: Callable[[ProgressEvent], None] | None = None,
) -> dict[str, Any]:
    """Solve ``model`` component by component with the backend ``engine`` (see the module
    docstring); the answer as :func:`illuknit.bench.solver_runs` reads a child's answer:
    status, spliced values (None unless every component has an assignment), objective and
    bound (sums, plus the model's offset and empty soft clauses), claimed cost and status
    (sums and the claims' union), trace, and how many components were solved."""
    from illuknit.solvers import solve
    from illuknit.solvers.base import interrupt_types

    t0 = time.perf_counter()
    comps, constant, unsat = component_models(model)
    values = np.zeros(model.pool.top + 1, dtype=bool)
    bound = claimed = float(constant + model.offset)
    claims: set[str] = set()
    trace: list[tuple[float, float | None, float | None]] = []
    answered = solved = 0
    for sub, ids in [] if unsat else comps:
        left = time_limit - (time.perf_counter() - t0)
        try:
            if left <= 0:
                break
            sol = solve(sub, solver=engine, time_limit=left, seed=seed)
        except interrupt_types():
            break
        if sol.status is Status.INFEASIBLE:
            unsat = True
            break
        bound += 0.0 if sol.bound is None else float(sol.bound)
        cost, claim = _claimed(sol)
        claimed += float("nan") if cost is None else float(cost)
        claims.add(claim)
        if sol.values is not None:
            answered += 1
            solved += sol.status is Status.OPTIMAL
            sub_values = np.asarray(sol.values, dtype=bool)[1 : ids.size + 1]
            named = ids <= model.pool.top
            values[ids[named]] = sub_values[named]
        trace.append((time.perf_counter() - t0, None, bound))
        if progress is not None:
            progress(ProgressEvent(trace[-1][0], None, bound))
    wall = time.perf_counter() - t0
    have_all = not unsat and answered == len(comps)
    status = (
        Status.INFEASIBLE
        if unsat
        else Status.TIMEOUT
        if not have_all
        else Status.OPTIMAL
        if solved == len(comps)
        else Status.FEASIBLE
    )
    objective = None
    if have_all:
        _, objective = model.evaluate(values)
        trace.append((wall, objective, bound))
    return {
        "status": status.value,
        "values": values if have_all else None,
        "objective": objective,
        "bound": bound if status is not Status.INFEASIBLE else None,
        "wall": wall,
        "found_by": f"{engine}+split",
        "found_at": wall if have_all else None,
        "trace": trace,
        "claimed_cost": round(claimed) if have_all and claimed == claimed else None,
        "claimed_status": "; ".join(sorted(c for c in claims if c)),
        "message": f"{solved} of {len(comps)} components solved to optimality",
        "components": len(comps),
    }
