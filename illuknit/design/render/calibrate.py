"""Calibrating the renderer from a knitted swatch (paper Fig. 8).

The swatch (:func:`calibration_swatch`) holds a grid of *cells* on a background of flat units in
the bump yarn. Cell ``(n, k)`` is ``n`` rows of raised units in the bump yarn (white in the paper),
then ``k`` rows of flat units in the other yarn (black), then ``n`` rows of bumps again, so it can
be read from either side. Seen from above at elevation ``theta``, the last bump before the flats
hides them completely once its top edge's line of sight reaches the unit after them::

      bump          k flats            next unit
     _______                                                tan(theta) = relief / (k L)
    |       |------------------------|________               relief = bump_height - flat_height
    |       |   k L along the wale     flat height
    ^ top edge at bump_height

so the *disappearance angle* of cell ``(n, k)`` is ``theta_k = atan(relief / (k L))``; in this
model it does not depend on ``n`` (the report shows the residuals per bump size so you can see
whether your yarn disagrees).

:func:`fit_bump_height` fits ``relief`` by least squares on the angles (Gauss-Newton on
``log relief``, so the fitted relief stays positive) and reports per-measurement residuals in
degrees. Measurements come from a CSV file (:func:`read_measurements`) with a header row::

    bump_rows,flat_rows,angle_deg,note
    1,1,31.5,
    1,2,17.0,left edge blurry

``flat_rows`` and ``angle_deg`` are required; ``bump_rows``, ``view`` and ``note`` optional; rows
with an empty ``angle_deg`` (cells not measured) are skipped and counted.
"""

from __future__ import annotations

import csv
import io
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from illuknit.core.arguments import check_instance, check_int, got
from illuknit.core.documents import read_text_file
from illuknit.core.errors import CalibrationError, RenderParamsError
from illuknit.core.pattern import MAX_UNITS, LogicalPattern, Yarn, check_yarns, parse_yarns
from illuknit.design.render.params import RenderParams

__all__ = [
    "CalibrationFit",
    "Measurement",
    "calibration_swatch",
    "disappearance_angle",
    "fit_bump_height",
    "measurements_template",
    "parse_measurements",
    "read_measurements",
]

REQUIRED_COLUMNS = ("flat_rows", "angle_deg")
OPTIONAL_COLUMNS = ("bump_rows", "view", "note")


def disappearance_angle(flat_rows: float, params: RenderParams) -> float:
    """Elevation (degrees) below which ``flat_rows`` flats behind a bump are fully hidden."""
    return math.degrees(math.atan2(params.relief, flat_rows * params.unit_length))


def _sizes(values: Sequence[int], name: str) -> tuple[int, ...]:
    out = tuple(values)
    if not out or any(
        isinstance(v, bool) or not isinstance(v, int | np.integer) or v < 1 for v in out
    ):
        raise CalibrationError(
            f"`{name}` must be a non-empty list of positive integers, got {values!r}"
        )
    if len(set(out)) != len(out):
        raise CalibrationError(f"`{name}` must not repeat sizes, got {values!r}")
    return tuple(int(v) for v in out)


