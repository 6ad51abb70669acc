"""Downloads: the picked pattern and everything made from it, and the knitout's summary."""

import json
from typing import Any

from fastapi import APIRouter, Query
from fastapi.responses import Response

from illuknit.app import design
from illuknit.app.knitting import CheckedKnitout, machine_file
from illuknit.app.lookups import SessionDep, current_pattern
from illuknit.app.sessions import Session
from illuknit.core.errors import AppRequestError
from illuknit.core.machine import get_machine
from illuknit.core.pattern import LogicalPattern

__all__ = ["DOWNLOADS", "router"]

router = APIRouter(prefix="/api/sessions/{sid}", tags=["downloads"])

DOWNLOADS = (
    "pattern.json",
    "previews.zip",
    "chart.png",
    "instructions.txt",
    "pattern.pdf",
    "chart.svg",
    "knitout.k",
    "check.json",
    "check.txt",
    "pattern.dat",
    "pattern.kc",
)


def attachment(data: bytes, filename: str, media_type: str) -> Response:
    return Response(
        data,
        media_type=media_type,
        headers={
            "Content-Disposition": f'attachment; filename="{filename}"',
            "Cache-Control": "no-store",
        },
    )


def knit_of(s: Session, pattern: LogicalPattern) -> CheckedKnitout:
    """The session's knitout if it was made from ``pattern`` (409 ``not_ready`` otherwise)."""
    with s.lock:
        knit = s.knit
    if knit is None or knit.key != design.pattern_key(pattern):
        raise AppRequestError(
            "make the knitout first (the picked pattern changed since)",
            field="knit",
            code="not_ready",
            status=409,
        )
    result: CheckedKnitout = knit
    return result


@router.get(
    "/download/{name}",
    summary="Download the picked pattern, previews, chart, instructions, knitout, check report",
)
def download(
    s: SessionDep,
    name: str,
    angle: float = Query(30.0, gt=0, le=90, title="Viewing angle"),
) -> Response:
    if name not in DOWNLOADS:
        raise AppRequestError(
            f"unknown download {name!r}; valid: {', '.join(DOWNLOADS)}",
            field="downloads",
            code="unknown",
            status=404,
        )
    from illuknit.app.inputs import design_gauge

    pattern = current_pattern(s)
    with s.lock:  # the gauge the design is drawn for: the machine's, or made for hands the hand's
        gauge = design_gauge(s.settings)
    stem = f"illuknit-{pattern.shape[0]}x{pattern.shape[1]}"
    if name == "pattern.json":
        return attachment(design.pattern_json_bytes(pattern), f"{stem}.json", "application/json")
    if name == "previews.zip":
        with s.lock:
            prepared = s.prepared
        return attachment(
            design.previews_zip(pattern, prepared, angle=angle, unit_aspect=gauge.unit_aspect),
            f"{stem}-previews.zip",
            "application/zip",
        )
    if name == "chart.png":
        chart = design.chart_png(pattern, unit_aspect=gauge.unit_aspect)
        return attachment(chart, f"{stem}-chart.png", "image/png")
    if name == "instructions.txt":
        return attachment(
            design.instructions_text(pattern, gauge=gauge).encode(),
            f"{stem}-instructions.txt",
            "text/plain; charset=utf-8",
        )
    if name in ("pattern.pdf", "chart.svg"):
        from illuknit.outputs.pattern_pdf import chart_svg, pattern_pdf

        if name == "chart.svg":
            return attachment(chart_svg(pattern).encode(), f"{stem}-chart.svg", "image/svg+xml")
        pdf = pattern_pdf(pattern, gauge=gauge, title="illuknit illusion pattern", angle=angle)
        return attachment(pdf, f"{stem}-pattern.pdf", "application/pdf")
    knit = knit_of(s, pattern)
    if name == "knitout.k":
        return attachment(knit.knitout.encode(), f"{stem}.k", "text/plain; charset=utf-8")
    if name in ("pattern.dat", "pattern.kc"):
        fmt = name.rsplit(".", 1)[1]
        filename = f"{stem}.{fmt}"
        return attachment(
            machine_file(knit, fmt, name=filename), filename, "application/octet-stream"
        )
    if name == "check.json":
        return attachment(
            json.dumps(knit.report, indent=1).encode(), f"{stem}-check.json", "application/json"
        )
    return attachment(knit.report_text.encode(), f"{stem}-check.txt", "text/plain; charset=utf-8")


@router.get(
    "/knit",
    summary="Knitout statistics, check summary, carrier-to-yarn table, needle range, machine files",
)
def get_knit(s: SessionDep) -> dict[str, Any]:
    pattern = current_pattern(s)
    with s.lock:
        knit = s.knit
    if knit is None or knit.key != design.pattern_key(pattern):
        return {"ready": False}
    return {
        "ready": True,
        "machine": knit.machine,
        "stats": knit.stats,
        "report": knit.report,
        "lines": knit.knitout.count("\n"),
        "carriers": list(knit.carriers),
        "needle_range": list(knit.needle_range),
        "formats": list(get_machine(knit.machine).formats),
    }
