"""Run a table of solver rows and write it: solvers.csv, traces.csv, solvers.json, solvers.md,
cactus.png and cost-over-time plots.

Rows run serially (``jobs=1``), in ``jobs`` worker processes, or on a Dask cluster; every row
isolates its own solver in a child process (:mod:`illuknit.bench.solver_runs`), so a worker
never dies with a solver. The parent writes every file (atomically).
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
import os
import platform
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from illuknit.bench.certify import certify_rows
from illuknit.bench.instances import Instance
from illuknit.bench.pictures import PictureInstance
from illuknit.bench.solver_report import solver_summary, summary_markdown, write_plots
from illuknit.bench.solver_runs import (
    ROW_FIELDS,
    TRACE_FIELDS,
    SolverTask,
    build_task_model,
    flag_rows,
    run_solver_task,
)
from illuknit.core.arguments import with_knobs
from illuknit.core.errors import BackendUnavailableError, ExecutorError, OptionError
from illuknit.core.files import atomic_write_text

__all__ = ["SolverRuns", "SolverTable", "bench_environment", "make_tasks", "run_solver_table"]


@dataclass(frozen=True)
class SolverTable:
    """The rows (flagged), the per-solver summary and the files written."""

    rows: list[dict[str, Any]]
    summary: list[dict[str, Any]]
    files: list[str] = field(default_factory=list)
    environment: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class SolverRuns:
    """How each run of :func:`make_tasks`' table is made.

    Parameters
    ----------
    time_limit : float
        Seconds per run.
    memory_mb : float, optional
        Memory limit of each run's process (None: none).
    repeat : int
        Runs of every combination, with seeds ``seed, seed + 1, ...``.
    seed : int
        The first run's seed.
    """

    time_limit: float = 10.0
    memory_mb: float | None = None
    repeat: int = 1
    seed: int = 0

    def __post_init__(self) -> None:
        if not isinstance(self.repeat, int) or self.repeat < 1:
            raise OptionError(f"`repeat` must be a positive integer, got {self.repeat!r}")


def make_tasks(
    instances: Sequence[Instance | PictureInstance],
    solvers: Sequence[str],
    *,
    models: Sequence[str] = ("logical",),
    warm_starts: Sequence[str] = ("none",),
    wcnf_files: Sequence[str] = (),
    runs: SolverRuns | None = None,
    **knobs: Any,
) -> list[SolverTask]:
    """Every (instance, model, solver, warm start) combination, then every WCNF file x solver,
    each ``runs.repeat`` times with seeds ``runs.seed, runs.seed + 1, ...``.

    Single-view instances get the single-view model once, whatever ``models`` says. ``knobs``
    are fields of ``runs`` (:class:`SolverRuns`: ``time_limit``, ``memory_mb``, ``repeat``,
    ``seed``) as a shorthand.
    """
    chosen = with_knobs(SolverRuns, runs, knobs, name="runs", what="run")
    time_limit, memory_mb, repeat, seed = (
        chosen.time_limit,
        chosen.memory_mb,
        chosen.repeat,
        chosen.seed,
    )
    extra: dict[str, Any] = {} if memory_mb is None else {"memory_mb": memory_mb}
    tasks = []
    for k in range(repeat):
        more = {**extra, "run": k, "seed": seed + k}
        for inst in instances:
            kinds = ["single"] if inst.kind == "single" else list(models)
            for kind in kinds:
                for s in solvers:
                    for ws in warm_starts:
                        tasks.append(SolverTask(inst, kind, s, ws, time_limit, **more))
        for path in wcnf_files:
            for s in solvers:
                tasks.append(
                    SolverTask(None, "wcnf", s, "none", time_limit, wcnf=str(path), **more)
                )
    return tasks


def _run(task: SolverTask, content: bytes | None) -> dict[str, Any]:
    return run_solver_task(task, content)


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
    """Rows on a Dask cluster: the one at ``address`` (started with the ordinary ``dask
    scheduler`` / ``dask worker`` commands) or a local one of ``jobs`` workers.

    Workers need no shared file system: a WCNF file is read here, uploaded once per distinct
    content (scattered under its SHA-256) and handed to every task that uses it. Each row
    isolates its solver with ``os.fork`` (:mod:`illuknit.solvers.isolate`), which Dask's
    daemonic worker processes allow.
    """
    try:
        from dask.distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise BackendUnavailableError(
            "--executor dask needs dask.distributed: pip install 'illuknit[dask]'"
        ) from None
    cluster = None
    if address:
        try:
            client = Client(address, timeout=30)
        except (OSError, ValueError, TypeError) as e:
            raise ExecutorError(f"cannot reach the Dask scheduler at {address}: {e}") from None
    else:
        cluster = LocalCluster(n_workers=max(1, jobs), threads_per_worker=1, processes=True)
        client = Client(cluster)
    try:
        uploads: dict[str, Any] = {}
        futures = []
        for t in tasks:
            content = None
            if t.wcnf is not None:
                data = Path(t.wcnf).read_bytes()
                digest = hashlib.sha256(data).hexdigest()
                if digest not in uploads:
                    uploads[digest] = client.scatter(data, hash=False)
                content = uploads[digest]
            futures.append(client.submit(_run, t, content, pure=False))
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


def _task_models(tasks: Sequence[SolverTask]) -> Any:
    """``models(instance, model)``: the parent's own copy of a row's model (built once)."""
    by_key = {t.key[:2]: t for t in tasks}
    cache: dict[tuple[str, str], Any] = {}

    def models(instance: str, kind: str) -> Any:
        if (instance, kind) not in cache:
            cache[(instance, kind)] = build_task_model(by_key[(instance, kind)])[0]
        return cache[(instance, kind)]

    return models


def run_solver_table(
    tasks: Sequence[SolverTask],
    outdir: str | Path,
    *,
    jobs: int = 1,
    executor: str = "local",
    dask_address: str | None = None,
    on_row: Any = None,
    certify_time: float | None = None,
) -> SolverTable:
    """Run ``tasks`` and write the table into ``outdir`` (see the module docstring).

    ``certify_time``: seconds for each independent check of a claim nothing else settles
    (:mod:`illuknit.bench.certify`; default the tasks' time limit, 0 to skip the checks).
    """
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    env_start = bench_environment(tasks, certify_time=certify_time)
    stream = (
        _iter_dask(tasks, jobs, dask_address) if executor == "dask" else _iter_local(tasks, jobs)
    )
    results = []
    for res in stream:
        results.append(res)
        if on_row is not None:
            on_row(res["row"])
    order = {t.key: i for i, t in enumerate(tasks)}

    def row_key(r: dict[str, Any]) -> tuple[Any, ...]:
        row = r["row"]
        return (row["instance"], row["model"], row["solver"], row["warm_start"], row["run"])

    results.sort(key=lambda r: order.get(row_key(r), len(order)))
    rows = flag_rows([r["row"] for r in results])
    limit = max((t.time_limit for t in tasks), default=10.0)
    ctime = limit if certify_time is None else certify_time
    if ctime > 0 and tasks:
        memory = max((t.memory_mb or 0 for t in tasks), default=0) or None
        assignments = {row_key(r): r.get("values") for r in results}
        rows = certify_rows(
            rows, _task_models(tasks), time_limit=ctime, memory_mb=memory, values=assignments
        )
    traces: dict[tuple[Any, ...], list[Any]] = {}
    trace_rows = []
    for r in results:
        key = row_key(r)
        traces[key] = r["trace"]
        row = r["row"]
        for s, c, b in r["trace"]:
            backed = (
                c is not None
                and row.get("time_best") is not None
                and float(c) == float(row["verified_cost"])
                and round(s, 3) >= float(row["time_best"])
            )
            point = (*key, round(s, 4), c, b, "verified" if backed else "claim")
            trace_rows.append(dict(zip(TRACE_FIELDS, point, strict=True)))
    summary = solver_summary(rows, traces)
    env = {**env_start, "load_average_end": _load_average()}
    env["solver_versions"] = {r["solver"]: r["version"] for r in rows if r.get("version")}
    atomic_write_text(out / "solvers.csv", _csv(rows, ROW_FIELDS))
    atomic_write_text(out / "traces.csv", _csv(trace_rows, TRACE_FIELDS))
    atomic_write_text(
        out / "solvers.json",
        json.dumps({"environment": env, "rows": rows, "summary": summary}, indent=1) + "\n",
    )
    atomic_write_text(out / "solvers.md", summary_markdown(rows, summary, env))
    files = ["solvers.csv", "traces.csv", "solvers.json", "solvers.md"]
    files += write_plots(rows, traces, out)
    return SolverTable(rows, summary, files, env)


def _load_average() -> list[float] | None:
    try:
        return [round(x, 2) for x in os.getloadavg()]
    except OSError:
        return None


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.lower().startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _memory_total_mb() -> float | None:
    try:
        import psutil

        return round(psutil.virtual_memory().total / 2**20)
    except ImportError:
        return None


def cgroup_v2_usable() -> bool:
    """Whether this process could create a cgroup v2 to account a run's memory exactly."""
    root = Path("/sys/fs/cgroup")
    return (root / "cgroup.controllers").is_file() and os.access(root, os.W_OK)


def bench_environment(
    tasks: Sequence[SolverTask], *, certify_time: float | None = None
) -> dict[str, Any]:
    """The limits, the machine and the software of a table (the top of solvers.md)."""
    from importlib.metadata import PackageNotFoundError, version

    limits = sorted({t.time_limit for t in tasks})
    memories = sorted({t.memory_mb for t in tasks if t.memory_mb is not None})
    software: dict[str, str] = {"python": platform.python_version()}
    for dist in ("illuknit", "python-sat", "ortools", "hermax", "numpy", "psutil"):
        try:
            software[dist] = version(dist)
        except PackageNotFoundError:
            continue
    grace = [round(3.0 + 0.1 * t, 2) for t in limits]
    return {
        "limits": {
            "time_limit_s": limits,
            "memory_mb": memories,
            "time": "wall clock from the start of the run's process; at the limit (+ 1 s + "
            "3 %) the run is asked to stop (SIGINT to the Python child, SIGTERM to an external "
            "binary), then killed after the grace period; an answer after the limit is a "
            "timeout",
            "grace_s": grace,
            "memory": "resident memory of the run's whole process tree (external binaries "
            "included), sampled every 0.1 s, the tree killed above the limit (memout); "
            "RLIMIT_AS backstop in the child"
            + ("" if cgroup_v2_usable() else "; cgroup v2 not writable on this machine"),
            "certify_time_s": max(limits, default=0) if certify_time is None else certify_time,
            "certifier": "the Lagrangian lower bound (knit-aware models), then every "
            "component of the formula (union-find over its clauses) solved exactly by an "
            "engine other than the claimant (RC2; CP-SAT for RC2's own claims), the optima "
            "summed against the claim",
        },
        "machine": {
            "cpu": _cpu_model(),
            "cores": os.cpu_count(),
            "memory_mb": _memory_total_mb(),
            "platform": platform.platform(),
            "load_average_start": _load_average(),
        },
        "software": software,
    }
