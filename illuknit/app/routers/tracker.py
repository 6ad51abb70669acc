"""The row tracker: the knitter at the needles follows the picked pattern row by row.

``GET /tracker`` answers the chart (every row's yarns and purl bumps, row 1 at the bottom as
knitted) and the written rows of the picked pattern (tile edits included), with the row the
knitter is on; ``PUT /tracker`` moves it. The row is kept per pattern (by its key) on the
session, so it is stored with the session and survives a reload or a restart of the app, and
coming back to a pattern finds its row again.
"""

from typing import Any

from fastapi import APIRouter
from pydantic import BaseModel, ConfigDict, Field

from illuknit.app import design
from illuknit.app.lookups import SessionDep, current_pattern
from illuknit.app.sessions import Session
from illuknit.core.errors import AppRequestError
from illuknit.core.pattern import LogicalPattern

__all__ = ["TRACKED_PATTERNS", "router"]

router = APIRouter(prefix="/api/sessions/{sid}", tags=["tracker"])

#: Patterns whose row a session remembers (the least recently moved are forgotten first).
TRACKED_PATTERNS = 32


class TrackerIn(BaseModel):
    """Body of ``PUT /tracker``."""

    model_config = ConfigDict(extra="forbid")

    row: int = Field(..., ge=1, title="Row", description="the row being knitted (1 = cast-on edge)")
    key: str = Field(
        ...,
        min_length=1,
        max_length=64,
        title="Pattern",
        description="the pattern's key from GET /tracker (refused when the pick changed since)",
    )


def _row_of(s: Session, key: str, rows: int) -> int:
    return min(max(1, int(s.tracker.get(key, 1))), rows)


def tracker_json(pattern: LogicalPattern, row: int) -> dict[str, Any]:
    """The chart and written rows of ``pattern``, and the current ``row``."""
    from illuknit.outputs.chart import hand_rows
    from illuknit.outputs.hand_pattern import written_row

    rows = hand_rows(pattern)
    names = [y.name for y in pattern.yarns]
    return {
        "key": design.pattern_key(pattern),
        "row": row,
        "rows": len(rows),
        "stitches": int(rows[0].yarn.shape[0]),
        "yarns": [{"name": y.name, "hex": y.hex} for y in pattern.yarns],
        # as seen on the right side, left to right; row 1 (the cast-on edge) first
        "chart": [r.yarn.astype(int).tolist() for r in rows],
        "purl": [r.purl_on_rs.astype(int).tolist() for r in rows],
        "written": [
            {"number": r.number, "side": r.side, "text": written_row(r.worked(), names)}
            for r in rows
        ],
    }


@router.get("/tracker", summary="The row tracker: chart, written rows and the current row")
def get_tracker(s: SessionDep) -> dict[str, Any]:
    pattern = current_pattern(s)
    key = design.pattern_key(pattern)
    with s.lock:
        row = _row_of(s, key, 2 * pattern.shape[0])
    return tracker_json(pattern, row)


@router.put("/tracker", summary="Move the row tracker to a row")
def put_tracker(s: SessionDep, body: TrackerIn) -> dict[str, Any]:
    pattern = current_pattern(s)
    key = design.pattern_key(pattern)
    rows = 2 * pattern.shape[0]
    if body.key != key:
        raise AppRequestError(
            "the picked pattern changed: reload the tracker",
            field="tracker",
            code="stale",
            status=409,
        )
    if body.row > rows:
        raise AppRequestError(
            f"row must be 1..{rows}, got {body.row}", field="tracker", code="range"
        )
    with s.changing():
        s.tracker.pop(key, None)  # the most recently moved last
        s.tracker[key] = body.row
        while len(s.tracker) > TRACKED_PATTERNS:
            s.tracker.pop(next(iter(s.tracker)))
    return {"key": key, "row": body.row, "rows": rows}
