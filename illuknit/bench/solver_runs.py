"""Solver rows of the benchmark: one (instance, model, solver, warm start) run each, isolated
and verified.

A run builds the model in the parent, then solves it in a forked child
(:func:`illuknit.solvers.isolate.run_in_child`) with the time and memory limits the parent
enforces, through the one orchestration :func:`illuknit.solvers.solve`. The child gets its own
copy of everything (python-sat's RC2 rewrites the formula it is handed), and a crash, a hang or
a silent exit is one row with status ``error``/``timeout`` and the reason.

The parent then checks the answer against **its own copy** of the model: the assignment must
satisfy every hard clause (else status ``error``, reason "violates hard clauses"), and the cost
is recomputed (``verified_cost``) independently of what the solver claimed (``claimed_cost``:
its ``o`` line, IPAMIR cost, or own objective). A claimed optimum is flagged (``flag``) when its
verified cost is above the DP's optimum (exact on the logical and single-view models), when the
claimed cost differs from the verified one, or -- across rows, see :func:`flag_rows` -- when
another run verified a cheaper assignment or a bound is above a verified cost.
"""

from __future__ import annotations

import contextlib
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from illuknit.bench.certify import SPLIT_SUFFIX
from illuknit.bench.instances import Instance, instance_model
from illuknit.bench.pictures import PictureInstance
from illuknit.bench.wcnf_files import read_wcnf, read_wcnf_text
from illuknit.core.errors import IlluknitError
from illuknit.solvers import HERMAX_NAMES, get_backend, parse_solver_name
from illuknit.solvers.base import ProgressEvent, Status
from illuknit.solvers.isolate import run_in_child
from illuknit.solvers.model import Model

__all__ = [
    "ROW_FIELDS",
    "TRACE_FIELDS",
    "SolverTask",
    "backed_at",
    "build_task_model",
    "flag_rows",
    "run_solver_task",
]

#: Columns of solvers.csv, in order (docs/solvers-bench.md explains each).
ROW_FIELDS = (
    "instance",
    "model",
    "run",
    "seed",
    "rows",
    "cols",
    "variables",
    "soft_clauses",
    "solver",
    "oracle",
    "version",
    "warm_start",
    "time_limit",
    "memory_mb",
    "status",
    "verified_cost",
    "claimed_cost",
    "claimed_status",
    "bound",
    "gap",
    "reference_optimum",
    "certificate",
    "time_first",
    "time_best",
    "time_prove",
    "wall_s",
    "cpu_s",
    "peak_rss_mb",
    "found_by",
    "flag",
    "reason",
)
TRACE_FIELDS = (
    "instance",
    "model",
    "solver",
    "warm_start",
    "run",
    "seconds",
    "cost",
    "bound",
    "backed",
)

#: Default memory limit of one run (MB of resident memory of the child's process group).
DEFAULT_MEMORY_MB = 4096.0


@dataclass(frozen=True)
class SolverTask:
    """One solver run: a bench instance (or a WCNF file), a model kind, a solver, a policy."""

    #: a manifest instance, or a picture pair whose models were built on the client
    instance: Instance | PictureInstance | None = None
    model: str = "logical"
    solver: str = "rc2"
    warm_start: str = "none"
    time_limit: float = 10.0
    memory_mb: float | None = DEFAULT_MEMORY_MB
    wcnf: str | None = None
    meta: dict[str, Any] = field(default_factory=dict, compare=False)
    #: repetition number (0-based) and the seed the solver is given
    run: int = 0
    seed: int = 0

    @property
    def key(self) -> tuple[str, str, str, str, int]:
        """(instance, model, solver, warm start, run): one row of the table."""
        model = self.model if self.wcnf is None else "wcnf"
        return (self.instance_name, model, self.solver, self.warm_start, self.run)

    @property
    def split(self) -> bool:
        """The row's solver gets the formula split into independent components first (the
        labelled pre-processing option, solver name ``NAME+split``)."""
        return self.solver.endswith(SPLIT_SUFFIX)

    @property
    def engine(self) -> str:
        """The solver's own name, without the pre-processing label."""
        return self.solver.removesuffix(SPLIT_SUFFIX)

    @property
    def instance_name(self) -> str:
        if self.wcnf is not None:
            return Path(self.wcnf).name
        assert self.instance is not None
        return self.instance.name


