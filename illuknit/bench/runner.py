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
needs no shared file system.
"""

from __future__ import annotations

import hashlib
import json
import shutil
import time
import traceback
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from illuknit import __version__
from illuknit.bench import report
from illuknit.bench.instances import Instance, instance_targets
from illuknit.bench.methods import MethodUnavailable, NoPattern, get_method
from illuknit.bench.results import FIELDS, FORMAT, machine_info
from illuknit.errors import (
    BackendUnavailableError,
    ExecutorError,
    OptionError,
    ResultsVersionError,
    SolverError,
)
from illuknit.knit.machine import DEFAULT_MACHINE_NAME, get_machine
from illuknit.outputs import atomic_write_bytes, atomic_write_text

__all__ = [
    "EXECUTORS",
    "FIELDS",
    "BenchRun",
    "Cell",
    "execute_cell",
    "load_rows",
    "machine_info",
    "prepare_results_dir",
    "run_bench",
]

EXECUTORS = ("local", "dask")
META_FILE = "bench.json"
RETRY_STATUSES = ("skipped", "error")


@dataclass(frozen=True)
class Cell:
    """One benchmark cell: an instance, a method name, the time limit it runs under, and the
    knitting machine (a preset of :data:`illuknit.knit.machine.MACHINES`) its pattern is knit on."""

    instance: Instance
    method: str
    time_limit: float
    knit_machine: str = DEFAULT_MACHINE_NAME

    @property
    def id(self) -> str:
        return f"{self.instance.name}/{self.method}"

    def key(self) -> str:
        text = json.dumps(
            [
                self.instance.key(),
                self.method,
                round(float(self.time_limit), 6),
                self.knit_machine,
            ],
            sort_keys=True,
        )
        return hashlib.sha256(text.encode()).hexdigest()[:16]


def _base_row(cell: Cell) -> dict[str, Any]:
    inst = cell.instance
    row: dict[str, Any] = dict.fromkeys(FIELDS)
    row.update(
        instance=inst.name,
        method=cell.method,
        kind=inst.kind,
        rows=inst.size[0],
        cols=inst.size[1],
        n_yarns=len(inst.yarns),
        time_limit=cell.time_limit,
        reason="",
        note="",
        knit_note="",
        knit_machine=cell.knit_machine,
        cell_key=cell.key(),
        instance_spec=inst.to_manifest(),
        illuknit_version=__version__,
        **machine_info(),
    )
    return row


def _finish(row: dict[str, Any]) -> dict[str, Any]:
    row["finished_at"] = datetime.now(UTC).isoformat(timespec="seconds")
    return row


def execute_cell(cell: Cell) -> dict[str, Any]:
    """Run one cell and measure it; never raises for a method's failure.

    Returns
    -------
    dict
        ``{"row": {...}, "files": {name: bytes}}`` — the metrics row (keys :data:`FIELDS`) and
        the cell's artefacts (pattern JSON, render PNGs) for the caller to write.
    """
    from illuknit.bench import metrics
    from illuknit.pattern import pattern_to_json
    from illuknit.previews import png_bytes

    row = _base_row(cell)
    files: dict[str, bytes] = {}
    try:
        method = get_method(cell.method)
    except Exception as e:  # unknown names are checked before running; this is a registry change
        row.update(status="error", reason=str(e))
        return {"row": _finish(row), "files": files}
    if cell.instance.kind not in method.kinds:
        row.update(
            status="skipped",
            reason=f"not applicable to {cell.instance.kind}-view instances",
        )
        return {"row": _finish(row), "files": files}

    t0 = time.perf_counter()
    try:
        with metrics.PeakMemory() as mem:
            instance_targets(cell.instance)  # drawing inputs is not the method's time
            t1 = time.perf_counter()
            pattern, info = method.run(cell.instance, cell.time_limit)
            wall = time.perf_counter() - t1
    except (MethodUnavailable, BackendUnavailableError) as e:
        row.update(status="skipped", reason=str(e) or type(e).__name__)
        return {"row": _finish(row), "files": files}
    except NoPattern as e:
        row.update(status=e.status, reason=str(e), wall_s=time.perf_counter() - t0)
        return {"row": _finish(row), "files": files}
    except Exception as e:
        last = traceback.extract_tb(e.__traceback__)[-1]
        where = f" ({Path(last.filename).name}:{last.lineno})"
        row.update(
            status="error",
            reason=f"{type(e).__name__}: {e}{where}",
            wall_s=time.perf_counter() - t0,
        )
        return {"row": _finish(row), "files": files}

    row.update(
        status=str(info.get("status", "ok")),
        objective=info.get("objective"),
        bound=info.get("bound"),
        gap=info.get("gap"),
        solve_s=info.get("solve_s"),
        compile_s=info.get("compile_s"),
        wall_s=wall,
        note=str(info.get("note", "") or ""),
        peak_rss_mb=round(mem.peak_mb, 1),
        peak_rss_delta_mb=round(mem.delta_mb, 1),
    )
    if row["solve_s"] is None and row["compile_s"] is None:
        row["solve_s"] = wall

    tm = time.perf_counter()
    try:
        targets = instance_targets(cell.instance)
        if pattern.shape != targets.a.shape:
            raise SolverError(
                f"method returned a {pattern.shape} pattern for a {targets.a.shape} instance"
            )
        errs = metrics.logical_errors(pattern, targets)
        renders, renderer = metrics.angled_renders(pattern)
        ta, tb = targets.rgb("A"), targets.rgb("B")
        ra = metrics.render_error(renders["A"], ta)
        rb = metrics.render_error(renders["B"], tb)
        cc = metrics.color_changes(pattern)
        row.update(metrics.picture_scores(renders, ta, tb, double=cell.instance.kind == "double"))
        row.update(
            logical_error_a=errs["A"],
            logical_error_b=errs["B"],
            render_mse_a=ra[0],
            render_mse_b=rb[0],
            render_ssim_a=ra[1],
            render_ssim_b=rb[1],
            render_mse=(ra[0] + rb[0]) / 2,
            render_ssim=(ra[1] + rb[1]) / 2,
            renderer=renderer,
            color_changes_mean=cc["changes_mean"],
            color_changes_max=cc["changes_max"],
            yarns_per_course_mean=cc["yarns_per_course_mean"],
            yarns_per_course_max=cc["yarns_per_course_max"],
        )
        row.update(metrics.knit_stats(pattern, machine=cell.knit_machine))
        files["pattern.json"] = json.dumps(pattern_to_json(pattern)).encode()
        for v in ("A", "B", "headon"):
            files[f"render_{v}.png"] = png_bytes((renders[v] * 255).round().clip(0, 255))
    except Exception as e:
        row.update(status="error", reason=f"measuring the pattern failed: {type(e).__name__}: {e}")
    row["metrics_s"] = time.perf_counter() - tm
    return {"row": _finish(row), "files": files}


# --- results folder -------------------------------------------------------------------------


def prepare_results_dir(outdir: str | Path, *, force: bool = False) -> Path:
    """Create or reopen a results folder, refusing one from another illuknit version.

    Raises
    ------
    ResultsVersionError
        The folder holds results of another version, or is a non-empty folder that is not a
        results folder (``force=True`` discards old cells / writes anyway).
    """
    out = Path(outdir)
    meta_path = out / META_FILE
    if out.exists() and not out.is_dir():
        raise ResultsVersionError(f"results folder {str(out)!r} exists and is not a folder")
    if meta_path.is_file():
        try:
            meta = json.loads(meta_path.read_text(encoding="utf-8"))
            version = meta.get("illuknit_version") if meta.get("format") == FORMAT else None
        except (OSError, ValueError, AttributeError):
            version = None
        if version != __version__:
            if not force:
                raise ResultsVersionError(
                    f"results folder {str(out)!r} holds results of illuknit {version or '(unknown)'}, "
                    f"this is {__version__}; use another folder or --force to discard them"
                )
            shutil.rmtree(out / "cells", ignore_errors=True)
    elif out.is_dir() and any(out.iterdir()) and not force:
        raise ResultsVersionError(
            f"{str(out)!r} is a non-empty folder without {META_FILE}; it does not look like a "
            "results folder (use an empty or new folder, or --force)"
        )
    out.mkdir(parents=True, exist_ok=True)
    meta = {
        "format": FORMAT,
        "illuknit_version": __version__,
        "machine": machine_info(),
        "updated": datetime.now(UTC).isoformat(timespec="seconds"),
    }
    atomic_write_text(meta_path, json.dumps(meta, indent=2) + "\n")
    return out


def _cell_dir(out: Path, instance: str, method: str) -> Path:
    return out / "cells" / instance / method


def _finished_row(out: Path, cell: Cell) -> dict[str, Any] | None:
    path = _cell_dir(out, cell.instance.name, cell.method) / "row.json"
    try:
        row = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not isinstance(row, dict) or row.get("cell_key") != cell.key():
        return None
    if row.get("status") in RETRY_STATUSES:
        return None
    return row


def _write_cell(out: Path, result: dict[str, Any]) -> dict[str, Any]:
    row = result["row"]
    d = _cell_dir(out, row["instance"], row["method"])
    d.mkdir(parents=True, exist_ok=True)
    for stale in ("pattern.json", "render_A.png", "render_B.png", "render_headon.png"):
        if stale not in result["files"]:
            (d / stale).unlink(missing_ok=True)
    for name, data in result["files"].items():
        atomic_write_bytes(d / name, data)
    atomic_write_text(d / "row.json", json.dumps(row, indent=1, default=str) + "\n")
    return row


def load_rows(outdir: str | Path) -> list[dict[str, Any]]:
    """Every cell row in a results folder (any order)."""
    rows = []
    for path in sorted(Path(outdir).glob("cells/*/*/row.json")):
        try:
            row = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
        if isinstance(row, dict) and row.get("illuknit_version") == __version__:
            rows.append(row)
    return rows


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
                row = _base_row(c)
                row.update(status="error", reason=f"worker failed: {type(e).__name__}: {e}")
                yield {"row": _finish(row), "files": {}}
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


def run_bench(
    instances: Sequence[Instance],
    methods: Sequence[str],
    outdir: str | Path,
    *,
    time_limit: float | None = None,
    jobs: int = 1,
    executor: str = "local",
    force: bool = False,
    progress: bool = True,
    dask_client: Any = None,
    dask_address: str | None = None,
    on_cell: Callable[[dict[str, Any]], None] | None = None,
    write_outputs: bool = True,
    machine: str | None = None,
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
    time_limit : float, optional
        Seconds per cell, overriding each instance's own limit.
    jobs : int
        Parallel worker processes (1: run in this process).
    executor : {"local", "dask"}
        ``dask`` sends cells to a Dask cluster: ``dask_client``, or one at ``dask_address``, or a
        local cluster of ``jobs`` workers.
    force : bool
        Discard results of another version, and re-run every cell.
    progress : bool
        Show a progress bar (rich, on stderr).
    on_cell : callable, optional
        Called with each finished row (after it is saved).
    write_outputs : bool
        Write results.csv/json, summary.md, contact sheets and the plot at the end (also after an
        interruption, for the cells finished so far).
    machine : str, optional
        Preset name of the knitting machine patterns are knit on for the pass counts and times
        (default ``generic540``); unknown names raise before anything runs.

    Returns
    -------
    BenchRun
        ``rows`` holds every finished cell of the folder (this run's and earlier ones).
    """
    if executor not in EXECUTORS:
        from illuknit.errors import UnknownNameError

        raise UnknownNameError("executor", executor, EXECUTORS)
    if not isinstance(jobs, int) or jobs < 1:
        raise OptionError(f"`jobs` must be a positive integer, got {jobs!r}")
    if time_limit is not None and not time_limit > 0:
        raise OptionError(f"`time_limit` must be positive seconds, got {time_limit!r}")
    for m in methods:
        get_method(m)  # unknown names fail before any work
    knit_machine = (machine or DEFAULT_MACHINE_NAME).strip().lower()
    get_machine(knit_machine)
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
                shutil.rmtree(_cell_dir(out, inst.name, m), ignore_errors=True)

    cells = [
        Cell(
            inst, m, float(time_limit if time_limit is not None else inst.time_limit), knit_machine
        )
        for inst in instances
        for m in methods
    ]
    run = BenchRun(out)
    todo = []
    for c in cells:
        if _finished_row(out, c) is not None:
            run.reused.append(c.id)
        else:
            todo.append(c)

    stream = _iter_dask(todo, dask_client, close) if executor == "dask" else _iter_local(todo, jobs)

    bar = None
    if progress and todo:
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
        )

        bar = Progress(
            TextColumn("[bold]bench"),
            BarColumn(),
            MofNCompleteColumn(),
            TimeElapsedColumn(),
            TextColumn("{task.description}"),
            console=Console(stderr=True),
        )
        task = bar.add_task("", total=len(todo))
        bar.start()
    try:
        for result in stream:
            row = _write_cell(out, result)
            run.ran.append(f"{row['instance']}/{row['method']}")
            if bar is not None:
                bar.update(
                    task,
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
