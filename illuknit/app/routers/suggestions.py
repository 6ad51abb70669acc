"""Suggested edits: the list for the current double-view design, before/after pictures, and
accepting (the pictures are replaced and the design is made again; the design before is kept
for undo, :mod:`~illuknit.app.routers.history`) or refusing one.

The list is made by a background job (``POST /jobs {"kind": "suggestions"}``). A suggestion
belongs to the design it was made for: once the pictures or settings change (an accepted edit
included), its id answers 410 ``superseded``, naming the current suggestion set as ``successor``
when there is one, as a replaced job answers with the job that replaced it.
"""

from typing import Any, Literal

from fastapi import APIRouter, Request
from fastapi.responses import Response

from illuknit.app import design
from illuknit.app.lookups import SessionDep, check_slot, runner_of, state_json, store_of
from illuknit.app.routers.jobs import start_candidates
from illuknit.app.sessions import Session, UploadedImage
from illuknit.app.suggestions import (
    SuggestedEdit,
    SuggestionSet,
    SupersededError,
    colour_counts,
)
from illuknit.core.errors import AppRequestError

__all__ = ["router"]

router = APIRouter(prefix="/api/sessions/{sid}/suggestions", tags=["suggestions"])


def suggestions_json(s: Session) -> dict[str, Any]:
    """The current suggestion set as the page lists it (call with ``s.lock`` held)."""
    got: SuggestionSet | None = s.suggestions
    if got is None:
        return {"set": None, "revision": s.revision, "suggestions": [], "refused": 0}
    # most helpful first; edits that make the design worse last
    order = {"better": 0, "same": 1, "mixed": 2, "worse": 3}
    edits = sorted(
        (e for e in got.edits if e.id not in s.refused),
        key=lambda e: (order[e.verdict], -e.benefit),
    )
    shown = [e.to_json() for e in edits]
    return {
        "set": got.id,
        "revision": got.revision,
        "readability": _rounded(got.before[0]),
        "ghosting": _rounded(got.before[1]),
        "suggestions": shown,
        "refused": len(got.edits) - len(shown),
    }


def _rounded(x: float) -> float | None:
    return None if x != x else round(float(x), 4)


def edit_of(s: Session, edit_id: str) -> tuple[SuggestionSet, SuggestedEdit]:
    """The suggestion ``edit_id`` of the session's current set (call with ``s.lock`` held).

    410 ``superseded`` for a suggestion of an earlier design of this session, 404
    ``no_suggestion`` for an id the session never had.
    """
    set_id, _, _ = edit_id.partition(".")
    current: SuggestionSet | None = s.suggestions
    if current is not None and set_id == current.id:
        edit = current.find(edit_id)
        if edit is not None:
            return current, edit
        ids = ", ".join(e.id for e in current.edits) or "none"
        raise AppRequestError(
            f"no suggested edit {edit_id!r} in this design; its suggestions are: {ids}",
            field="suggestions",
            code="no_suggestion",
            status=404,
        )
    if set_id in s.retired_suggestions:
        then = (
            f"the current suggestions are set {current.id!r}"
            if current is not None
            else "ask for suggestions again"
        )
        raise SupersededError(
            f"suggestion {edit_id!r} was made for an earlier design (the pictures or settings "
            f"changed since); {then}",
            successor=None if current is None else current.id,
        )
    raise AppRequestError(
        f"no suggested edit {edit_id!r} in this session; ask for suggestions first",
        field="suggestions",
        code="no_suggestion",
        status=404,
    )


@router.get("", summary="Suggested edits of the current double-view design")
def get_suggestions(s: SessionDep) -> dict[str, Any]:
    with s.lock:
        return suggestions_json(s)


@router.get(
    "/{edit_id}/{slot}/{which}.png",
    summary="A picture before or after a suggested edit, in its picture colours (PNG)",
)
def get_preview(
    s: SessionDep, edit_id: str, slot: str, which: Literal["before", "after"]
) -> Response:
    from illuknit.outputs.previews import upscale

    check_slot(slot)
    with s.lock:
        got, edit = edit_of(s, edit_id)
    if slot not in edit.changed:
        raise AppRequestError(
            f"suggestion {edit_id!r} leaves picture {slot.upper()} unchanged",
            field="suggestions",
            code="unchanged",
            status=404,
        )
    img = got.originals[slot] if which == "before" else edit.pictures[slot]
    scale = max(1, 240 // max(img.shape[:2]))
    return Response(
        design.png_bytes(upscale(img, scale)),
        media_type="image/png",
        headers={"Cache-Control": "no-store"},
    )


@router.post(
    "/{edit_id}/accept",
    summary="Accept a suggestion: its pictures replace the inputs and the candidates are found again",
)
def accept(request: Request, s: SessionDep, edit_id: str) -> dict[str, Any]:
    with s.changing():
        got, edit = edit_of(s, edit_id)
        had, colors = colour_counts(got, edit)
        settings = s.settings
        # an edit that changes the colour count (a re-quantisation) changes the setting with it,
        # else quantising the edited pictures again would undo it
        recount = colors != had and 2 <= colors <= 4
        if recount and colors > len(settings.yarns):
            raise AppRequestError(
                f"this edit gives the pictures {colors} colours but there are "
                f"{len(settings.yarns)} yarns; add a yarn first",
                field="suggestions",
                code="too_few_yarns",
                status=409,
            )
        s.remember(edit.description)  # the design as it is, for Undo
        if recount:
            s.settings = settings.model_copy(update={"n_colors": colors})
        from illuknit.app.inputs import sizing_aspect
        from illuknit.pictures.sizing import grid_picture

        # the edit is on the unit grid: kept in the proportions the grid is sized in, so that
        # sizing it again gives this grid back (not 1 / 0.7 of its rows)
        aspect = sizing_aspect(s.settings)
        for slot, rgb in edit.pictures.items():
            old = s.images[slot]
            note = f"suggested edit accepted: {edit.description}"
            picture = grid_picture(rgb, unit_aspect=aspect)
            s.images[slot] = UploadedImage(old.filename, old.sent_bytes, picture, (note,))
        s.bump()
        job = start_candidates(
            s, runner_of(request), isolate=request.app.state.config.isolate_search
        )
        s.replace_job("candidates", job)
        answer = {"accepted": edit_id, "state": state_json(s), "job": job.to_json()}
    store_of(request).trim(keep=s.id)
    return answer


@router.post("/{edit_id}/refuse", summary="Refuse a suggestion: it is no longer listed")
def refuse(s: SessionDep, edit_id: str) -> dict[str, Any]:
    with s.changing():
        edit_of(s, edit_id)
        s.refused.add(edit_id)
        return suggestions_json(s)
