"""Write everything a user gets for a pattern into one folder.

``pattern.json`` (the pattern), ``headon.png`` / ``view_a.png`` / ``view_b.png`` / ``contact.png``
(previews), ``chart.png``, ``chart.svg``, ``instructions.txt`` and the print-ready
``pattern.pdf`` (hand knitting, :mod:`illuknit.outputs.pattern_pdf`), ``legend.json`` (which picture
colour became which yarn, when known) and ``report.json`` (numbers about the pattern, and what it
shows head-on, measured: :func:`illuknit.outputs.captions.headon_likeness`).
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from illuknit.core.arguments import check_instance, check_int, check_str, with_knobs
from illuknit.core.files import atomic_write_text
from illuknit.core.gauge import Gauge, finished_size
from illuknit.core.pattern import LogicalPattern, save_pattern
from illuknit.core.progress import Report
from illuknit.outputs.captions import headon_likeness
from illuknit.outputs.chart import chart_png_rgb, written_instructions
from illuknit.outputs.hand_pattern import MAX_BORDER_UNITS, with_border
from illuknit.outputs.previews import save_png, unit_scale, upscale, write_previews
from illuknit.pictures.images import QuantisedImage

__all__ = ["ExportOptions", "export_pattern", "pattern_stats"]


def pattern_stats(pattern: LogicalPattern) -> dict[str, Any]:
    """Counts a knitter cares about: size, raised units, colour changes per row, knit/purl changes."""
    n, m = pattern.shape
    changes = (np.diff(pattern.yarn, axis=1) != 0).sum(axis=1)
    texture = int((np.diff(pattern.raised.astype(np.int8), axis=0) != 0).sum())
    return {
        "rows": n,
        "cols": m,
        "stitches": 2 * m,
        "courses": 2 * n,
        "yarns": [{"name": y.name, "rgb": y.hex} for y in pattern.yarns],
        "raised_units": int(pattern.raised.sum()),
        "colour_changes_per_row": {"mean": float(changes.mean()), "max": int(changes.max())},
        "knit_purl_changes_between_rows": texture,
    }


@dataclass(frozen=True)
class ExportOptions:
    """How :func:`export_pattern` lays the knitter's documents out.

    Parameters
    ----------
    title : str, optional
        The title of the instructions and ``pattern.pdf`` (a generic one when None).
    gauge : Gauge, optional
        The finished fabric's (default: the default machine's,
        :attr:`~illuknit.core.machine.MachineSpec.fabric_gauge`); it sets the finished size
        written in the report and instructions and the proportions of the previews.
    chart : str
        What a square of ``pattern.pdf``'s chart is
        (:data:`~illuknit.outputs.pattern_pdf.CHART_KINDS`).
    border : int
        A garter border this many ridge units wide around the hand documents (``pattern.pdf``,
        ``chart.svg``, ``chart.png``, ``instructions.txt``;
        :func:`~illuknit.outputs.hand_pattern.with_border`): 4 stitches and 4 rows more a
        unit. 0 (the default): none. ``pattern.json`` and the previews stay the design's.
    """

    title: str | None = None
    gauge: Gauge | None = None
    chart: str = "units"
    border: int = 0

    def __post_init__(self) -> None:
        if self.title is not None:
            check_str(self.title, "title")
        if self.gauge is not None:
            check_instance(self.gauge, Gauge, "gauge")
        check_str(self.chart, "chart")
        check_int(self.border, "border", min=0, max=MAX_BORDER_UNITS)


def export_pattern(
    pattern: LogicalPattern,
    outdir: str | os.PathLike[str],
    *,
    quantised: Mapping[str, QuantisedImage] | None = None,
    report: Mapping[str, Any] | None = None,
    targets: Mapping[str, ArrayLike] | None = None,
    options: ExportOptions | None = None,
    progress: Report | None = None,
    **knobs: Any,
) -> dict[str, Path]:
    """Write the pattern, previews, chart, instructions, legend and report into ``outdir``.

    ``outdir`` should be a fresh folder (use :func:`illuknit.core.files.staged_dir` so a failure
    leaves nothing behind). ``options`` (:class:`ExportOptions`; its fields ``title``,
    ``gauge``, ``chart`` and ``border`` may be given as keywords instead) lays the documents out.
    ``progress(fraction, message)`` hears how far it is (:func:`illuknit.core.progress.work_bar`).
    Returns name -> path of everything written.
    """
    opts = with_knobs(ExportOptions, options, knobs, what="export")
    title, gauge, chart = opts.title, opts.gauge, opts.chart
    say: Report = progress or (lambda fraction, message: None)
    if gauge is None:
        from illuknit.core.machine import DEFAULT_MACHINE

        gauge = DEFAULT_MACHINE.fabric_gauge
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    paths: dict[str, Path] = {}
    save_pattern(pattern, out / "pattern.json")
    paths["pattern"] = out / "pattern.json"
    shown = dict(targets or {})
    # quantised pictures are on the unit grid: drawn, like every preview, in the fabric's
    # proportions (units gauge.unit_aspect as tall as wide), not one square pixel a unit
    s = max(2, unit_scale(pattern.shape))
    for name, q in (quantised or {}).items():
        picture = q.rgb()
        shown.setdefault(name, picture)  # on the grid: write_previews draws it in proportion
        key = f"quantised_{name.lower().replace(' ', '_')}"
        if picture.shape[:2] == pattern.shape:
            picture = upscale(picture, s, s * gauge.unit_aspect)
        paths[key] = save_png(picture, out / f"{key}.png")
    say(0.1, "drawing the previews")
    paths.update(write_previews(pattern, out, targets=shown, unit_aspect=gauge.unit_aspect))
    say(0.3, "drawing the chart and writing the instructions")
    hand = with_border(pattern, opts.border)  # what the hand documents knit
    paths["chart"] = save_png(chart_png_rgb(hand, unit_aspect=gauge.unit_aspect), out / "chart.png")
    paths["instructions"] = atomic_write_text(
        out / "instructions.txt", written_instructions(hand, title=title, gauge=gauge)
    )
    from illuknit.outputs.pattern_pdf import write_pattern_pdf

    say(0.4, "writing pattern.pdf")
    paths.update(
        write_pattern_pdf(
            pattern,
            out,
            gauge=gauge,
            title=title or "illuknit illusion pattern",
            chart=chart,
            border=opts.border,
        )
    )
    if quantised:
        legend = {name: q.legend() for name, q in quantised.items()}
        paths["legend"] = atomic_write_text(
            out / "legend.json", json.dumps(legend, indent=1) + "\n"
        )
    say(0.95, "measuring what head-on shows")
    full = {
        "pattern": pattern_stats(pattern),
        "finished_size": finished_size(pattern.shape, gauge).as_dict(),
        "headon": headon_likeness(pattern).as_dict(),
        **dict(report or {}),
    }
    paths["report"] = atomic_write_text(
        out / "report.json", json.dumps(full, indent=1, default=_jsonable) + "\n"
    )
    return paths


def _jsonable(o: Any) -> Any:
    if isinstance(o, np.integer):
        return int(o)
    if isinstance(o, np.floating):
        return float(o)
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, Path):
        return str(o)
    raise TypeError(f"not JSON-serialisable: {type(o).__name__}")
