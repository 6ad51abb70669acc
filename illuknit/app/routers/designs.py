"""Designs: the ranked candidates, the designer's pick, per-pair tile edits and renders."""

from typing import Annotated, Any, Literal

import numpy as np
from fastapi import APIRouter, Query
from fastapi.responses import Response

from illuknit.app import design
from illuknit.app.lookups import (
    SessionDep,
    candidate_of,
    current_pattern,
    prepared_of,
    state_json,
)
from illuknit.app.measures import Order, measure_candidate, order_candidates
from illuknit.app.schemas import OverrideIn, SelectionIn
from illuknit.core.errors import AppRequestError

__all__ = ["router"]

router = APIRouter(prefix="/api/sessions/{sid}", tags=["design"])


@router.get("/candidates", summary="Ranked candidates, in the order asked for")
def get_candidates(
    s: SessionDep,
    order: Annotated[
        Order,
        Query(
            title="Order",
            description="the search's rank, or (once measured) the perceptual score, the most "
            "sides the reader reads, the worse view's correlation or contrast, least ghosting, "
            "fastest to knit on the machine, or quickest to knit by hand (estimated hours)",
        ),
    ] = "rank",
) -> dict[str, Any]:
    with s.lock:
        return {
            "revision": s.candidates_revision,
            "selected": s.selected if s.candidates else None,
            "order": order,
            "measured": bool(s.candidates) and all(c.measured for c in s.candidates),
            "measured_at": measured_at(s.settings),
            "made_for": s.settings.made_for,
            "candidates": [
                c.to_json()
                for c in order_candidates(s.candidates, order, hands=s.settings.made_for == "hands")
            ],
        }


@router.put("/selection", summary="Pick a candidate")
def put_selection(s: SessionDep, body: SelectionIn) -> dict[str, Any]:
    with s.changing():
        candidate_of(s, body.candidate)
        if body.candidate != s.selected:
            s.selected = body.candidate
            s.overrides = {}
            s.knit = None
        return state_json(s)


def measured_at(settings: Any) -> dict[str, float]:
    """Where the measures look from (the session's settings; a new viewpoint drops the
    measures taken from the old one, so every measure shown was taken from here)."""
    return {"angle": settings.view_angle, "distance": settings.view_distance}


@router.get(
    "/pairs",
    summary="Overlap pairs of the picked candidate, their tiles and the bank's alternatives",
)
def get_pairs(s: SessionDep) -> dict[str, Any]:
    with s.lock:
        return _pairs_measured(s, candidate_of(s, None))


def _pairs_measured(s: Any, cand: Any) -> dict[str, Any]:
    """The pairs, and how the picked design reads with the tile edits (``edited``: None when
    there are none; ``measures`` the candidate's own, when measured)."""
    answer = design.pairs_json(cand, s.overrides)
    answer["measures"] = None if cand.measured is None else cand.measured.to_json()
    answer["edited"] = None
    answer["measured_at"] = measured_at(s.settings)
    if s.overrides and s.prepared is not None:
        pattern = design.pattern_for(cand, s.overrides)
        m = measure_candidate(
            pattern,
            s.prepared,
            machine=s.settings.machine,
            knit_time=False,
            viewpoint=s.settings.viewpoint,
        )
        answer["edited"] = m.to_json()
    return answer


@router.put(
    "/pairs/{a}/{b}",
    summary="Use another tile for the overlap pair (a, b) of the picked candidate",
)
def put_pair(s: SessionDep, a: int, b: int, body: OverrideIn) -> dict[str, Any]:
    with s.changing():
        cand = candidate_of(s, None)
        overrides = dict(s.overrides)
        if body.tile is None:
            overrides.pop((a, b), None)
        else:
            overrides[(a, b)] = body.tile
        design.pattern_for(cand, overrides)  # validates before keeping it
        if overrides != s.overrides:
            tile = "its default tile" if body.tile is None else f"tile {body.tile}"
            s.remember(f"tile edit: A colour {a} over B colour {b} to {tile}")
            s.redo_steps.clear()  # a new edit: what was undone cannot be redone
        s.overrides = overrides
        s.knit = None
        return _pairs_measured(s, cand)


@router.get("/tiles/{tile_id}.png", summary="Picture of a bank tile")
def get_tile_png(s: SessionDep, tile_id: str) -> Response:
    with s.lock:
        cand = candidate_of(s, None)
    return Response(design.tile_png(tile_id, cand), media_type="image/png")


