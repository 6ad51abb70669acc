"""History: undo an accepted suggested edit (the design before it comes back whole), and redo it.

The session keeps the design as it was before each accepted edit (:mod:`illuknit.app.history`).
Both routes answer ``{"undone" or "redone": what, "state": the session, "job": a candidate
search or null}``: the design comes back with its candidates when they had been found, else
the search is started again, as after an accept. With nothing to undo (redo) they answer 409
``nothing_to_undo`` (``nothing_to_redo``).
"""

from collections.abc import Callable
from typing import Any

from fastapi import APIRouter, Request

from illuknit.app.jobs import Job
from illuknit.app.lookups import SessionDep, runner_of, state_json, store_of
from illuknit.app.routers.jobs import start_candidates
from illuknit.app.sessions import Session
from illuknit.core.errors import AppRequestError

__all__ = ["router"]

router = APIRouter(prefix="/api/sessions/{sid}/history", tags=["suggestions"])


@router.get("", summary="What Undo and Redo would do, newest first")
def get_history(s: SessionDep) -> dict[str, Any]:
    with s.lock:
        answer: dict[str, Any] = state_json(s)["history"]
        return answer


@router.post("/undo", summary="Undo the last accepted edit: the design before it comes back")
def post_undo(request: Request, s: SessionDep) -> dict[str, Any]:
    return _step(request, s, Session.undo, "undone")


@router.post("/redo", summary="Accept the last undone edit again")
def post_redo(request: Request, s: SessionDep) -> dict[str, Any]:
    return _step(request, s, Session.redo, "redone")


def _step(request: Request, s: Session, step: Callable[[Session], str], key: str) -> dict[str, Any]:
    """Undo or redo (``step``) under the session's lock, design the restored state again if it
    has no candidates, and answer ``{key: what, "state": ..., "job": ...}``."""
    with s.changing():
        what = step(s)
        job = _design_again(request, s)
        answer = {
            key: what,
            "state": state_json(s),
            "job": None if job is None else job.to_json(),
        }
    store_of(request).trim(keep=s.id)
    return answer


def _design_again(request: Request, s: Session) -> Job | None:
    """A candidate search for a restored state that had none yet (None when it has them, or
    when its inputs cannot be designed: the page then shows why, next to the control)."""
    if s.candidates:
        return None
    try:
        job = start_candidates(
            s, runner_of(request), isolate=request.app.state.config.isolate_search
        )
    except AppRequestError:
        return None
    s.replace_job("candidates", job)
    return job
