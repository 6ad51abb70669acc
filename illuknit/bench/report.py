"""Benchmark outputs: CSV, JSON, a Markdown summary, contact sheets and the Pareto plot.

All are regenerated from the cell rows of a results folder (:func:`illuknit.bench.results.load_rows`)
after every run, so they always describe every finished cell. The Pareto plot needs matplotlib
(``pip install 'illuknit[plots]'``); without it the summary says so and everything else is written.
"""

from __future__ import annotations

import csv
import importlib.util
import io
import json
import math
from collections.abc import Sequence
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from illuknit import __version__
from illuknit.bench.results import FIELDS, FORMAT, machine_info
from illuknit.core.errors import IlluknitError
from illuknit.core.files import atomic_write_bytes, atomic_write_text

__all__ = [
    "contact_sheet_for",
    "format_summary",
    "pareto_points",
    "write_outputs",
]


def _fmt(v: Any, digits: int = 3) -> str:
    if v is None or v == "":
        return "–"
    if isinstance(v, float):
        if math.isnan(v):
            return "–"
        if v != 0 and abs(v) < 10 ** (-digits):
            return f"{v:.1e}"
        return f"{v:.{digits}f}"
    return str(v)


def _pct(v: Any) -> str:
    return "–" if v is None else f"{100 * float(v):.1f}%"


def _knit_reason(note: str) -> str:
    """The general part of a knit note (drops the per-pattern counts before the first ';')."""
    _, sep, tail = note.partition(";")
    return tail.strip() if sep else note


def format_summary(rows: Sequence[dict[str, Any]]) -> str:
    """Markdown: one table per instance, one line per method."""
    from illuknit.design.measures import BLUR_SIGMA, RENDER_ANGLE

    lines = [
        "# illuknit benchmark summary",
        "",
        f"illuknit {__version__}; {len(rows)} cells. *Logical error*: share of units seen in the "
        "wrong colour (boolean model) against the original inputs, views A / B. *MSE*, *SSIM*: "
        f"angled renders at {RENDER_ANGLE:g}° against the targets, both blurred by a Gaussian of "
        f"σ = {BLUR_SIGMA:g} units in linear light. *Corr*: correlation of blurred luminance "
        "(is the picture there, whatever its contrast). *Ghost* (double view): how much of the "
        "other view's picture shows through. *Head-on* (single view): how visible the picture is "
        "head-on (should be low). *Changes*: colour changes per course (mean / max). *Passes*: "
        "the carriage passes the SWG machine runs for the pattern's knitout program (the pass "
        "rows of the reference backend's .dat), *knit time* on those passes.",
        "",
    ]
    by_inst: dict[str, list[dict[str, Any]]] = {}
    for r in rows:
        by_inst.setdefault(r["instance"], []).append(r)
    for name, group in by_inst.items():
        r0 = group[0]
        double = r0["kind"] == "double"
        lines += [
            f"## {name}",
            "",
            f"{r0['kind']}-view, {r0['rows']} x {r0['cols']} units, {r0['n_yarns']} yarns, "
            f"time limit {_fmt(r0['time_limit'], 0)} s",
            "",
            "| method | status | logical err A / B | MSE A / B | SSIM A / B | corr A / B | "
            + ("ghost A / B" if double else "head-on")
            + " | changes/course | passes (xfer) | knit time | solve + compile s | peak MB |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|",
        ]
        notes: dict[str, list[str]] = {}
        kept: list[str] = []  # long floats the bench knits anyway (see metrics.knit_stats)
        for r in group:
            status = r["status"]
            if r.get("gap") not in (None, 0, 0.0) and status in ("feasible", "timeout"):
                status += f" (gap {_pct(r['gap'])})"
            if r.get("logical_error_a") is None:
                reason = str(r.get("reason", "")).replace("|", "/")
                lines.append(f"| {r['method']} | {status} | {reason} |" + " |" * 9)
                continue
            passes = "–"
            if r.get("carriage_passes") is not None:
                passes = f"{r['carriage_passes']} ({_fmt(r.get('transfer_passes'))})"
                if r.get("knit_note"):
                    kept.append(f"{r['method']}: {r['knit_note']}")
            elif r.get("knit_note"):
                notes.setdefault(_knit_reason(r["knit_note"]), []).append(r["method"])
            knit = "–" if r.get("knit_time_min") is None else f"{r['knit_time_min']:.1f} min"
            secs = sum(float(r.get(k) or 0.0) for k in ("solve_s", "compile_s"))
            third = (
                f"{_fmt(r.get('ghost_a'), 2)} / {_fmt(r.get('ghost_b'), 2)}"
                if double
                else _fmt(r.get("headon_visibility"), 2)
            )
            lines.append(
                f"| {r['method']} | {status} | {_pct(r['logical_error_a'])} / "
                f"{_pct(r['logical_error_b'])} | {_fmt(r['render_mse_a'], 4)} / "
                f"{_fmt(r['render_mse_b'], 4)} | {_fmt(r['render_ssim_a'], 2)} / "
                f"{_fmt(r['render_ssim_b'], 2)} | {_fmt(r.get('render_corr_a'), 2)} / "
                f"{_fmt(r.get('render_corr_b'), 2)} | {third} | "
                f"{_fmt(r['color_changes_mean'], 1)} / {_fmt(r['color_changes_max'], 0)} | "
                f"{passes} | {knit} | {secs:.2f} | {_fmt(r.get('peak_rss_mb'), 0)} |"
            )
        for reason, methods in notes.items():
            lines += ["", f"No knitting numbers for {', '.join(methods)}: {reason}"]
        for note in kept:
            lines += ["", f"Knit with long floats (measured anyway) -- {note}"]
        renderers = sorted({str(r.get("renderer")) for r in group if r.get("renderer")})
        if renderers and any(not x.startswith("angled") for x in renderers):
            lines += ["", "Renders: " + ", ".join(renderers)]
        lines.append("")
    return "\n".join(lines) + "\n"