@router.get("/tile.png", summary="Picture of any tile: a bank number or rows such as 0/1^")
def get_any_tile_png(
    s: SessionDep,
    tile: str = Query(..., title="Tile", description="bank tile number, or rows like 0/1^"),
) -> Response:
    return get_tile_png(s, tile)


@router.get("/render", summary="Render a candidate from one side or head-on at an angle (PNG)")
def render(
    s: SessionDep,
    view: Literal["A", "B", "headon"] = Query(
        "A", title="View", description="side A (above), side B (below) or head-on"
    ),
    angle: float = Query(
        30.0, gt=0, le=90, title="Viewing angle", description="elevation of the eye in degrees"
    ),
    candidate: int | None = Query(
        None, ge=1, title="Candidate", description="rank; default: the picked one"
    ),
    distance: float | None = Query(
        None,
        gt=0,
        le=1000,
        title="Viewing distance",
        description="metres: the render as a 20/20 eye resolves it from there (the fabric "
        "at the chosen machine's gauge); default: every detail",
    ),
) -> Response:
    from illuknit.app.inputs import design_gauge
    from illuknit.core.machine import get_machine

    pattern = current_pattern(s, candidate)
    aspect = design_gauge(s.settings).unit_aspect
    img = design.render_view(pattern, view, angle=angle, unit_aspect=aspect)
    if distance is not None:
        from illuknit.design.tiles.perception import eye_blur_units, seen_from

        gauge = get_machine(s.settings.machine).gauge
        per_unit = img.shape[1] / pattern.shape[1]  # pixels per unit across
        img = seen_from(img, eye_blur_units(distance, gauge=gauge) * per_unit)
    return Response(
        design.png_bytes(img), media_type="image/png", headers={"Cache-Control": "no-store"}
    )


@router.get(
    "/diagnostic.png",
    summary="Where a view fails: wrong shade in red, the other picture showing through in blue",
)
def diagnostic(
    s: SessionDep,
    view: Literal["A", "B", "headon"] = Query(
        "A", title="View", description="side A, side B, or head-on (head-on designs)"
    ),
    angle: float = Query(30.0, gt=0, le=90, title="Viewing angle"),
    candidate: int | None = Query(None, ge=1, title="Candidate"),
) -> Response:
    from illuknit.design.tiles.perception import diagnostic_rgb
    from illuknit.outputs.previews import upscale

    pattern = current_pattern(s, candidate)
    picture, other = diagnosed_pictures(prepared_of(s), view)
    img, _ = diagnostic_rgb(pattern, picture, other, view=view, angle=angle)
    scale = max(1, 480 // max(img.shape[:2]))
    return Response(
        design.png_bytes(upscale(img, scale)),
        media_type="image/png",
        headers={"Cache-Control": "no-store"},
    )


def diagnosed_pictures(prepared: design.Prepared, view: str) -> tuple[Any, Any]:
    """(what ``view`` should show, what must not show through it) in the prepared mode.

    Double view: each side its picture, the other picture must not ghost. Single view: both
    sides picture A. Head-on: head-on shows the front picture (A) and not the side picture;
    at an angle the sides show the side picture (B), or a plain field without one, and the
    front picture must have gone.
    """
    q = prepared.quantised
    if prepared.mode == "headon":
        front = q["a"].rgb()
        side = q["b"].rgb() if "b" in q else np.full_like(front, 128)
        return (front, q["b"].rgb() if "b" in q else None) if view == "headon" else (side, front)
    if view == "headon":
        raise AppRequestError(
            "head-on, a single or double view shows a plain stripe: diagnose side A or B",
            field="view",
            code="not_available",
            status=409,
        )
    if prepared.mode == "single":
        return q["a"].rgb(), None
    own, other = ("a", "b") if view == "A" else ("b", "a")
    return q[own].rgb(), q[other].rgb()


@router.get(
    "/widths",
    summary="The smallest width at which both sides read (the widths job's answer), per width "
    "tried",
)
def get_widths(s: SessionDep) -> dict[str, Any]:
    from illuknit.app.reading import widths_key
    from illuknit.design.legibility import reader_available

    with s.lock:
        got = s.legible_widths
        current = got is not None and got.key == widths_key(s.images, s.settings)
        return {
            # False without tesseract: the page says so instead of offering the search
            "reader": reader_available(),
            # the answer, and whether it holds for the pictures and settings as they are now
            # (a change of width keeps it: the width is what it answers)
            "result": None if got is None else got.to_json(),
            "current": current,
        }
