"""Run the benchmark: instance x method cells, resumable, serial, in processes or on Dask.

Results folder layout (everything written atomically)::

    results/
      bench.json                      illuknit version and machine that made the folder
      cells/<instance>/<method>/      one folder per finished cell
          row.json                    the cell's metrics row (written last: marks it finished)
          pattern.json                the designed pattern (when the method produced one)
          render_A.png, render_B.png  angled renders, one pixel per unit
      results.csv, results.json       every finished cell, one row each
      summary.md                      Markdown tables per instance
      contact/<instance>.png          targets and each method's renders side by side
      pareto.png                      render error against estimated knitting time (matplotlib)

A cell is *finished* when its ``row.json`` exists, its ``cell_key`` (a hash of the instance's
definition, the method and the time limit) matches, and its status is neither ``skipped`` nor
``error`` — those are retried on the next run, as the method may have been installed or fixed
meanwhile. A folder made by another illuknit version is refused unless ``force=True``, which
discards its cells.

Workers compute a cell and *return* its files; only the parent process writes, so a Dask cluster
needs no shared file system. One cell's run and measurement is :mod:`illuknit.bench.cells`; the
folder's reading and writing :mod:`illuknit.bench.results`.
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from illuknit.bench import report
from illuknit.bench.cells import Cell, base_row, execute_cell, finish_row
from illuknit.bench.instances import Instance
from illuknit.bench.methods import get_method
from illuknit.bench.results import cell_dir, load_rows, prepare_results_dir, write_cell
from illuknit.core.arguments import with_knobs
from illuknit.core.errors import (
    BackendUnavailableError,
    ExecutorError,
    OptionError,
    UnknownNameError,
)
from illuknit.core.machine import DEFAULT_MACHINE_NAME, get_machine

__all__ = ["EXECUTORS", "BenchOptions", "BenchRun", "run_bench", "sort_rows"]

EXECUTORS = ("local", "dask")
RETRY_STATUSES = ("skipped", "error")


def _finished_row(out: Path, cell: Cell) -> dict[str, Any] | None:
    """The row of ``cell`` if an earlier run finished it (same key, not to be retried)."""
    path = cell_dir(out, cell.instance.name, cell.method) / "row.json"
    try:
        row = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not isinstance(row, dict) or row.get("cell_key") != cell.key():
        return None
    if row.get("status") in RETRY_STATUSES:
        return None
    return row


# --- execution ------------------------------------------------------------------------------


@dataclass
class BenchRun:
    """What :func:`run_bench` did."""

    outdir: Path
    rows: list[dict[str, Any]] = field(default_factory=list)
    ran: list[str] = field(default_factory=list)
    reused: list[str] = field(default_factory=list)
    outputs: dict[str, str] = field(default_factory=dict)


def _iter_local(cells: Sequence[Cell], jobs: int) -> Iterable[dict[str, Any]]:
    if jobs <= 1:
        for c in cells:
            yield execute_cell(c)
        return
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor, as_completed

    # spawn: no fork of a process that runs threads (progress bar, solver pools)
    ex = ProcessPoolExecutor(max_workers=jobs, mp_context=mp.get_context("spawn"))
    futures = {ex.submit(execute_cell, c): c for c in cells}
    try:
        for fut in as_completed(futures):
            try:
                yield fut.result()
            except Exception as e:  # a worker died (out of memory, killed)
                c = futures[fut]
                row = base_row(c)
                row.update(status="error", reason=f"worker failed: {type(e).__name__}: {e}")
                yield {"row": finish_row(row), "files": {}}
    except BaseException:
        # Ctrl-C: drop queued cells at once; running ones end within their time limits.
        ex.shutdown(wait=False, cancel_futures=True)
        raise
    ex.shutdown(wait=True)


def _connect_dask(address: str | None, jobs: int) -> tuple[Any, Callable[[], None]]:
    """A Dask client (at ``address``, or on a local cluster) and the function that closes it.

    Called before the results folder is touched, so an unreachable scheduler leaves nothing behind.
    """
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise BackendUnavailableError(
            "--executor dask needs dask.distributed: pip install 'illuknit[dask]'"
        ) from None
    if address:
        try:
            client = Client(address)
        except (OSError, ValueError, TypeError) as e:
            raise ExecutorError(f"cannot reach the Dask scheduler at {address}: {e}") from None
        return client, client.close
    cluster = LocalCluster(n_workers=max(1, jobs), threads_per_worker=1, processes=True)
    client = Client(cluster)

    def close() -> None:
        client.close()
        cluster.close()

    return client, close


def _iter_dask(cells: Sequence[Cell], client: Any, close: Callable[[], None] | None):
    from dask.distributed import as_completed

    try:
        futures = [client.submit(execute_cell, c, pure=False) for c in cells]
        for fut in as_completed(futures):
            yield fut.result()
    finally:
        if close is not None:
            close()


@dataclass(frozen=True)
class BenchOptions:
    """How :func:`run_bench` runs its cells.

    Parameters
    ----------
    time_limit : float, optional
        Seconds per cell, overriding each instance's own limit.
    jobs : int
        Parallel worker processes (1: run in this process).
    executor : {"local", "dask"}
        ``dask`` sends cells to a Dask cluster: the ``dask_client`` given to :func:`run_bench`,
        or one at ``dask_address``, or a local cluster of ``jobs`` workers.
    dask_address : str, optional
        The Dask scheduler's address.
    force : bool
        Discard results of another version, and re-run every cell.
    progress : bool
        Show a progress bar (rich, on stderr).
    write_outputs : bool
        Write results.csv/json, summary.md, contact sheets and the plot at the end (also after an
        interruption, for the cells finished so far).
    machine : str, optional
        Preset name of the knitting machine patterns are knit on for the pass counts and times
        (default ``generic540``); unknown names raise before anything runs.
    """

    time_limit: float | None = None
    jobs: int = 1
    executor: str = "local"
    dask_address: str | None = None
    force: bool = False
    progress: bool = True
    write_outputs: bool = True
    machine: str | None = None

    def __post_init__(self) -> None:
        if self.executor not in EXECUTORS:
            raise UnknownNameError("executor", self.executor, EXECUTORS)
        if not isinstance(self.jobs, int) or self.jobs < 1:
            raise OptionError(f"`jobs` must be a positive integer, got {self.jobs!r}")
        if self.time_limit is not None and not self.time_limit > 0:
            raise OptionError(f"`time_limit` must be positive seconds, got {self.time_limit!r}")


def run_bench(
    instances: Sequence[Instance],
    methods: Sequence[str],
    outdir: str | Path,
    *,
    options: BenchOptions | None = None,
    dask_client: Any = None,
    on_cell: Callable[[dict[str, Any]], None] | None = None,
    **knobs: Any,
) -> BenchRun:
    """Run every instance x method cell not already finished in ``outdir``, then write outputs.

    Parameters
    ----------
    instances : sequence of Instance
    methods : sequence of str
        Method names (:data:`illuknit.bench.methods.METHODS`); unknown names raise before anything
        runs.
    outdir : path
        Results folder (see the module docstring); reused cells are not run again.
    options : BenchOptions, optional
        How to run (time limit, jobs, executor, force, progress bar, outputs, machine; defaults:
        ``BenchOptions()``).
    dask_client : distributed.Client, optional
        The Dask client of ``executor="dask"`` (else one is made, see :class:`BenchOptions`).
    on_cell : callable, optional
        Called with each finished row (after it is saved).
    **knobs
        Shorthand for fields of ``options`` (``run_bench(i, m, out, jobs=2)`` is
        ``run_bench(i, m, out, options=BenchOptions(jobs=2))``).

    Returns
    -------
    BenchRun
        ``rows`` holds every finished cell of the folder (this run's and earlier ones).
    """
    opts = with_knobs(BenchOptions, options, knobs, what="bench")
    executor, jobs, time_limit, force = opts.executor, opts.jobs, opts.time_limit, opts.force
    knit_machine = _check_options(methods, opts.machine)
    dask_address, progress, write_outputs = opts.dask_address, opts.progress, opts.write_outputs
    close = None
    if executor == "dask" and dask_client is None:
        dask_client, close = _connect_dask(dask_address, jobs)
    try:
        out = prepare_results_dir(outdir, force=force)
    except BaseException:
        if close is not None:
            close()
        raise
    if force:
        for inst in instances:
            for m in methods:
                shutil.rmtree(cell_dir(out, inst.name, m), ignore_errors=True)

    run, todo = _plan(out, instances, methods, time_limit=time_limit, knit_machine=knit_machine)
    stream = _iter_dask(todo, dask_client, close) if executor == "dask" else _iter_local(todo, jobs)

    bar = _progress_bar(len(todo)) if progress and todo else None
    try:
        for result in stream:
            row = write_cell(out, result)
            run.ran.append(f"{row['instance']}/{row['method']}")
            if bar is not None:
                bar.update(
                    bar.task_ids[0],
                    advance=1,
                    description=f"{row['instance']} {row['method']}: {row['status']}",
                )
            if on_cell is not None:
                on_cell(row)
    finally:
        if bar is not None:
            bar.stop()
        order = [i.name for i in instances]
        run.rows = sort_rows(load_rows(out), order, list(methods))
        if write_outputs:
            run.outputs = report.write_outputs(out, run.rows)
    return run


def _plan(
    out: Path,
    instances: Sequence[Instance],
    methods: Sequence[str],
    *,
    time_limit: float | None,
    knit_machine: str,
) -> tuple[BenchRun, list[Cell]]:
    """The run over the folder ``out`` with its finished cells counted as reused, and the
    cells still to run."""
    run = BenchRun(out)
    todo = []
    for inst in instances:
        for m in methods:
            limit = float(time_limit if time_limit is not None else inst.time_limit)
            c = Cell(inst, m, limit, knit_machine)
            if _finished_row(out, c) is not None:
                run.reused.append(c.id)
            else:
                todo.append(c)
    return run, todo


def _check_options(methods: Sequence[str], machine: str | None) -> str:
    """Refuse unknown methods and machines before any work (see :func:`run_bench`); the knitting
    machine's name."""
    for m in methods:
        get_method(m)  # unknown names fail before any work
    knit_machine = (machine or DEFAULT_MACHINE_NAME).strip().lower()
    get_machine(knit_machine)
    return knit_machine


def _progress_bar(total: int) -> Any:
    """A started rich progress bar on stderr with one task of ``total`` cells."""
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    bar = Progress(
        TextColumn("[bold]bench"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        TextColumn("{task.description}"),
        console=Console(stderr=True),
    )
    bar.add_task("", total=total)
    bar.start()
    return bar


def sort_rows(rows: list[dict[str, Any]], instances: Sequence[str], methods: Sequence[str]):
    """Rows ordered by the given instance and method orders (others after, by name)."""
    io = {n: k for k, n in enumerate(instances)}
    mo = {n: k for k, n in enumerate(methods)}
    return sorted(
        rows,
        key=lambda r: (
            io.get(r["instance"], len(io)),
            r["instance"],
            mo.get(r["method"], len(mo)),
            r["method"],
        ),
    )
