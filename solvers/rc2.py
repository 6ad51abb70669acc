"""pysat RC2: core-guided (OLL) exact MaxSAT.

The model is encoded to clauses (:meth:`Model.to_clauses`); weighted models use
``RC2Stratified``. RC2 only improves a lower bound until it finds the optimum, so on a time limit
(or Ctrl-C) it has no assignment of its own: the backend then returns the model's hint or one
plain SAT solution of the hard constraints, with status ``timeout`` and RC2's lower bound.
"""

from __future__ import annotations

import time
from threading import Timer
from typing import TYPE_CHECKING

from illuknit.solvers.base import (
    ProgressCallback,
    ProgressEvent,
    Solution,
    Status,
    assignment_from_lits,
    fallback_assignment,
)

if TYPE_CHECKING:
    from illuknit.model import Model

__all__ = ["RC2Backend"]


class RC2Backend:
    """pysat RC2 (``RC2Stratified`` for weighted models), adapt + exhaust + minimise cores."""

    name = "rc2"
    extra: str | None = None
    exact = True

    def handles(self, model: Model) -> bool:
        return True

    def is_available(self) -> bool:
        try:
            import pysat.examples.rc2  # noqa: F401
        except ImportError:
            return False
        return True

    def solve(
        self,
        model: Model,
        *,
        time_limit: float | None = None,
        seed: int = 0,
        progress: ProgressCallback | None = None,
    ) -> Solution:
        from pysat.examples.rc2 import RC2, RC2Stratified

        t0 = time.perf_counter()
        wcnf = model.to_pysat_wcnf()
        cls = RC2Stratified if model.is_weighted() else RC2
        rc2 = cls(wcnf, solver="g3", adapt=True, exhaust=True, minz=True)
        timer = Timer(time_limit, rc2.interrupt) if time_limit is not None else None
        interrupted = False
        try:
            if timer is not None:
                timer.start()
            try:
                lits = rc2.compute(expect_interrupt=True)
            except KeyboardInterrupt:
                lits, interrupted = None, True
            finally:
                if timer is not None:
                    timer.cancel()
            stopped = interrupted or rc2.interrupted
            bound = float(rc2.cost) + model.offset
            stats = {"cores": len(getattr(rc2, "sums", [])), "interrupted": interrupted}
        finally:
            rc2.delete()
        wall = time.perf_counter() - t0
        top = model.pool.top
        if lits is not None and not stopped:
            v = assignment_from_lits(lits, top)
            _, cost = model.evaluate(v)
            if progress:
                progress(ProgressEvent(wall, cost, cost))
            return Solution(
                Status.OPTIMAL, v, cost, float(cost), wall, stats, self.name, model.pool
            )
        if not stopped:
            return Solution(Status.INFEASIBLE, None, None, None, wall, stats, self.name, model.pool)
        v, cost = fallback_assignment(model)
        wall = time.perf_counter() - t0
        status = Status.FEASIBLE if interrupted else Status.TIMEOUT
        if v is None:
            status = Status.TIMEOUT
        return Solution(status, v, cost, bound, wall, stats, self.name, model.pool)