def calibration_swatch(
    *,
    bump_sizes: Sequence[int] = (1, 2, 3),
    flat_sizes: Sequence[int] = (1, 2, 3, 4),
    cell_width: int = 6,
    gap: int = 2,
    yarns: Sequence[Yarn] | str = "white,black",
    split_rows: int = 0,
) -> LogicalPattern:
    """The calibration swatch as a pattern (see the module docstring).

    Parameters
    ----------
    bump_sizes : sequence of int
        Rows of bumps before (and after) the flats; one band of cells per size, top to bottom.
    flat_sizes : sequence of int
        Rows of flats per cell; one cell per size, left to right.
    cell_width : int
        Width of each cell in units (wales).
    gap : int
        Background units between cells and around the edge.
    yarns : two yarns or a yarn string
        The bump (and background) yarn first, the flat yarn second.
    split_rows : int
        Rows of split bumps in a band below the cells (0: none): first course in the bump yarn,
        second in the flat yarn, to measure the split share (``docs/split-bumps.md``).

    Returns
    -------
    LogicalPattern
        ``meta["cells"]`` lists every cell with its sizes and its row and column ranges
        (half-open, picture order) so measurements can be matched to cells; with
        ``split_rows``, ``meta["split_band"]`` holds the band's rows and columns.
    """
    for label, sizes in (("bump_sizes", bump_sizes), ("flat_sizes", flat_sizes)):
        if isinstance(sizes, (str, bytes)) or not isinstance(sizes, Sequence) or not sizes:
            raise CalibrationError(
                f"`{label}` must be a non-empty sequence of whole numbers, got {got(sizes)}"
            )
        for v in sizes:
            check_int(v, f"{label} entries", min=1, max=MAX_UNITS, error=CalibrationError)
    check_int(cell_width, "cell_width", min=1, max=MAX_UNITS, error=CalibrationError)
    check_int(gap, "gap", min=1, max=MAX_UNITS, error=CalibrationError)
    if not isinstance(yarns, str):
        check_yarns(yarns)
    bumps = _sizes(bump_sizes, "bump_sizes")
    flats = _sizes(flat_sizes, "flat_sizes")
    if isinstance(cell_width, bool) or not isinstance(cell_width, int) or cell_width < 1:
        raise CalibrationError(f"`cell_width` must be a positive integer, got {cell_width!r}")
    if isinstance(gap, bool) or not isinstance(gap, int) or gap < 1:
        raise CalibrationError(f"`gap` must be a positive integer, got {gap!r}")
    ys = parse_yarns(yarns) if isinstance(yarns, str) else tuple(yarns)
    if len(ys) != 2:
        raise CalibrationError(f"the swatch needs exactly two yarns (bump, flat), got {len(ys)}")
    check_int(split_rows, "split_rows", min=0, max=MAX_UNITS, error=CalibrationError)
    band_h = [2 * n + max(flats) for n in bumps]
    rows = gap + sum(h + gap for h in band_h) + (split_rows + gap if split_rows else 0)
    cols = gap + len(flats) * (cell_width + gap)
    if max(rows, cols) > MAX_UNITS:
        raise CalibrationError(
            f"the swatch would be {rows} x {cols} units, above the {MAX_UNITS}-unit limit; "
            "use fewer or smaller cells"
        )
    yarn = np.zeros((rows, cols), dtype=np.int16)
    raised = np.zeros((rows, cols), dtype=bool)
    cells = []
    r = gap
    for n, h in zip(bumps, band_h, strict=True):
        c = gap
        for k in flats:
            top = r + (h - 2 * n - k) // 2  # centre short cells in the band
            sl = slice(c, c + cell_width)
            raised[top : top + n, sl] = True
            yarn[top + n : top + n + k, sl] = 1
            raised[top + n + k : top + 2 * n + k, sl] = True
            cells.append(
                {
                    "bump_rows": n,
                    "flat_rows": k,
                    "rows": [top, top + 2 * n + k],
                    "cols": [c, c + cell_width],
                }
            )
            c += cell_width + gap
        r += h + gap
    meta: dict[str, object] = {
        "kind": "calibration-swatch",
        "bump_yarn": ys[0].name,
        "flat_yarn": ys[1].name,
        "cells": cells,
    }
    upper = None
    if split_rows:
        # Split bumps across the cells' width: first course bump yarn, second flat yarn.
        sl = slice(gap, cols - gap)
        raised[r : r + split_rows, sl] = True
        upper = yarn.copy()
        upper[r : r + split_rows, sl] = 1
        meta["split_band"] = {"rows": [r, r + split_rows], "cols": [gap, cols - gap]}
    return LogicalPattern(yarn, raised, ys, meta, upper=upper)


@dataclass(frozen=True)
class Measurement:
    """One measured disappearance angle (degrees) of ``flat_rows`` flats behind ``bump_rows`` bumps."""

    flat_rows: int
    angle_deg: float
    bump_rows: int | None = None
    view: str = ""
    note: str = ""
    line: int = 0


def measurements_template(swatch: LogicalPattern, *, params: RenderParams | None = None) -> str:
    """A CSV to fill in, one row per swatch cell; notes give the angle the current params predict."""
    params = RenderParams() if params is None else params
    cells = swatch.meta.get("cells")
    if not isinstance(cells, list | tuple) or not cells:
        raise CalibrationError("the pattern is not a calibration swatch (no `cells` in its meta)")
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["bump_rows", "flat_rows", "angle_deg", "note"])
    for cell in cells:
        pred = disappearance_angle(cell["flat_rows"], params)
        w.writerow(
            [
                cell["bump_rows"],
                cell["flat_rows"],
                "",
                f"predicted {pred:.1f} deg with current params",
            ]
        )
    return buf.getvalue()