def build_task_model(task: SolverTask, content: bytes | None = None) -> tuple[Model, int | None]:
    """(the task's model, the DP's optimum where the DP is exact on it, else None).

    ``content`` is the WCNF file's bytes when they travelled with the task (a Dask worker has no
    access to the file); the file is read otherwise. A picture pair's model was built on the
    client (:mod:`illuknit.bench.pictures`) and travels with the task.
    """
    if task.wcnf is not None:
        if content is not None:
            return read_wcnf_text(
                content.decode("ascii", errors="replace"), Path(task.wcnf).stem
            ), None
        return read_wcnf(task.wcnf), None
    assert task.instance is not None
    if isinstance(task.instance, PictureInstance):  # built on the client, shipped built
        return task.instance.model(task.model)
    return instance_model(task.instance, model=task.model)


#: Modules a backend imports when it solves, loaded in the parent before the fork so that a
#: run's time is solving, not importing (backend name prefix -> modules).
PRELOAD = {
    "rc2": ("pysat.examples.rc2", "pysat.formula", "scipy.sparse.csgraph"),
    "lsu": ("pysat.solvers", "pysat.card"),
    "fm": ("pysat.examples.fm", "pysat.card", "pysat.formula"),
    "cpsat": ("ortools.sat.python.cp_model",),
    "hermax": ("hermax.incremental", "hermax.non_incremental"),
}


def preload_backend(solver: str) -> None:
    """Import what ``solver`` will need (see :data:`PRELOAD`); missing modules are skipped."""
    import importlib
    import importlib.util

    base = parse_solver_name(solver).base
    for mod in PRELOAD.get("hermax" if base in HERMAX_NAMES else base, ()):
        if importlib.util.find_spec(mod.partition(".")[0]) is not None:
            importlib.import_module(mod)


def _child_solve(model: Model, task: SolverTask, progress: Any = None) -> dict[str, Any]:
    """In the child: the orchestrated solve, returned as plain data; every improvement it
    reports is also sent to the parent as it happens (``progress``), so the bounds and costs
    reported before a kill are not lost."""
    from illuknit.solvers import get_backend, solve

    backend = get_backend(task.engine)
    if task.split and parse_solver_name(task.engine).base != "rc2":
        from illuknit.bench.split import solve_split

        out = solve_split(
            model, task.engine, time_limit=task.time_limit, seed=task.seed, progress=progress
        )
        return {**out, "version": backend.version()}
    if parse_solver_name(task.engine).base == "rc2":
        # in this child only: plain RC2 on the formula as given, or after the labelled split
        backend_class = type(backend)
        backend_class.split = task.split  # type: ignore[attr-defined]
    sol = solve(
        model,
        solver=task.engine,
        warm_start=task.warm_start,
        time_limit=task.time_limit,
        seed=task.seed,
        progress=progress,
    )
    stats = dict(sol.stats)
    return {
        "status": sol.status.value,
        "values": None if sol.values is None else np.asarray(sol.values, dtype=bool),
        "objective": sol.objective,
        "bound": sol.bound,
        "wall": sol.wall_time,
        "found_by": sol.found_by,
        "found_at": sol.found_at,
        "trace": list(sol.trace),
        "claimed_cost": stats.get("claimed_cost", stats.get("reported_cost", sol.objective)),
        "claimed_status": stats.get("claimed_status", ""),
        "message": str(stats.get("message", "")),
        "components": stats.get("components"),
        "version": backend.version(),
    }


def _fmt(x: float | None, nd: int = 3) -> float | None:
    return None if x is None or (isinstance(x, float) and math.isnan(x)) else round(float(x), nd)


def not_applicable(model: Model, task: SolverTask) -> str | None:
    """Why the task's solver (or warm start) does not apply to its model, or None.

    Such a run is a row with status ``n/a``: not a failure of the solver, and out of the scores.
    """
    from illuknit.core.errors import SolverError
    from illuknit.solvers import get_backend
    from illuknit.solvers.warm_start import resolve_policy

    backend = get_backend(task.engine, check_available=False)
    if task.split:
        # each component is a formula of its own: no illusion model, no warm start
        if task.warm_start != "none":
            return f"a warm start does not apply to the component split ({SPLIT_SUFFIX})"
        why = backend.why_not(Model("component"))
        return None if why is None else f"on a component of the split: {why}"
    why = backend.why_not(model)
    if why is not None:
        return why
    if task.warm_start != "none" and backend.accepts_warm_start:
        try:
            resolve_policy(task.warm_start, model)
        except SolverError as e:
            return str(e)
    return None


