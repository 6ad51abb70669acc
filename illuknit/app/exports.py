"""What the page shows and the designer takes away: angled renders, PNGs, the pattern JSON,
previews, the hand-knitting chart and written instructions.
"""

from __future__ import annotations

import io
import os
import tempfile
import zipfile
from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import NDArray

from illuknit.app.controls import blame
from illuknit.core.errors import AppRequestError
from illuknit.core.gauge import STOCKINETTE_COURSE_ASPECT, Gauge
from illuknit.core.pattern import LogicalPattern, pattern_to_json

if TYPE_CHECKING:
    from illuknit.app.inputs import Prepared

__all__ = [
    "View",
    "chart_png",
    "instructions_text",
    "pattern_json_bytes",
    "pattern_key",
    "png_bytes",
    "previews_zip",
    "render_view",
]

#: The sides a pattern is seen from: A (from above), B (from below), or head-on.
View = Literal["A", "B", "headon"]


def render_view(
    pattern: LogicalPattern,
    view: View,
    *,
    angle: float,
    unit_aspect: float = STOCKINETTE_COURSE_ASPECT,
) -> NDArray[np.uint8]:
    """(H, W, 3) uint8 picture of ``view`` ("A", "B", "headon") at elevation ``angle`` degrees.

    The angled renderer, supersampled along the wales and widened by the same factor so that it
    shows sub-unit coverage; drawn in the fabric's proportions (units ``unit_aspect`` as tall as
    wide, foreshortened by ``sin(angle)``; head-on is 90 degrees).
    """
    if not 0 < angle <= 90:
        raise AppRequestError(
            f"the viewing angle must be in (0, 90] degrees, got {angle}",
            field="angle",
            code="range",
        )
    if view not in ("A", "B", "headon"):
        raise AppRequestError(
            f"view must be A, B or headon, got {view!r}", field="view", code="range"
        )
    from illuknit.design.render import render_pattern

    ss = int(min(6, max(1, round(360 / max(pattern.shape)))))
    with blame("angle"):
        img = render_pattern(pattern, view=view, angle=angle, supersample=ss)
    from illuknit.outputs.previews import stretch_rows

    wide = np.repeat(np.asarray(img, dtype=np.uint8), ss, axis=1)
    seen = 90.0 if view == "headon" else angle
    height = round(pattern.shape[0] * ss * unit_aspect * np.sin(np.radians(seen)))
    return stretch_rows(wide, height)


def png_bytes(rgb: NDArray[np.uint8]) -> bytes:
    """Fast PNG encoding for live previews (low compression: these are tiny and short-lived)."""
    from illuknit.outputs.previews import png_bytes as encode

    return encode(rgb, compress_level=1)


def pattern_json_bytes(pattern: LogicalPattern) -> bytes:
    import json

    return (json.dumps(pattern_to_json(pattern), indent=1) + "\n").encode()


def previews_zip(
    pattern: LogicalPattern,
    prepared: Prepared | None,
    *,
    angle: float,
    unit_aspect: float = STOCKINETTE_COURSE_ASPECT,
) -> bytes:
    """A zip of the library's previews (chart, side views, contact sheet) plus angled renders,
    drawn in the fabric's proportions (units ``unit_aspect`` as tall as wide)."""
    from illuknit.outputs.previews import upscale, write_previews

    targets = {}
    if prepared is not None:
        for slot, q in prepared.quantised.items():
            targets[f"quantised {slot.upper()}"] = q.rgb()
    buf = io.BytesIO()
    with tempfile.TemporaryDirectory(prefix="illuknit-previews-") as tmp:
        paths = write_previews(pattern, tmp, targets=targets, unit_aspect=unit_aspect)
        with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as zf:
            for name, path in paths.items():
                zf.write(path, f"previews/{os.path.basename(path) or name}")
            # write_previews renders at the calibrated angle; add the angle the page shows
            for view in ("A", "B"):
                img = render_view(pattern, view, angle=angle, unit_aspect=unit_aspect)
                s = max(1, 640 // max(img.shape[:2]))
                zf.writestr(f"previews/render_{view}_{angle:g}deg.png", png_bytes(upscale(img, s)))
    return buf.getvalue()


def chart_png(pattern: LogicalPattern, *, unit_aspect: float = STOCKINETTE_COURSE_ASPECT) -> bytes:
    """The chart, its squares in the fabric's proportions (``unit_aspect`` as tall as wide)."""
    from illuknit.outputs.chart import chart_png_rgb

    return png_bytes(chart_png_rgb(pattern, unit_aspect=unit_aspect))


def instructions_text(pattern: LogicalPattern, *, gauge: Gauge) -> str:
    """Written instructions, with the finished size at ``gauge`` (the session's
    :func:`~illuknit.app.inputs.design_gauge`)."""
    from illuknit.outputs.chart import written_instructions

    return written_instructions(pattern, gauge=gauge)


def pattern_key(pattern: LogicalPattern) -> str:
    import hashlib

    h = hashlib.sha1()
    h.update(np.ascontiguousarray(pattern.yarn).tobytes())
    h.update(np.ascontiguousarray(pattern.raised).tobytes())
    h.update(repr(pattern.shape).encode())
    h.update(repr([y.rgb for y in pattern.yarns]).encode())
    return h.hexdigest()[:16]
