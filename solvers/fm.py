"""pysat's FM (Fu-Malik, the WMSU1 variant for weights): the first core-guided MaxSAT algorithm.

A baseline for the benchmark rather than a tool: it relaxes each soft clause of a core with a
fresh variable and adds an at-most-one constraint over them (here a sequential counter), so it
proves optimality like RC2 but with weaker relaxations. ``FM`` has no interrupt, so the solve
runs in a child process whose time limit the parent enforces (:mod:`illuknit.solvers.isolate`);
on the limit the status is ``timeout`` with no assignment. The formula handed to FM is built in
the child, so FM's changes to it never reach the caller.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any

from illuknit.solvers.base import (
    OracleBackendBase,
    ProgressCallback,
    ProgressEvent,
    Solution,
    Status,
)
from illuknit.solvers.isolate import run_in_child

if TYPE_CHECKING:
    from illuknit.solvers.model import Model

__all__ = ["FMBackend"]


def _run_fm(model: Model, oracle: str) -> dict[str, Any]:
    from pysat.card import EncType
    from pysat.examples.fm import FM
    from pysat.formula import WCNF

    cs = model.to_clauses()
    w = WCNF()
    w.extend(cs.hard)
    w.extend(cs.soft, weights=list(cs.weights))
    fm = FM(w, enc=EncType.seqcounter, solver=oracle, verbose=0)
    try:
        if not fm.compute():
            return {"sat": False}
        return {"sat": True, "lits": list(fm.model), "cost": int(fm.cost)}
    finally:
        fm.delete()


class FMBackend(OracleBackendBase):
    """pysat FM (WMSU1) in a child process; ``fm:ORACLE`` picks the SAT oracle (default m22)."""

    name = "fm"
    requires = ("pysat",)
    distribution = "python-sat"
    default_oracle = "m22"

    def __init__(self, oracle: str | None = None) -> None:
        super().__init__(oracle)
        self.time_limited = False  # python-sat's FM takes no limit: only the child's kill stops it

    def solve(
        self,
        model: Model,
        *,
        time_limit: float | None = None,
        seed: int = 0,
        progress: ProgressCallback | None = None,
    ) -> Solution:
        t0 = time.perf_counter()
        res = run_in_child(lambda _p: _run_fm(model, self.oracle), time_limit=time_limit)
        stats: dict[str, Any] = {"peak_rss_mb": res.peak_rss_mb}
        if failed := self.child_failure(model, res, t0, stats):
            return failed
        if not res.value["sat"]:
            return self.solution(model, Status.INFEASIBLE, t0, stats=stats)
        values, cost, bad = self.checked_assignment(
            model, res.value["lits"], res.value["cost"], t0, stats, who="FM's"
        )
        if bad:
            return bad
        if progress:
            progress(ProgressEvent(time.perf_counter() - t0, cost, cost))
        return self.solution(model, Status.OPTIMAL, t0, values, cost, float(cost), stats)
