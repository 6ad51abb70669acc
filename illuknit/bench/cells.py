"""One benchmark cell: an instance designed by one method, then measured.

:func:`execute_cell` runs in a worker (a process, or a Dask worker) and returns the cell's metrics
row and files; only the parent writes them (:mod:`illuknit.bench.runner`). A method's failure is
a row with status ``error`` or ``skipped``, never an exception.
"""

from __future__ import annotations

import hashlib
import json
import time
import traceback
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from illuknit import __version__
from illuknit.bench.instances import Instance, instance_targets
from illuknit.bench.methods import MethodUnavailable, NoPattern, get_method
from illuknit.bench.results import FIELDS, machine_info
from illuknit.core.errors import BackendUnavailableError, SolverError
from illuknit.core.machine import DEFAULT_MACHINE_NAME
from illuknit.core.pattern import LogicalPattern

__all__ = ["Cell", "base_row", "execute_cell", "finish_row"]


@dataclass(frozen=True)
class Cell:
    """One benchmark cell: an instance, a method name, the time limit it runs under, and the
    knitting machine (a preset of :data:`illuknit.core.machine.MACHINES`) its pattern is knit on."""

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


def base_row(cell: Cell) -> dict[str, Any]:
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


def finish_row(row: dict[str, Any]) -> dict[str, Any]:
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

    row = base_row(cell)
    files: dict[str, bytes] = {}
    try:
        method = get_method(cell.method)
    except Exception as e:  # unknown names are checked before running; this is a registry change
        row.update(status="error", reason=str(e))
        return {"row": finish_row(row), "files": files}
    if cell.instance.kind not in method.kinds:
        row.update(
            status="skipped",
            reason=f"not applicable to {cell.instance.kind}-view instances",
        )
        return {"row": finish_row(row), "files": files}

    t0 = time.perf_counter()
    try:
        with metrics.PeakMemory() as mem:
            instance_targets(cell.instance)  # drawing inputs is not the method's time
            t1 = time.perf_counter()
            pattern, info = method.run(cell.instance, cell.time_limit)
            wall = time.perf_counter() - t1
    except (MethodUnavailable, BackendUnavailableError) as e:
        row.update(status="skipped", reason=str(e) or type(e).__name__)
        return {"row": finish_row(row), "files": files}
    except NoPattern as e:
        row.update(status=e.status, reason=str(e), wall_s=time.perf_counter() - t0)
        return {"row": finish_row(row), "files": files}
    except Exception as e:
        last = traceback.extract_tb(e.__traceback__)[-1]
        where = f" ({Path(last.filename).name}:{last.lineno})"
        row.update(
            status="error",
            reason=f"{type(e).__name__}: {e}{where}",
            wall_s=time.perf_counter() - t0,
        )
        return {"row": finish_row(row), "files": files}

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

    files = _measure(cell, pattern, row)
    return {"row": finish_row(row), "files": files}


def _measure(cell: Cell, pattern: LogicalPattern, row: dict[str, Any]) -> dict[str, bytes]:
    """Fill ``row`` with the pattern's metrics (status ``error`` if measuring fails); its files."""
    from illuknit.bench import metrics
    from illuknit.core.pattern import pattern_to_json
    from illuknit.design import measures
    from illuknit.outputs.previews import png_bytes

    files: dict[str, bytes] = {}
    tm = time.perf_counter()
    try:
        targets = instance_targets(cell.instance)
        if pattern.shape != targets.a.shape:
            raise SolverError(
                f"method returned a {pattern.shape} pattern for a {targets.a.shape} instance"
            )
        errs = metrics.logical_errors(pattern, targets)
        renders, renderer = measures.angled_renders(pattern)
        ta, tb = targets.rgb("A"), targets.rgb("B")
        ra = measures.render_error(renders["A"], ta)
        rb = measures.render_error(renders["B"], tb)
        cc = measures.color_changes(pattern)
        row.update(measures.picture_scores(renders, ta, tb, double=cell.instance.kind == "double"))
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
    return files
