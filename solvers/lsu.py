"""Linear SAT-UNSAT search (LSU) on pysat: an anytime MaxSAT algorithm.

Each soft clause gets a selector literal ``s`` (a unit soft clause ``[l]`` uses ``-l`` itself) and
the hard formula gains ``clause + [s]``. After each model of cost ``c`` (computed with numpy over
the original model), the constraint ``sum w_i s_i <= c - 1`` is added through an incremental
totalizer over the selectors, each repeated ``w_i`` times (fine for the small integer weights of
the illusion models; :meth:`LSUBackend.handles` refuses total weights above ``MAX_TOTAL_WEIGHT``).
UNSAT after a model proves it optimal, and so does a model whose cost meets a proven
``lower_bound`` handed in (the knit-aware model's Lagrangian bound, from a warm start). Upper bounds improve over time, so a time limit or Ctrl-C
returns the best model so far (status ``timeout`` / ``feasible``); the lower bound is 0 until
optimality is proven.

Unlike pysat's own ``LSU`` class this handles weights and keeps the best model's phases so each
SAT call starts near the incumbent.
"""

from __future__ import annotations

import time
from threading import Timer
from typing import TYPE_CHECKING, Any

import numpy as np

from illuknit.solvers.base import (
    OracleBackendBase,
    ProgressCallback,
    ProgressEvent,
    Solution,
    Status,
    assignment_from_lits,
    interrupt_types,
)

if TYPE_CHECKING:
    from illuknit.solvers.model import ClauseSet, Model

__all__ = ["MAX_TOTAL_WEIGHT", "LSUBackend"]

#: The totalizer repeats each selector by its weight; beyond this the encoding gets too large.
MAX_TOTAL_WEIGHT = 200_000
#: Above this many totalizer clauses (inputs x bound, roughly) the search stops with its incumbent.
MAX_TOTALIZER_SIZE = 30_000_000