def base_solver_row(task: SolverTask) -> dict[str, Any]:
    """The row's identifying columns, before anything runs."""
    row: dict[str, Any] = dict.fromkeys(ROW_FIELDS)
    row.update(
        instance=task.instance_name,
        model=task.model if task.wcnf is None else "wcnf",
        run=task.run,
        seed=task.seed,
        solver=task.solver,
        oracle=parse_solver_name(task.engine).oracle,
        warm_start=task.warm_start,
        time_limit=task.time_limit,
        memory_mb=task.memory_mb,
        flag="",
        reason="",
    )
    return row


def run_solver_task(task: SolverTask, content: bytes | None = None) -> dict[str, Any]:
    """Run one task; returns ``{"row": dict over ROW_FIELDS, "trace": [(seconds, cost, bound)],
    "values": the verified assignment or None}``.

    ``content``: the WCNF file's bytes, for a worker that cannot read the file (see
    :func:`build_task_model`). Never raises for a solver's misbehaviour: that is the row's status
    and reason.
    """
    row = base_solver_row(task)
    try:
        model, optimum = build_task_model(task, content)
    except (IlluknitError, OSError) as e:
        row.update(status="error", reason=f"cannot build the model: {e}")
        return {"row": row, "trace": []}
    if task.instance is not None:
        row.update(rows=task.instance.size[0], cols=task.instance.size[1])
    row.update(variables=model.pool.top, soft_clauses=model.num_soft, reference_optimum=optimum)
    with contextlib.suppress(Exception):  # an unknown or broken backend: the run says why
        row["version"] = get_backend(task.engine, check_available=False).version()
    try:
        why = not_applicable(model, task)
    except IlluknitError as e:
        why = None
        row["reason"] = str(e)
    if why is not None:
        row.update(status="n/a", reason=why)
        return {"row": row, "trace": []}
    try:
        preload_backend(task.engine)
    except ImportError as e:  # a broken optional install: the run itself will say more
        row["reason"] = f"preloading failed: {e}"
    events: list[ProgressEvent] = []
    res = run_in_child(
        lambda p: _child_solve(model, task, p),
        time_limit=task.time_limit,
        memory_mb=task.memory_mb,
        on_event=events.append,
    )
    row.update(
        peak_rss_mb=_fmt(res.peak_rss_mb, 1), wall_s=_fmt(res.wall_time), cpu_s=_fmt(res.cpu_time)
    )
    event_trace = [(e.elapsed, e.objective, e.bound) for e in events]
    if res.status != "ok":
        row.update(status=res.status, reason=res.reason)
        # the lower bounds it reported before the end are kept (checked like any bound)
        bounds = [float(b) for _, _, b in event_trace if b is not None]
        if bounds:
            bound = max(bounds)
            if optimum is not None and bound > optimum:
                row["flag"] = f"bound {bound:g} above the DP optimum {optimum}"
            else:
                row["bound"] = _fmt(bound)
        return {"row": row, "trace": event_trace}
    out = res.value
    row.update(
        version=out["version"],
        claimed_cost=out["claimed_cost"],
        claimed_status=out["claimed_status"],
        found_by=out["found_by"],
        reason=out["message"],
    )
    _verify(row, model, out, optimum)
    # the child's own trace, else what the parent received (both are re-timed from the start)
    trace = [(float(t), o, b) for t, o, b in out["trace"]] or event_trace
    _timings(row, out, trace)
    if res.late and row["status"] in (Status.OPTIMAL.value, Status.FEASIBLE.value):
        # the Evaluation's rule: an answer after the limit is a timeout, whatever it claims
        row.update(status=Status.TIMEOUT.value, time_prove=None)
        row["reason"] = "; ".join(
            filter(None, [row["reason"], f"answered after the time limit ({res.wall_time:.2f} s)"])
        )
    good = row["verified_cost"] is not None and out["values"] is not None
    return {"row": row, "trace": trace, "values": out["values"] if good else None}