def _csv_text(rows: Sequence[dict[str, Any]]) -> str:
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(FIELDS), extrasaction="ignore", lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in FIELDS})
    return buf.getvalue()


def _load_png(path: Path) -> np.ndarray | None:
    from PIL import Image

    try:
        with Image.open(path) as im:
            return np.asarray(im.convert("RGB"))
    except (OSError, ValueError):
        return None


def _scaled(img: np.ndarray, width: int = 200) -> np.ndarray:
    from illuknit.outputs.previews import upscale

    s = max(1, round(width / max(1, img.shape[1])))
    return upscale(img, s)


def contact_sheet_for(outdir: Path, rows: Sequence[dict[str, Any]]) -> np.ndarray | None:
    """Targets (top) and each method's renders of view A and B for one instance's rows."""
    from illuknit.bench.instances import instance_targets, parse_manifest
    from illuknit.outputs.previews import contact_sheet

    panels: list[tuple[str, np.ndarray]] = []
    spec = next((r["instance_spec"] for r in rows if r.get("instance_spec")), None)
    if spec is not None:
        try:
            targets = instance_targets(parse_manifest({"instance": [spec]}).instances[0])
            panels += [
                ("target A", _scaled((targets.rgb("A") * 255).round().astype(np.uint8))),
                ("target B", _scaled((targets.rgb("B") * 255).round().astype(np.uint8))),
            ]
        except IlluknitError:  # a spec this version cannot draw: show the renders only
            pass
    for r in rows:
        d = outdir / "cells" / r["instance"] / r["method"]
        a, b = _load_png(d / "render_A.png"), _load_png(d / "render_B.png")
        if a is None or b is None:
            continue
        panels += [
            (f"{r['method']} A  mse {_fmt(r.get('render_mse_a'), 3)}", _scaled(a)),
            (f"{r['method']} B  mse {_fmt(r.get('render_mse_b'), 3)}", _scaled(b)),
        ]
    if not any(t.startswith(tuple(r["method"] for r in rows)) for t, _ in panels):
        return None
    return contact_sheet(panels, columns=2)


#: Plots: y value of a row, its axis label, file name, title.
PLOTS: dict[str, tuple[str, str, str]] = {
    "render_mse": ("render MSE (blurred)", "pareto.png", "render error against knitting cost"),
    "ghost": (
        "ghosting (mean of A and B)",
        "pareto_ghost.png",
        "interference between the views against knitting cost",
    ),
}


def _y(row: dict[str, Any], metric: str) -> float | None:
    if metric == "ghost":
        g = [row.get("ghost_a"), row.get("ghost_b")]
        if any(v is None or v != v for v in g):
            return None
        return (float(g[0]) + float(g[1])) / 2  # type: ignore[arg-type]
    v = row.get(metric)
    return None if v is None else float(v)


