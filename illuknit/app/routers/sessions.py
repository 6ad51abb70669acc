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


@router.get("", summary="Saved designs to reopen (sessions with a picture), newest first")
def list_sessions(store: StoreDep) -> dict[str, Any]:
    return {"sessions": store.saved()}


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
        changes = _implied(s.settings, changes)
        new = DesignSettings.model_validate({**s.settings.model_dump(), **changes})
        if "yarns" not in changes and changes.keys() & {"n_colors", "mode"}:
            # more colours than yarns: yarns are added from the pictures, as the CLI chooses them
            new = new.model_copy(update={"yarns": design.yarns_for_colors(new, s.images)})
        _check_fits(new, changes, s.images)
        if new != s.settings:
            s.remember(settings_change(_as_sized(s.settings, s.images), new))  # for Undo
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
    "made_for": "made for",
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


def _as_sized(settings: DesignSettings, images: dict[str, Any]) -> DesignSettings:
    """``settings`` with the width it gives when sized from the picture (so that the words for
    a change say the width the designer saw, not the unused stored one)."""
    if settings.size_mode != "picture":
        return settings
    try:
        width, _ = design.width_of(settings, images)
    except AppRequestError:
        return settings
    return settings.model_copy(update={"width_units": width})


def _implied(old: DesignSettings, changes: dict[str, Any]) -> dict[str, Any]:
    """A width typed while the piece is sized from the picture sizes it by that width from
    then on (units, or physical for a width in cm or a gauge)."""
    if old.size_mode != "picture" or "size_mode" in changes:
        return changes
    if "width_units" in changes:
        return {**changes, "size_mode": "units"}
    if changes.keys() & {"width_cm", "gauge"}:
        return {**changes, "size_mode": "physical"}
    return changes


def _check_fits(settings: DesignSettings, changes: dict[str, Any], images: dict[str, Any]) -> None:
    """Refuse a width the chosen bed cannot knit now, before any work, next to the control the
    designer just changed (the machine, or the width)."""
    if changes.keys().isdisjoint({"machine", "width_units", "width_cm", "gauge", "size_mode"}):
        return
    try:
        design.width_of(settings, images)
    except AppRequestError as e:
        if e.code == "too_wide" and "machine" in changes:
            e.field = "machine"
        raise
