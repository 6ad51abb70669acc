"""Terminal summaries shared by the commands (rich tables on stdout)."""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # annotations only: `illuknit check` uses console() without loading numpy
    from illuknit.core.pattern import LogicalPattern

__all__ = ["console", "print_written", "summarise_pattern"]


def console() -> Any:
    from rich.console import Console

    return Console(highlight=False, soft_wrap=True)


def summarise_pattern(
    pattern: LogicalPattern,
    *,
    legend_path: Path | None = None,
    report_path: Path | None = None,
) -> None:
    from rich.table import Table

    from illuknit.outputs.export import pattern_stats

    c = console()
    s = pattern_stats(pattern)
    c.print(
        f"[bold]{s['rows']} x {s['cols']} units[/] = {s['stitches']} stitches x {s['courses']} courses; "
        f"{s['raised_units']} raised units; colour changes per row: mean "
        f"{s['colour_changes_per_row']['mean']:.2f}, max {s['colour_changes_per_row']['max']}"
    )
    size = None
    if report_path is not None and Path(report_path).exists():
        size = json.loads(Path(report_path).read_text()).get("finished_size")
    if size is None:
        from illuknit.core.gauge import finished_size
        from illuknit.core.machine import DEFAULT_MACHINE

        size = finished_size(pattern.shape, DEFAULT_MACHINE.fabric_gauge).as_dict()
    c.print(
        f"finished size: [bold]{size['width_cm']} x {size['height_cm']} cm[/] "
        f"({size['width_in']} x {size['height_in']} in) at {size['gauge']} "
        f"({size['gauge_source']})"
    )
    if legend_path is not None and Path(legend_path).exists():
        legend = json.loads(Path(legend_path).read_text())
        for name, entries in legend.items():
            t = Table(title=f"legend ({name})", show_header=True, header_style="bold")
            for col in ("image colour", "yarn", "yarn colour", "share"):
                t.add_column(col)
            for e in entries:
                t.add_row(e["image_color"], e["yarn"], e["yarn_color"], f"{100 * e['share']:.1f}%")
            c.print(t)


def print_written(outdir: Path, paths: Mapping[str, Path]) -> None:
    c = console()
    names = ", ".join(sorted(p.name for p in paths.values()))
    c.print(f"wrote {len(paths)} files to [bold]{outdir}[/]: {names}")
