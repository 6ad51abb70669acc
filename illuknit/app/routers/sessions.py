"""Sessions: one per browser tab; start, read, end, and change its settings."""

from typing import Annotated, Any

from fastapi import APIRouter, Depends

from illuknit.app import design
from illuknit.app.lookups import SessionDep, state_json, store_of
from illuknit.app.schemas import DesignSettings, SettingsPatch
from illuknit.app.sessions import SessionStore
from illuknit.core.errors import AppRequestError
from illuknit.core.pattern import parse_yarns

__all__ = ["router"]

router = APIRouter(prefix="/api/sessions", tags=["sessions"])

StoreDep = Annotated[SessionStore, Depends(store_of)]


@router.post("", status_code=201, summary="Start a session (one per tab)")
def create_session(store: StoreDep) -> dict[str, Any]:
    s = store.create()
    with s.lock:
        return state_json(s)


@router.get("/{sid}", summary="The session's state")
def get_session(s: SessionDep) -> dict[str, Any]:
    with s.lock:
        return state_json(s)


@router.delete("/{sid}", summary="End a session, cancelling its jobs")
def delete_session(s: SessionDep, store: StoreDep) -> dict[str, Any]:
    store.delete(s.id)
    return {"deleted": s.id}


@router.put("/{sid}/settings", tags=["inputs"], summary="Change design settings")
def put_settings(s: SessionDep, body: SettingsPatch) -> dict[str, Any]:  # type: ignore[valid-type]
    changes = body.model_dump(exclude_none=True)  # type: ignore[attr-defined]
    if "yarns" in changes:
        with design.blame("yarns"):
            parse_yarns(list(changes["yarns"]))
    with s.changing():
        new = DesignSettings.model_validate({**s.settings.model_dump(), **changes})
        _check_fits(new, changes)
        if new != s.settings:
            s.remember(settings_change(s.settings, new))  # the design as it is, for Undo
            same_design = new.model_dump(exclude=set(VIEWPOINT)) == s.settings.model_dump(
                exclude=set(VIEWPOINT)
            )
            s.settings = new
            if same_design:  # the same candidates, to be measured from somewhere else
                s.remeasure()
            else:
                s.bump()
        return state_json(s)


#: The settings that say where the measures look from, not what is designed.
VIEWPOINT = ("view_angle", "view_distance")

#: How the page names each setting in the list of what Undo takes back.
SETTING_WORDS = {
    "mode": "mode",
    "size_mode": "size by",
    "width_units": "width (units)",
    "width_cm": "width (cm)",
    "gauge": "gauge",
    "n_colors": "colours per picture",
    "yarns": "yarns",
    "candidates": "candidates shown",
    "resize": "stretch B to A's size",
    "machine": "machine",
    "smooth": "smoothing",
    "square_units": "square units",
    "split_bumps": "split bumps",
    "view_angle": "measured at angle",
    "view_distance": "measured from (m)",
}


def settings_change(old: DesignSettings, new: DesignSettings) -> str:
    """A change of settings in words, e.g. "width (units) 60 -> 24"."""
    a, b = old.model_dump(), new.model_dump()
    parts = []
    for key in a:
        if a[key] != b[key]:
            word = SETTING_WORDS.get(key, key.replace("_", " "))
            if key == "yarns":
                parts.append(f"yarns ({len(a[key])} -> {len(b[key])})")
            else:
                parts.append(f"{word} {a[key]} -> {b[key]}")
    return "change of " + ", ".join(parts) if parts else "change of settings"


def _check_fits(settings: DesignSettings, changes: dict[str, Any]) -> None:
    """Refuse a width the chosen bed cannot knit now, before any work, next to the control the
    designer just changed (the machine, or the width)."""
    if changes.keys().isdisjoint({"machine", "width_units", "width_cm", "gauge", "size_mode"}):
        return
    try:
        design.width_of(settings)
    except AppRequestError as e:
        if e.code == "too_wide" and "machine" in changes:
            e.field = "machine"
        raise
