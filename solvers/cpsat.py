"""OR-Tools CP-SAT on the native model.

Translation: one Boolean per pool variable (created in id order, so the response's flat solution
vector maps straight back to ids); hard clauses -> ``AddBoolOr``; exactly-one / at-most-k /
at-least-k / linear <= kept as native constraints; a unit soft clause ``[l]`` with weight ``w``
contributes ``w * (1 - l)`` to the objective, a wider one gets a violation Boolean ``b`` with
``AddBoolOr(clause + [b])`` and contributes ``w * b``. The model's hint becomes a CP-SAT hint.

Worker choice, measured on the illusion models (loaded 2-core machine, 20 s limits): on small
and medium models one worker with the full LP relaxation (``linearization_level=2``) is by far
the best — it proved the knit-aware optimum at 30 x 30 and 40 x 40 units in 16-19 s and the
logical one at 100 x 100 in 12-21 s, while CP-SAT's default 2-worker portfolio timed out with a
weak bound (a 75-variable model took 12 s against 0.02 s). On large knit-aware models (70 x 70)
that single LP worker found no solution at all, while two workers — one full-LP worker
(``max_lp``) for the bound and one ``quick_restart_no_lp`` worker for solutions — improved on
the warm start and proved a real bound. So by default (``num_workers=None``) models with more
than ``LARGE_MODEL_VARS`` variables *and* cross-wale constraints run the 2-worker pair, others
the single LP worker. ``CPSATBackend(num_workers=N)`` forces N workers of CP-SAT's own portfolio.

Honours ``time_limit`` (returning the best assignment and CP-SAT's best bound with status
``timeout``; if CP-SAT found nothing in time the model's hint is returned when feasible), and
catches SIGINT the same way (status ``feasible``, ``stats["interrupted"]``).
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any

import numpy as np

from illuknit.solvers.base import (
    BackendBase,
    BackendKind,
    ProgressCallback,
    ProgressEvent,
    Solution,
    Status,
    fallback_assignment,
)

if TYPE_CHECKING:
    from illuknit.solvers.model import Model

__all__ = ["LARGE_MODEL_VARS", "CPSATBackend"]

#: Above this many variables (with cross-wale constraints) the 2-worker LP + search pair is used.
LARGE_MODEL_VARS = 12_000


class CPSATBackend(BackendBase):
    """OR-Tools CP-SAT (worker choice by model size; see the module docstring)."""

    name = "cpsat"
    kind = BackendKind.CP
    accepts_lower_bound = True
    requires = ("ortools",)
    distribution = "ortools"

    def __init__(self, num_workers: int | None = None, linearization_level: int = 2) -> None:
        self.num_workers = num_workers
        self.linearization_level = linearization_level

    def _workers(self, model: Model) -> tuple[int, list[str]]:
        if self.num_workers is not None:
            return self.num_workers, []
        separable = model.problem is not None and model.problem.separable
        if model.num_vars > LARGE_MODEL_VARS and not separable:
            return 2, ["max_lp", "quick_restart_no_lp"]
        return 1, []

    def solve(
        self,
        model: Model,
        *,
        time_limit: float | None = None,
        seed: int = 0,
        progress: ProgressCallback | None = None,
        lower_bound: int | None = None,
    ) -> Solution:
        from ortools.sat.python import cp_model

        t0 = time.perf_counter()
        cp, obj_vars = _build(model, cp_model, lower_bound=lower_bound)
        top = model.pool.top

        solver = cp_model.CpSolver()
        workers, subsolvers = self._workers(model)
        solver.parameters.num_workers = workers
        solver.parameters.linearization_level = self.linearization_level
        if subsolvers:
            solver.parameters.subsolvers.extend(subsolvers)
        solver.parameters.random_seed = int(seed)
        solver.parameters.catch_sigint_signal = True
        if time_limit is not None:
            remaining = time_limit - (time.perf_counter() - t0)
            solver.parameters.max_time_in_seconds = max(0.05, remaining)
        build = time.perf_counter() - t0

        cb = _Progress(progress, t0) if progress else None
        status = solver.Solve(cp, cb) if cb else solver.Solve(cp)
        wall = time.perf_counter() - t0
        stats = {
            "build_time": round(build, 4),
            "cpsat_status": solver.StatusName(status),
            "conflicts": int(solver.NumConflicts()),
            "branches": int(solver.NumBranches()),
            "num_workers": workers,
            "subsolvers": subsolvers,
        }
        limited = time_limit is not None and wall >= 0.95 * time_limit
        if status == cp_model.INFEASIBLE:
            return Solution(Status.INFEASIBLE, None, None, None, wall, stats, self.name, model.pool)
        if status in (cp_model.OPTIMAL, cp_model.FEASIBLE):
            sol = np.fromiter(solver.ResponseProto().solution, dtype=np.int64)[:top].astype(bool)
            v = np.concatenate([[False], sol])
            _, cost = model.evaluate(v)
            bound: float | None = float(solver.BestObjectiveBound()) if obj_vars else float(cost)
            if status == cp_model.OPTIMAL:
                st = Status.OPTIMAL
                bound = float(cost)
            else:
                st = Status.TIMEOUT if limited else Status.FEASIBLE
                stats["interrupted"] = not limited
            return Solution(st, v, cost, bound, wall, stats, self.name, model.pool)
        if status == cp_model.UNKNOWN:
            bound = float(solver.BestObjectiveBound()) if obj_vars else None
            fb, fb_cost = (
                fallback_assignment(model, budget=1.0) if model.hint is not None else (None, None)
            )
            if fb is not None:
                stats["fallback"] = "hint"
            wall = time.perf_counter() - t0
            return Solution(Status.TIMEOUT, fb, fb_cost, bound, wall, stats, self.name, model.pool)
        stats["message"] = f"CP-SAT returned {solver.StatusName(status)}"
        return Solution(Status.ERROR, None, None, None, wall, stats, self.name, model.pool)


class _Progress:
    """Solution callback forwarding improvements to a progress function (built lazily)."""

    def __new__(cls, fn: ProgressCallback, t0: float) -> Any:
        from ortools.sat.python import cp_model

        class _CB(cp_model.CpSolverSolutionCallback):
            def on_solution_callback(self) -> None:
                fn(
                    ProgressEvent(
                        time.perf_counter() - t0,
                        float(self.ObjectiveValue()),
                        float(self.BestObjectiveBound()),
                    )
                )

        return _CB()


def _proto_lits(a: np.ndarray) -> np.ndarray:
    """Model literals -> CP-SAT proto literals (var id v is proto index v-1; not(i) is -i-1)."""
    return np.where(a > 0, a - 1, a)


def _join(rows: list[list[int]]) -> list[str]:
    return [", ".join(map(str, r)) for r in rows]


def _build(model: Model, cp_model: Any, *, lower_bound: int | None = None) -> tuple[Any, list[int]]:
    """The CP-SAT model, built as protobuf text and parsed in one call; a proven
    ``lower_bound`` of the objective becomes the linear constraint ``objective >= lower_bound``
    (CP-SAT's own bound starts there, and a solution that meets it is proven optimal).

    One Python API call per clause costs ~20 us in OR-Tools 9.x, seconds for the 10^5 clauses of a
    large illusion model; the text route builds the same proto several times faster. Cardinality
    and linear constraints (few) go through the API afterwards.
    """
    top = model.pool.top
    h = None if model.hint is None else np.asarray(model.hint, dtype=bool)
    parts: list[str] = []
    for block, _family in model.hard_blocks():
        pl = _proto_lits(block)
        rows = (
            pl.tolist()
            if not (block == 0).any()
            else [
                [x for x, o in zip(r, ro, strict=True) if o]
                for r, ro in zip(pl.tolist(), block.tolist(), strict=True)
            ]
        )
        parts.extend(f"constraints {{ bool_or {{ literals: [{t}] }} }}" for t in _join(rows))
    obj_idx: list[int] = []
    obj_coef: list[int] = []
    offset = int(model.offset)
    n_aux = 0
    hint_aux: list[int] = []
    for block, weights in model.soft_blocks():
        widths = (block != 0).sum(axis=1)
        w = weights.astype(np.int64)
        unit = widths == 1
        if unit.any():
            lits = block[unit].sum(axis=1)  # the one non-zero literal (padding is 0)
            wu = w[unit]
            pos = lits > 0
            # violated <=> not l:  w * (1 - x) for l = x,  w * x for l = not x
            offset += int(wu[pos].sum())
            obj_idx.extend((np.abs(lits) - 1).tolist())
            obj_coef.extend(np.where(pos, -wu, wu).tolist())
        wide = ~unit
        if wide.any():
            blk = block[wide]
            k = blk.shape[0]
            aux = np.arange(top + n_aux, top + n_aux + k)
            n_aux += k
            pl = _proto_lits(blk)
            rows = [
                [x for x, o in zip(r, ro, strict=True) if o] + [b]
                for r, ro, b in zip(pl.tolist(), blk.tolist(), aux.tolist(), strict=True)
            ]
            parts.extend(f"constraints {{ bool_or {{ literals: [{t}] }} }}" for t in _join(rows))
            obj_idx.extend(aux.tolist())
            obj_coef.extend(w[wide].tolist())
            if h is not None:
                a = np.abs(blk)
                lv = np.where(blk > 0, h[a], ~h[a]) & (blk != 0)
                hint_aux.extend((~lv.any(axis=1)).astype(int).tolist())
    head = ["variables { domain: [0, 1] }"] * (top + n_aux)
    tail: list[str] = []
    if obj_idx:
        # CP-SAT rejects a variable listed twice in the objective: merge the terms
        coef = np.bincount(obj_idx, weights=obj_coef, minlength=top + n_aux).astype(np.int64)
        nz = np.flatnonzero(coef)
        tail.append(
            f"objective {{ vars: [{', '.join(map(str, nz.tolist()))}] "
            f"coeffs: [{', '.join(map(str, coef[nz].tolist()))}] offset: {offset} }}"
        )
        if lower_bound is not None:
            tail.append(
                f"constraints {{ linear {{ vars: [{', '.join(map(str, nz.tolist()))}] "
                f"coeffs: [{', '.join(map(str, coef[nz].tolist()))}] "
                f"domain: [{int(lower_bound) - offset}, {2**62}] }} }}"
            )
    if h is not None:
        hv = h[1 : top + 1].astype(int).tolist() + hint_aux
        tail.append(
            f"solution_hint {{ vars: [{', '.join(map(str, range(len(hv))))}] "
            f"values: [{', '.join(map(str, hv))}] }}"
        )
    cp = cp_model.CpModel()
    if not cp.Proto().parse_text_format("\n".join(head + parts + tail)):
        raise RuntimeError("CP-SAT could not parse the generated model")
    if model.cards or model.linears:
        _add_natives(cp, model)
    return cp, obj_idx


def _add_natives(cp: Any, model: Model) -> None:
    """The model's cardinality and linear constraints, through the CP-SAT API (they are few)."""
    xs = [cp.get_bool_var_from_proto_index(i) for i in range(model.pool.top)]

    def lit(v: int) -> Any:
        return xs[v - 1] if v > 0 else xs[-v - 1].Not()

    for c in model.cards:
        ls = [lit(v) for v in c.lits]
        if c.op == "==" and c.k == 1:
            cp.add_exactly_one(ls)
        elif c.op == "<=" and c.k == 1:
            cp.add_at_most_one(ls)
        elif c.op == "<=":
            cp.add(sum(ls) <= c.k)
        elif c.op == ">=":
            cp.add(sum(ls) >= c.k)
        else:
            cp.add(sum(ls) == c.k)
    for lc in model.linears:
        cp.add(sum(cf * lit(v) for v, cf in zip(lc.lits, lc.coeffs, strict=True)) <= lc.bound)
