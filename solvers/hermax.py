"""The MaxSAT Evaluation's solvers through hermax (``pip install 'illuknit[maxsat]'``).

`hermax <https://pypi.org/project/hermax/>`_ wraps EvalMaxSAT, UWrMaxSat, CASHWMaxSAT, Open-WBO,
CGSS, WMaxCDCL and anytime (incomplete) solvers such as Loandra and Open-WBO-Inc behind one
IPAMIR-style API (``add_clause``, ``add_soft_unit``, ``solve``, ``get_cost``, ``get_model``),
and since 1.2.10 the 2026 Evaluation's Aperture and CoreTrail.
Each backend here encodes the model (:meth:`Model.to_clauses`; a non-unit soft clause gets a
relaxation variable), and runs the solver **in a child process** (:mod:`illuknit.solvers.isolate`):
most complete solvers refuse a time limit (``time_limited = False``), so the parent enforces it,
and a crash in C code costs one result. The anytime solvers and CoreTrail get the time limit
themselves and return their best model.

The solver's own claims (status, cost) are kept in ``stats`` (``claimed_status``,
``claimed_cost``); the returned ``objective`` is always recomputed from the model, and an
assignment that breaks a hard clause is an ``error``.
"""

from __future__ import annotations

import importlib
import time
from typing import TYPE_CHECKING, Any, Self

import numpy as np

from illuknit.solvers.base import (
    BackendBase,
    ProgressCallback,
    ProgressEvent,
    Solution,
    Status,
)
from illuknit.solvers.isolate import run_in_child

if TYPE_CHECKING:
    from illuknit.solvers.model import Model

__all__ = ["HERMAX_SOLVERS", "HermaxBackend"]

#: backend name -> (hermax class "module:attr", anytime (incomplete), takes a time limit itself:
#: ``solve(time_limit=...)`` returns the best model so far; the others refuse one and only the
#: parent's kill stops them)
HERMAX_SOLVERS: dict[str, tuple[str, bool, bool]] = {
    "evalmaxsat": ("hermax.incremental:EvalMaxSAT", False, False),
    "uwrmaxsat": ("hermax.incremental:UWrMaxSAT", False, False),
    "cashwmaxsat": ("hermax.non_incremental:CASHWMaxSAT", False, False),
    "openwbo": ("hermax.non_incremental:OpenWBO", False, False),
    "cgss": ("hermax.non_incremental:CGSS", False, False),
    "wmaxcdcl": ("hermax.non_incremental:WMaxCDCL", False, False),
    "aperture": ("hermax.incremental:Aperture", False, False),
    "coretrail": ("hermax.incremental:CoreTrail", False, True),
    "loandra": ("hermax.non_incremental.incomplete:Loandra", True, True),
    "openwbo-inc": ("hermax.non_incremental.incomplete:OpenWBOInc", True, True),
    "tt-openwbo-inc": ("hermax.non_incremental.incomplete:TTOpenWBOInc", True, True),
    "nuwls-c-ibr": ("hermax.non_incremental.incomplete:NuWLSCIBR", True, True),
    "spb-maxsat-c-fps": ("hermax.non_incremental.incomplete:SPBMaxSATCFPS", True, True),
}

# IPAMIR status codes (hermax.core.ipamir_solver_interface.SolveStatus)
_OPTIMUM, _SAT, _UNSAT = 30, 10, 20