def parse_measurements(text: str, *, source: str = "measurements") -> tuple[list[Measurement], int]:
    """Parse measurement CSV text; returns (measurements, number of rows skipped for no angle)."""
    reader = csv.DictReader(io.StringIO(text))
    header = [h.strip() for h in (reader.fieldnames or [])]
    if not header:
        raise CalibrationError(
            f"{source}: empty file; expected a header row with {', '.join(REQUIRED_COLUMNS)}"
        )
    missing = [c for c in REQUIRED_COLUMNS if c not in header]
    if missing:
        raise CalibrationError(
            f"{source}: missing column(s) {', '.join(missing)} (header: {', '.join(header)})"
        )
    unknown = [c for c in header if c not in REQUIRED_COLUMNS + OPTIONAL_COLUMNS]
    if unknown:
        valid = ", ".join(REQUIRED_COLUMNS + OPTIONAL_COLUMNS)
        raise CalibrationError(f"{source}: unknown column(s) {', '.join(unknown)}; valid: {valid}")
    out: list[Measurement] = []
    skipped = 0
    for i, raw in enumerate(reader, start=2):
        row = {
            (k or "").strip(): (v or "").strip() if isinstance(v, str) else ""
            for k, v in raw.items()
        }
        if not any(row.values()):
            continue
        where = f"{source} line {i}"
        if not row.get("angle_deg"):
            skipped += 1
            continue
        flat = _int(row.get("flat_rows", ""), f"{where}: `flat_rows`")
        bump = _int(row["bump_rows"], f"{where}: `bump_rows`") if row.get("bump_rows") else None
        try:
            angle = float(row["angle_deg"])
        except ValueError:
            raise CalibrationError(
                f"{where}: `angle_deg` must be a number, got {row['angle_deg']!r}"
            ) from None
        if not math.isfinite(angle) or not 0 < angle < 90:
            raise CalibrationError(
                f"{where}: `angle_deg` must lie in (0, 90) degrees, got {row['angle_deg']}"
            )
        out.append(Measurement(flat, angle, bump, row.get("view", ""), row.get("note", ""), i))
    return out, skipped


