"""What every router looks up in a session: the session itself, its state as JSON, its prepared
inputs, its candidates and the pattern the designer picked.

The routers (:mod:`illuknit.app.routers`) stay thin: they parse the request, call these and the
design pipeline (:mod:`illuknit.app.design`), and answer.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Annotated, Any

from fastapi import Depends, Request

from illuknit.app import design
from illuknit.app.jobs import JobRunner
from illuknit.app.sessions import Session, SessionStore
from illuknit.core.errors import AppRequestError
from illuknit.core.pattern import LogicalPattern

__all__ = [
    "SessionDep",
    "candidate_of",
    "check_slot",
    "current_pattern",
    "prepared_of",
    "runner_of",
    "session_of",
    "state_json",
    "store_of",
]


def store_of(request: Request) -> SessionStore:
    store: SessionStore = request.app.state.store
    return store


def runner_of(request: Request) -> JobRunner:
    runner: JobRunner = request.app.state.runner
    return runner


def session_of(request: Request, sid: str) -> Iterator[Session]:
    """The session named in the path (404 ``no_session`` when unknown, 410 ``evicted`` when
    deleted), read back from disk when it is not in memory, and kept in memory while the
    request works on it.

    A route that changes the session does so inside ``with s.changing():``
    (:meth:`~illuknit.app.sessions.Session.changing`): the change is stored whole (one
    transaction) before the answer is sent, and kept in memory only once stored, so every
    change a page saw answered survives a restart and a change answered as failed (a full
    disk) is not kept. (Work finishing in the background stores it again:
    ``Session.replace_job``.)"""
    store = store_of(request)
    with store.using(sid) as session:
        yield session


#: A route parameter that is the session of the path's ``{sid}`` (kept in memory while the route
#: runs: the dependency's scope is the route function, not the whole request).
SessionDep = Annotated[Session, Depends(session_of, scope="function")]


def image_json(s: Session, slot: str) -> dict[str, Any]:
    im = s.images[slot]
    w, h = im.size
    return {
        "slot": slot,
        "filename": im.filename,
        "width": w,
        "height": h,
        "bytes": im.sent_bytes,
        "notes": list(im.notes),
        "url": f"/api/sessions/{s.id}/images/{slot}?r={s.revision}",
    }


def state_json(s: Session) -> dict[str, Any]:
    """The session as the page sees it (call with ``s.lock`` held)."""
    return {
        "id": s.id,
        "revision": s.revision,
        "settings": s.settings.to_json(),
        # the piece's width in units now (sized from the picture by default), None when the
        # settings cannot give one (the page shows why next to the control)
        "width_units": _width_now(s),
        "images": {slot: image_json(s, slot) for slot in s.images},
        "candidates": len(s.candidates),
        "selected": s.selected if s.candidates else None,
        "overrides": [{"a": a, "b": b, "tile": t} for (a, b), t in s.overrides.items()],
        "knit_ready": s.knit is not None,
        "jobs": {k: j.to_json() for k, j in s.jobs.items()},
        # what Undo and Redo would do, newest first (the accepted edits' descriptions)
        "history": {
            "undo": [step.label for step in reversed(s.undo_steps)],
            "redo": [step.label for step in reversed(s.redo_steps)],
        },
    }


def _width_now(s: Session) -> int | None:
    if s.settings.size_mode == "picture" and "a" not in s.images:
        return None  # sized from a picture not given yet
    try:
        return design.width_of(s.settings, s.images)[0]
    except AppRequestError:
        return None


def check_slot(slot: str) -> None:
    if slot not in ("a", "b"):
        raise AppRequestError(
            f"image slot must be 'a' or 'b', got {slot!r}",
            field="slot",
            code="bad_slot",
            status=404,
        )


def prepared_of(s: Session) -> design.Prepared:
    """The session's pictures quantised under its settings (computed once per revision)."""
    # Quantising is done outside the session lock so that quick requests of the same tab
    # (thumbnails, state) are not held up; the result is kept only if nothing changed since.
    with s.lock:
        if s.prepared is not None:
            prepared: design.Prepared = s.prepared
            return prepared
        images, settings, revision = dict(s.images), s.settings, s.revision
    prepared = design.prepare_inputs(images, settings)
    with s.lock:
        if s.revision == revision:
            s.prepared = prepared
    return prepared


def candidate_of(s: Session, rank: int | None) -> design.Candidate:
    """Candidate ``rank`` (the picked one when None); 409 before any candidates exist."""
    if not s.candidates:
        raise AppRequestError(
            "no candidates yet: press 'Find candidates'",
            field="candidates",
            code="no_candidates",
            status=409,
        )
    r = s.selected if rank is None else rank
    if not 1 <= r <= len(s.candidates):
        raise AppRequestError(
            f"candidate must be 1..{len(s.candidates)}, got {r}",
            field="candidate",
            code="range",
        )
    candidate: design.Candidate = s.candidates[r - 1]
    return candidate


def current_pattern(s: Session, rank: int | None = None) -> LogicalPattern:
    """The pattern of candidate ``rank``, or of the picked one with the designer's tile edits."""
    with s.lock:
        cand = candidate_of(s, rank)
        if rank is not None and rank != s.selected:
            return cand.pattern
        return design.pattern_for(cand, s.overrides)