def _run_hermax(
    class_path: str,
    model: Model,
    time_limit: float | None,
    limited: bool,
    started: float | None = None,
) -> dict[str, Any]:
    """Build and solve in the current (child) process; a plain dict goes back to the parent.

    A solver that takes a time limit gets what is left of ``time_limit`` after the build
    (``started``: ``time.perf_counter()`` when the backend was called), so it answers on time.
    """
    module, _, attr = class_path.partition(":")
    cls = getattr(importlib.import_module(module), attr)
    cs = model.to_clauses()
    nv = cs.nv
    solver = cls()
    try:
        for c in cs.hard:
            solver.add_clause([int(x) for x in c])
        # IPAMIR's set_soft *replaces* the weight of a literal declared before: unit soft
        # clauses on one literal are summed, and a variable soft in both polarities is relaxed
        units: dict[int, int] = {}
        for c, w in zip(cs.soft, cs.weights, strict=True):
            if len(c) == 1 and -int(c[0]) not in units:
                units[int(c[0])] = units.get(int(c[0]), 0) + int(w)
            else:
                nv += 1
                solver.add_soft_relaxed([int(x) for x in c], int(w), relax_var=nv)
        for lit, w in units.items():
            solver.add_soft_unit(lit, w)
        kwargs: dict[str, float] = {}
        if limited and time_limit is not None:
            used = 0.0 if started is None else time.perf_counter() - started
            kwargs["time_limit"] = max(0.1, time_limit - used - 0.1 - 0.02 * time_limit)
        t0 = time.perf_counter()
        solver.solve(**kwargs)
        code = int(solver.get_status())
        out: dict[str, Any] = {"code": code, "seconds": time.perf_counter() - t0}
        if code in (_OPTIMUM, _SAT):
            out["cost"] = int(solver.get_cost())
            out["lits"] = np.asarray(solver.get_model() or [], dtype=np.int64)
        out["signature"] = str(solver.signature())
        return out
    finally:
        solver.close()


class HermaxBackend(BackendBase):
    """One hermax solver by name (see :data:`HERMAX_SOLVERS`), run in a child process."""

    extra = "maxsat"
    requires = ("hermax",)
    distribution = "hermax"

    @classmethod
    def from_name(cls, name: str, argument: str | None) -> Self | None:
        """One class, many names: the registered name chooses the hermax solver."""
        return cls(name) if argument is None else None

    def __init__(self, name: str) -> None:
        self.name = name
        self.class_path, self.anytime, self.time_limited = HERMAX_SOLVERS[name]
        self.exact = not self.anytime
        self.proves_bound = self.exact

    def solve(
        self,
        model: Model,
        *,
        time_limit: float | None = None,
        seed: int = 0,
        progress: ProgressCallback | None = None,
    ) -> Solution:
        t0 = time.perf_counter()
        res = run_in_child(
            lambda _progress: _run_hermax(
                self.class_path, model, time_limit, self.time_limited, t0
            ),
            time_limit=time_limit,
            interruptible=False,  # a C solver: stopped by its own limit, or by the kill
        )
        stats: dict[str, Any] = {"peak_rss_mb": res.peak_rss_mb}
        if failed := self.child_failure(model, res, t0, stats):
            return failed
        out = res.value
        code = out["code"]
        stats["signature"] = out["signature"]
        if code == _UNSAT:
            stats["claimed_status"] = "UNSATISFIABLE"
            return self.solution(model, Status.INFEASIBLE, t0, stats=stats)
        if "lits" not in out:
            stats["message"] = f"solver ended with IPAMIR status {code} and no model"
            # no model at the limit (its own, or the request to stop it got): a timeout
            late = time_limit is not None and time.perf_counter() - t0 >= time_limit
            timed_out = late or (self.time_limited and time_limit is not None)
            return self.solution(
                model, Status.TIMEOUT if timed_out else Status.ERROR, t0, stats=stats
            )
        stats["claimed_status"] = "OPTIMUM FOUND" if code == _OPTIMUM else "SATISFIABLE"
        values, cost, bad = self.checked_assignment(
            model, out["lits"], out["cost"], t0, stats, who="the solver's"
        )
        if bad:
            return bad
        if progress:
            progress(ProgressEvent(time.perf_counter() - t0, cost, None))
        if code == _OPTIMUM:
            return self.solution(model, Status.OPTIMAL, t0, values, cost, float(cost), stats)
        limited = time_limit is not None and self.time_limited
        st = Status.TIMEOUT if limited else Status.FEASIBLE
        return self.solution(model, st, t0, values, cost, None, stats)