def _int(text: str, what: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise CalibrationError(f"{what} must be a positive integer, got {text!r}") from None
    if v < 1:
        raise CalibrationError(f"{what} must be a positive integer, got {text!r}")
    return v


def read_measurements(path: str | os.PathLike[str]) -> tuple[list[Measurement], int]:
    """Read a measurements CSV file (see the module docstring)."""
    p = Path(path)
    # Spreadsheets often save CSV with a byte-order mark.
    text = read_text_file(p, error=CalibrationError, what="measurements").removeprefix("\ufeff")
    return parse_measurements(text, source=str(p))


@dataclass(frozen=True, eq=False)
class CalibrationFit:
    """A fitted bump height with its residuals.

    Attributes
    ----------
    params : RenderParams
        The base parameters with the fitted ``bump_height``.
    relief : float
        Fitted ``bump_height - flat_height``.
    relief_stderr : float
        Standard error of ``relief`` (from the residuals; 0 when they vanish).
    predicted_deg, residual_deg : ndarray of shape (n,)
        Model angle of each measurement and ``measured - predicted``.
    rms_deg : float
        Root-mean-square residual in degrees.
    """

    params: RenderParams
    relief: float
    relief_stderr: float
    measurements: tuple[Measurement, ...]
    predicted_deg: NDArray[np.float64]
    residual_deg: NDArray[np.float64]
    rms_deg: float
    skipped: int = 0

    def report(self) -> str:
        """A plain-text residual report."""
        p = self.params
        lines = [
            f"fitted bump height {p.bump_height:.4g} (relief {self.relief:.4g} ± {self.relief_stderr:.2g} "
            f"over flat height {p.flat_height:.4g}, unit length {p.unit_length:.4g})",
            f"{len(self.measurements)} measurements, rms residual {self.rms_deg:.2f} deg"
            + (f", {self.skipped} row(s) without an angle skipped" if self.skipped else ""),
            f"can_see holds exactly at {p.exact_angle:.1f} deg",
            "",
            "line  bump_rows  flat_rows  measured  predicted  residual",
        ]
        for m, pr, r in zip(self.measurements, self.predicted_deg, self.residual_deg, strict=True):
            b = "-" if m.bump_rows is None else str(m.bump_rows)
            lines.append(
                f"{m.line:>4}  {b:>9}  {m.flat_rows:>9}  {m.angle_deg:>8.2f}  {pr:>9.2f}  {r:>+8.2f}"
            )
        sizes = sorted({m.bump_rows for m in self.measurements if m.bump_rows is not None})
        if len(sizes) > 1:
            lines.append("")
            for s in sizes:
                sel = [
                    r
                    for m, r in zip(self.measurements, self.residual_deg, strict=True)
                    if m.bump_rows == s
                ]
                lines.append(
                    f"bump_rows {s}: mean residual {np.mean(sel):+.2f} deg over {len(sel)}"
                )
        return "\n".join(lines)

    def summary(self) -> dict[str, Any]:
        """JSON-ready summary."""
        return {
            "bump_height": self.params.bump_height,
            "relief": self.relief,
            "relief_stderr": self.relief_stderr,
            "rms_deg": self.rms_deg,
            "measurements": len(self.measurements),
            "skipped": self.skipped,
        }


def fit_bump_height(
    measurements: Sequence[Measurement],
    *,
    params: RenderParams | None = None,
    skipped: int = 0,
) -> CalibrationFit:
    """Least-squares bump height from measured disappearance angles.

    Minimises ``sum_i (angle_i - atan(relief / (k_i L)))^2`` over ``relief > 0`` with ``flat_height``
    and ``unit_length`` taken from ``params``.

    Raises
    ------
    CalibrationError
        Fewer than two measurements, or all angles equal (they cannot determine a height: the
        angle must fall as the flat runs get longer).
    """
    if (
        isinstance(measurements, (str, bytes))
        or not isinstance(measurements, Sequence)
        or not all(isinstance(m, Measurement) for m in measurements)
    ):
        raise CalibrationError(
            f"`measurements` must be a sequence of Measurement (see read_measurements), got {got(measurements)}"
        )
    if params is not None:
        check_instance(params, RenderParams, "params", error=RenderParamsError)
    check_int(skipped, "skipped", min=0, max=1_000_000)  # rows of a measurement file
    params = RenderParams() if params is None else params
    ms = tuple(measurements)
    if len(ms) < 2:
        raise CalibrationError(
            f"need at least two measurements to fit a bump height, got {len(ms)}"
            + (f" ({skipped} row(s) had no angle)" if skipped else "")
        )
    ang = np.radians([m.angle_deg for m in ms])
    if np.ptp(ang) == 0:
        raise CalibrationError(
            f"all {len(ms)} measured angles are equal ({ms[0].angle_deg} deg): they cannot determine a "
            "bump height; measure cells with different numbers of flat rows"
        )
    kl = np.array([m.flat_rows for m in ms], dtype=np.float64) * params.unit_length
    # Start from the median of the per-measurement heights, then Gauss-Newton on log(relief).
    log_r = math.log(float(np.median(kl * np.tan(ang))))
    for _ in range(100):
        r = math.exp(log_r)
        res = ang - np.arctan(r / kl)
        jac = -(kl * r) / (kl * kl + r * r)  # d(residual)/d(log relief)
        step = float(jac @ res) / float(jac @ jac)
        log_r -= step
        if abs(step) < 1e-12:
            break
    relief = math.exp(log_r)
    pred = np.arctan(relief / kl)
    res = ang - pred
    jac = -(kl * relief) / (kl * kl + relief * relief)
    dof = max(1, len(ms) - 1)
    var_log = float(res @ res) / dof / float(jac @ jac)
    fitted = replace(params, bump_height=params.flat_height + relief)
    return CalibrationFit(
        params=fitted,
        relief=relief,
        relief_stderr=relief * math.sqrt(var_log),
        measurements=ms,
        predicted_deg=np.degrees(pred),
        residual_deg=np.degrees(res),
        rms_deg=float(np.degrees(np.sqrt(np.mean(res * res)))),
        skipped=skipped,
    )
