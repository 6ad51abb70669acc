"""Run a table of solver rows and write it: solvers.csv, traces.csv, solvers.json, solvers.md,
cactus.png and cost-over-time plots.

Rows run serially (``jobs=1``), in ``jobs`` worker processes, or on a Dask cluster; every row
isolates its own solver in a child process (:mod:`illuknit.bench.solver_runs`), so a worker
never dies with a solver. The parent writes every file (atomically).
"""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from illuknit.bench.instances import Instance
from illuknit.bench.solver_report import solver_summary, summary_markdown, write_plots
from illuknit.bench.solver_runs import (
    ROW_FIELDS,
    TRACE_FIELDS,
    SolverTask,
    flag_rows,
    run_solver_task,
)
from illuknit.core.errors import BackendUnavailableError
from illuknit.core.files import atomic_write_text

__all__ = ["SolverTable", "make_tasks", "run_solver_table"]


@dataclass(frozen=True)
class SolverTable:
    """The rows (flagged), the per-solver summary and the files written."""

    rows: list[dict[str, Any]]
    summary: list[dict[str, Any]]
    files: list[str] = field(default_factory=list)


def make_tasks(
    instances: Sequence[Instance],
    solvers: Sequence[str],
    *,
    models: Sequence[str] = ("logical",),
    warm_starts: Sequence[str] = ("none",),
    time_limit: float = 10.0,
    memory_mb: float | None = None,
    wcnf_files: Sequence[str] = (),
) -> list[SolverTask]:
    """Every (instance, model, solver, warm start) combination, then every WCNF file x solver.

    Single-view instances get the single-view model once, whatever ``models`` says.
    """
    extra: dict[str, Any] = {} if memory_mb is None else {"memory_mb": memory_mb}
    tasks = []
    for inst in instances:
        kinds = ["single"] if inst.kind == "single" else list(models)
        for kind in kinds:
            for s in solvers:
                for ws in warm_starts:
                    tasks.append(SolverTask(inst, kind, s, ws, time_limit, **extra))
    for path in wcnf_files:
        for s in solvers:
            tasks.append(SolverTask(None, "wcnf", s, "none", time_limit, wcnf=str(path), **extra))
    return tasks


def _iter_local(tasks: Sequence[SolverTask], jobs: int) -> Iterable[dict[str, Any]]:
    if jobs <= 1:
        for t in tasks:
            yield run_solver_task(t)
        return
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor, as_completed

    # workers are single-threaded processes, so forking each run's child from them is safe
    with ProcessPoolExecutor(max_workers=jobs, mp_context=mp.get_context("fork")) as ex:
        futures = [ex.submit(run_solver_task, t) for t in tasks]
        for fut in as_completed(futures):
            yield fut.result()


def _iter_dask(tasks: Sequence[SolverTask], jobs: int, address: str | None) -> Iterable[Any]:
    try:
        import dask
        from dask.distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise BackendUnavailableError(
            "--executor dask needs dask.distributed: pip install 'illuknit[dask]'"
        ) from None
    cluster = None
    # each row forks its solver: workers must be allowed children (not daemonic)
    with dask.config.set({"distributed.worker.daemon": False}):
        if address:
            client = Client(address)
        else:
            cluster = LocalCluster(n_workers=max(1, jobs), threads_per_worker=1, processes=True)
            client = Client(cluster)
        try:
            futures = [client.submit(run_solver_task, t, pure=False) for t in tasks]
            for fut in as_completed(futures):
                yield fut.result()
        finally:
            client.close()
            if cluster is not None:
                cluster.close()


def _csv(rows: Sequence[dict[str, Any]], fields: Sequence[str]) -> str:
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(fields), extrasaction="ignore", lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: "" if r.get(k) is None else r.get(k) for k in fields})
    return buf.getvalue()


def run_solver_table(
    tasks: Sequence[SolverTask],
    outdir: str | Path,
    *,
    jobs: int = 1,
    executor: str = "local",
    dask_address: str | None = None,
    on_row: Any = None,
) -> SolverTable:
    """Run ``tasks`` and write the table into ``outdir`` (see the module docstring)."""
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    stream = (
        _iter_dask(tasks, jobs, dask_address) if executor == "dask" else _iter_local(tasks, jobs)
    )
    results = []
    for res in stream:
        results.append(res)
        if on_row is not None:
            on_row(res["row"])
    order = {(t.instance_name, t.solver, t.warm_start): i for i, t in enumerate(tasks)}
    results.sort(
        key=lambda r: (
            order.get((r["row"]["instance"], r["row"]["solver"], r["row"]["warm_start"]), 0),
            r["row"]["model"],
        )
    )
    rows = flag_rows([r["row"] for r in results])
    traces: dict[tuple[str, ...], list[Any]] = {}
    trace_rows = []
    for r in results:
        row = r["row"]
        key = (row["instance"], row["model"], row["solver"], row["warm_start"])
        traces[key] = r["trace"]
        for s, c, b in r["trace"]:
            trace_rows.append(dict(zip(TRACE_FIELDS, (*key, round(s, 4), c, b), strict=True)))
    summary = solver_summary(rows, traces)
    atomic_write_text(out / "solvers.csv", _csv(rows, ROW_FIELDS))
    atomic_write_text(out / "traces.csv", _csv(trace_rows, TRACE_FIELDS))
    atomic_write_text(
        out / "solvers.json", json.dumps({"rows": rows, "summary": summary}, indent=1) + "\n"
    )
    atomic_write_text(out / "solvers.md", summary_markdown(rows, summary))
    files = ["solvers.csv", "traces.csv", "solvers.json", "solvers.md"]
    files += write_plots(rows, traces, out)
    return SolverTable(rows, summary, files)