class LSUBackend(OracleBackendBase):
    """pysat linear search from above (SAT-UNSAT), weighted via a repeated-selector totalizer.

    ``oracle`` names the SAT solver (python-sat's names, default ``g4``); ``lsu:ORACLE`` by name.
    """

    name = "lsu"
    accepts_lower_bound = True
    requires = ("pysat",)
    distribution = "python-sat"
    default_oracle = "g4"
    interruptible_oracle = True

    def why_not(self, model: Model) -> str | None:
        if model.total_soft_weight() <= MAX_TOTAL_WEIGHT:
            return None
        return f"total soft weight {model.total_soft_weight()} exceeds {MAX_TOTAL_WEIGHT}"

    def solve(
        self,
        model: Model,
        *,
        time_limit: float | None = None,
        seed: int = 0,
        progress: ProgressCallback | None = None,
        lower_bound: int | None = None,
    ) -> Solution:
        from pysat.solvers import Solver

        t0 = time.perf_counter()
        cs = model.to_clauses()
        top = model.pool.top
        oracle = Solver(name=self.oracle, bootstrap_with=cs.hard)
        sels, wts, nv = _add_selectors(oracle, cs)
        if model.hint is not None:
            h = np.asarray(model.hint, dtype=bool)
            oracle.set_phases([i if h[i] else -i for i in range(1, top + 1)])
        deadline = None if time_limit is None else t0 + time_limit
        best_v: np.ndarray | None = None
        best_cost: int | None = None
        proven = False
        interrupted = False
        calls = 0
        tot: Any = None
        stats_note = ""
        if model.hint is not None:
            ok, hint_cost = model.evaluate(model.hint)
            if ok:
                # start from the warm start: the first SAT call must already beat it
                best_v, best_cost = np.asarray(model.hint, dtype=bool), hint_cost
        try:
            # a model of cost 0 (or of a proven lower bound's cost) needs no UNSAT call
            floor = model.offset if lower_bound is None else max(model.offset, lower_bound)
            if best_cost is not None and best_cost <= floor:
                proven = True
            elif best_cost is not None:
                tot = self._bound(oracle, sels, wts, best_cost - model.offset, nv)
                if tot is None:
                    stats_note = "bound encoding too large; kept the warm start"
            while not proven and (tot is not None or best_v is None):
                budget = None if deadline is None else deadline - time.perf_counter()
                if budget is not None and budget <= 0:
                    break
                res = _timed_solve(oracle, budget)
                calls += 1
                if res is None:
                    break
                if res is False:
                    proven = True
                    break
                lits = oracle.get_model()
                v = assignment_from_lits(lits, top)
                _, cost = model.evaluate(v)
                best_v, best_cost = v, cost
                oracle.set_phases(lits[:top])
                if progress:
                    progress(ProgressEvent(time.perf_counter() - t0, cost, None))
                raw = cost - model.offset
                if cost <= floor:
                    proven = True
                    break
                if tot is None:
                    tot = self._bound(oracle, sels, wts, raw, nv)
                    if tot is None:
                        stats_note = "bound encoding too large; stopped at the first model"
                        break
                else:
                    # sum < raw  <=>  not (sum >= raw)  <=>  -rhs[raw - 1]
                    oracle.add_clause([-tot.rhs[raw - 1]])
        except interrupt_types():
            interrupted = True
        finally:
            oracle.delete()
            if tot is not None:
                tot.delete()
        stats: dict[str, Any] = {"sat_calls": calls, "interrupted": interrupted}
        if stats_note:
            stats["message"] = stats_note
        return self._solution(model, t0, stats, best_v, best_cost, proven=proven)

    def _solution(
        self,
        model: Model,
        t0: float,
        stats: dict[str, Any],
        best_v: np.ndarray | None,
        best_cost: int | None,
        *,
        proven: bool,
    ) -> Solution:
        """The search's outcome: optimal when proven, else feasible (stopped) or timeout."""
        wall = time.perf_counter() - t0
        interrupted = bool(stats["interrupted"])
        stats_note = stats.get("message", "")
        if best_v is None:
            if proven:
                return Solution(
                    Status.INFEASIBLE, None, None, None, wall, stats, self.name, model.pool
                )
            return Solution(Status.TIMEOUT, None, None, None, wall, stats, self.name, model.pool)
        assert best_cost is not None
        if proven:
            return Solution(
                Status.OPTIMAL,
                best_v,
                best_cost,
                float(best_cost),
                wall,
                stats,
                self.name,
                model.pool,
            )
        gave_up = bool(stats_note) and not interrupted
        st = Status.FEASIBLE if (interrupted or gave_up) else Status.TIMEOUT
        return Solution(
            st, best_v, best_cost, float(model.offset), wall, stats, self.name, model.pool
        )

    @staticmethod
    def _bound(oracle: Any, sels: list[int], wts: list[int], raw: int, nv: int) -> Any:
        """Add ``sum w_i s_i <= raw - 1`` via a totalizer; None if it would be too large."""
        from pysat.card import ITotalizer

        if raw <= 0 or sum(wts) * raw > MAX_TOTALIZER_SIZE:
            return None
        expanded = [s for s, w in zip(sels, wts, strict=True) for _ in range(w)]
        tot = ITotalizer(lits=expanded, ubound=raw, top_id=nv)
        oracle.append_formula(tot.cnf.clauses)
        oracle.add_clause([-tot.rhs[raw - 1]])
        return tot


def _add_selectors(oracle: Any, cs: ClauseSet) -> tuple[list[int], list[int], int]:
    """Give each soft clause a selector literal that is true when the clause is violated.

    A unit soft clause ``[l]`` uses ``-l``; a longer one gets a fresh variable added to it.
    Returns (selectors, their weights, the largest variable id now in use).
    """
    nv = cs.nv
    sels: list[int] = []
    wts: list[int] = []
    for cl, w in zip(cs.soft, cs.weights, strict=True):
        if len(cl) == 1:
            sels.append(-cl[0])
        else:
            nv += 1
            oracle.add_clause([*cl, nv])
            sels.append(nv)
        wts.append(w)
    return sels, wts, nv


def _timed_solve(oracle: Any, budget: float | None) -> bool | None:
    """One SAT call, interrupted after ``budget`` seconds (None: when interrupted)."""
    timer = Timer(budget, oracle.interrupt) if budget is not None else None
    if timer is not None:
        timer.start()
    try:
        return oracle.solve_limited(expect_interrupt=True)
    finally:
        if timer is not None:
            timer.cancel()
        oracle.clear_interrupt()