def pareto_points(
    rows: Sequence[dict[str, Any]], metric: str = "render_mse"
) -> tuple[str, list[tuple[str, float, float]]]:
    """(x-axis label, [(method, x, y)]) for one instance's measured rows.

    y is ``metric`` ("render_mse", or "ghost": the mean ghosting of both views). x is the
    estimated knitting time when every measured row has it, else colour changes per course (a
    proxy: each change costs carriage work), and the label says which.
    """
    measured = [(r, y) for r in rows if (y := _y(r, metric)) is not None]
    if measured and all(r.get("knit_time_min") is not None for r, _ in measured):
        return "estimated knitting time (min)", [
            (str(r["method"]), float(r["knit_time_min"]), y) for r, y in measured
        ]
    return "colour changes per course (knit time unavailable)", [
        (str(r["method"]), float(r["color_changes_mean"]), y) for r, y in measured
    ]


def _pareto_png(
    groups: dict[str, list[dict[str, Any]]], metric: str = "render_mse"
) -> bytes | None:
    if importlib.util.find_spec("matplotlib") is None:  # the optional plotting extra
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = [n for n, g in groups.items() if pareto_points(g, metric)[1]]
    if not names:
        return None
    ylabel, _, title = PLOTS[metric]
    cols = min(3, len(names))
    nrows = math.ceil(len(names) / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(4.2 * cols, 3.4 * nrows), squeeze=False)
    markers = dict(
        zip(
            ["tiles", "single", "dp", "rc2", "cpsat", "knit-aware", "gradient"],
            ["o", "P", "s", "^", "v", "D", "*"],
            strict=True,
        )
    )
    for ax, name in zip(axes.flat, names, strict=False):
        label, pts = pareto_points(groups[name], metric)
        for method, x, y in pts:
            k = list(markers).index(method) if method in markers else 7
            ax.scatter([x], [y], marker=markers.get(method, "x"), s=60, color=f"C{k}")
            ax.annotate(method, (x, y), textcoords="offset points", xytext=(4, 4), fontsize=7)
        ax.set_title(name, fontsize=9)
        ax.set_xlabel(label, fontsize=8)
        ax.set_ylabel(ylabel, fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(names) :]:
        ax.axis("off")
    fig.suptitle(f"{title} (lower left is better)", fontsize=10)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    plt.close(fig)
    return buf.getvalue()


def write_outputs(outdir: str | Path, rows: Sequence[dict[str, Any]]) -> dict[str, str]:
    """Write results.csv/json, summary.md, contact sheets and pareto.png; return their paths."""
    from illuknit.outputs.previews import png_bytes

    out = Path(outdir)
    written: dict[str, str] = {}
    atomic_write_text(out / "results.csv", _csv_text(rows))
    written["csv"] = str(out / "results.csv")
    doc = {
        "format": FORMAT,
        "illuknit_version": __version__,
        "machine": machine_info(),
        "generated": datetime.now(UTC).isoformat(timespec="seconds"),
        "rows": list(rows),
    }
    atomic_write_text(out / "results.json", json.dumps(doc, indent=1, default=str) + "\n")
    written["json"] = str(out / "results.json")

    groups: dict[str, list[dict[str, Any]]] = {}
    for r in rows:
        groups.setdefault(r["instance"], []).append(r)
    summary = format_summary(rows)
    for name, group in groups.items():
        sheet = contact_sheet_for(out, group)
        if sheet is not None:
            p = out / "contact" / f"{name}.png"
            p.parent.mkdir(exist_ok=True)
            atomic_write_bytes(p, png_bytes(sheet))
            written[f"contact:{name}"] = str(p)
    for metric, (_, fname, title) in PLOTS.items():
        png = _pareto_png(groups, metric)
        if png is not None:
            atomic_write_bytes(out / fname, png)
            written["pareto" if metric == "render_mse" else f"pareto:{metric}"] = str(out / fname)
            summary += f"\n![{title}]({fname})\n"
    if "pareto" not in written:
        summary += (
            "\nPareto plot not written: install matplotlib (`pip install 'illuknit[plots]'`).\n"
        )
    atomic_write_text(out / "summary.md", summary)
    written["summary"] = str(out / "summary.md")
    return written