def _verify(row: dict[str, Any], model: Model, out: dict[str, Any], optimum: int | None) -> None:
    """Status, verified cost, bound, gap and flags of one answer, checked on the parent's model."""
    status = out["status"]
    values = out["values"]
    flags: list[str] = []
    verified: int | None = None
    if values is not None:
        ok, verified = model.evaluate(values)
        if not ok:
            status = Status.ERROR.value
            row["reason"] = "the returned assignment violates hard clauses"
            flags.append("violates hard clauses")
            verified = None
    claimed = row["claimed_cost"]
    if verified is not None and claimed is not None and int(claimed) != verified:
        flags.append(f"claimed cost {claimed} but the assignment costs {verified}")
    bound = out["bound"]
    if status == Status.OPTIMAL.value:
        if verified is None:
            flags.append("claimed optimum without an assignment")
        elif optimum is not None and verified > optimum:
            flags.append(f"claimed optimum {verified} above the DP optimum {optimum}")
        elif optimum is not None:
            row["certificate"] = "reference (dp)"
        bound = verified if bound is None else bound
    if status == Status.INFEASIBLE.value and optimum is not None:
        flags.append(f"claimed UNSATISFIABLE but the DP found an optimum of {optimum}")
    if bound is not None and optimum is not None and bound > optimum:
        flags.append(f"bound {bound:g} above the DP optimum {optimum}")
        bound = None
    row.update(status=status, verified_cost=verified, bound=_fmt(bound))
    if verified is not None and bound is not None:
        row["gap"] = _fmt(max(0.0, verified - float(bound)) / max(1.0, float(verified)), 5)
    row["flag"] = "; ".join(flags)


def _timings(row: dict[str, Any], out: dict[str, Any], trace: list[Any]) -> None:
    """time_first, time_best (both: when an assignment backs a cost, see :func:`backed_at`)
    and time_prove of a verified answer."""
    if row["verified_cost"] is None:
        return
    at = backed_at(trace, float(row["verified_cost"]))
    row["time_first"] = row["time_best"] = _fmt(at if at is not None else out["wall"])
    if row["status"] == Status.OPTIMAL.value and not row["flag"]:
        row["time_prove"] = _fmt(out["wall"])


def backed_at(trace: list[Any], verified: float) -> float | None:
    """The first time the run reported the cost its verified assignment has (the MaxSAT
    Evaluation's reading of an ``o`` line that the final ``v`` line backs), or None. A reported
    cost no assignment backs -- lower than the verified one, or never followed by an assignment
    -- is a claim: it sets no time and scores nothing."""
    times = [float(t) for t, o, _ in trace if o is not None and float(o) == verified]
    return min(times) if times else None


def _add_flag(row: dict[str, Any], text: str) -> None:
    row["flag"] = "; ".join(filter(None, [row.get("flag", ""), text]))


def flag_rows(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Cross-row checks per (instance, model): a claimed optimum above another run's verified
    cost, a bound above one, or a claim of UNSATISFIABLE where another run verified an
    assignment, is flagged. Returns the rows (updated copies)."""
    best: dict[tuple[str, str], tuple[int, str]] = {}
    for r in rows:
        v = r.get("verified_cost")
        if v is not None and not r.get("flag"):
            key = (r["instance"], r["model"])
            if key not in best or v < best[key][0]:
                best[key] = (v, r["solver"])
    out = []
    for r in rows:
        r = dict(r)
        got = best.get((r["instance"], r["model"]))
        v = r.get("verified_cost")
        if got is not None:
            b, who = got
            if r.get("status") == "optimal" and v is not None and v > b:
                _add_flag(r, f"claimed optimum {v} but {who} verified {b}")
                r["time_prove"] = None
                r["certificate"] = "refuted (another run)"
            if r.get("bound") is not None and float(r["bound"]) > b:
                _add_flag(r, f"bound {r['bound']:g} above a verified cost {b}")
            if r.get("status") == "infeasible":
                _add_flag(r, f"claimed UNSATISFIABLE but {who} verified an assignment of cost {b}")
                r["certificate"] = "refuted (another run)"
        out.append(r)
    return out
