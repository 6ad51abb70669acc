"""The benchmark's results: the columns of results.csv, where they were measured, and the folder.

Shared by :mod:`illuknit.bench.runner` (which writes rows) and :mod:`illuknit.bench.report`
(which turns them into tables and pictures), so neither imports the other's internals. The
folder's layout is described in :mod:`illuknit.bench.runner`.
"""

from __future__ import annotations

import json
import os
import platform
import shutil
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from illuknit import __version__
from illuknit.core.errors import ResultsVersionError
from illuknit.core.files import atomic_write_bytes, atomic_write_text

__all__ = [
    "FIELDS",
    "FORMAT",
    "META_FILE",
    "cell_dir",
    "load_rows",
    "machine_info",
    "prepare_results_dir",
    "write_cell",
]

#: The ``format`` tag of bench.json and results.json.
FORMAT = "illuknit-bench-results"

#: The file that marks a results folder and names the version that made it.
META_FILE = "bench.json"

#: Columns of results.csv, in order.
FIELDS = (
    "instance",
    "method",
    "kind",
    "rows",
    "cols",
    "n_yarns",
    "time_limit",
    "status",
    "reason",
    "objective",
    "bound",
    "gap",
    "logical_error_a",
    "logical_error_b",
    "render_mse_a",
    "render_mse_b",
    "render_ssim_a",
    "render_ssim_b",
    "render_mse",
    "render_ssim",
    "render_corr_a",
    "render_corr_b",
    "ghost_a",
    "ghost_b",
    "headon_visibility",
    "renderer",
    "color_changes_mean",
    "color_changes_max",
    "yarns_per_course_mean",
    "yarns_per_course_max",
    "carriage_passes",
    "transfer_passes",
    "scheduled_passes",
    "knit_time_min",
    "knit_note",
    "knit_machine",
    "solve_s",
    "compile_s",
    "wall_s",
    "metrics_s",
    "peak_rss_mb",
    "peak_rss_delta_mb",
    "note",
    "cell_key",
    "illuknit_version",
    "python",
    "platform",
    "machine",
    "cpus",
    "finished_at",
)


def machine_info() -> dict[str, Any]:
    """Where the numbers were measured."""
    return {
        "python": platform.python_version(),
        "platform": platform.platform(),
        "machine": platform.machine()
        + (f" {platform.processor()}" if platform.processor() else ""),
        "cpus": os.cpu_count(),
    }


# --- the results folder ---------------------------------------------------------------------


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


def cell_dir(out: Path, instance: str, method: str) -> Path:
    """The folder of one finished cell."""
    return out / "cells" / instance / method


def write_cell(out: Path, result: dict[str, Any]) -> dict[str, Any]:
    """Write a cell's files, then its row (last: it marks the cell finished); returns the row."""
    row = result["row"]
    d = cell_dir(out, row["instance"], row["method"])
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
