"""The benchmark's results format: the columns of results.csv and where they were measured.

Shared by :mod:`illuknit.bench.runner` (which writes rows) and :mod:`illuknit.bench.report`
(which turns them into tables and pictures), so neither imports the other's internals.
"""

from __future__ import annotations

import os
import platform
from typing import Any

__all__ = ["FIELDS", "FORMAT", "machine_info"]

#: The ``format`` tag of bench.json and results.json.
FORMAT = "illuknit-bench-results"

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
