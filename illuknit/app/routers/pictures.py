"""Pictures: upload picture A or B, see it as sent, and see both quantised to the yarns."""

from typing import Annotated, Any

from fastapi import APIRouter, File, Request, UploadFile
from fastapi.responses import Response

from illuknit.app import design
from illuknit.app.lookups import SessionDep, check_slot, prepared_of, state_json, store_of
from illuknit.app.sessions import UploadedImage
from illuknit.core.errors import AppRequestError

__all__ = ["router"]

router = APIRouter(prefix="/api/sessions/{sid}", tags=["inputs"])


@router.put("/images/{slot}", summary="Upload (or replace) picture A or B; settings are kept")
def put_image(
    request: Request,
    s: SessionDep,
    slot: str,
    file: Annotated[UploadFile | None, File()] = None,
) -> dict[str, Any]:
    check_slot(slot)
    field = f"image_{slot}"
    if file is None:
        raise AppRequestError(
            "no file in the upload (form field 'file')", field=field, code="missing"
        )
    # the one upload limit, configured (UploadLimit refuses the request before it is read when
    # its body alone is over it; this finds a file just over it inside the multipart framing)
    limit = request.app.state.config.max_upload_bytes
    data = file.file.read(limit + 1)
    if len(data) > limit:
        raise AppRequestError(
            design.too_large_message(limit), field=field, code="too_large", status=413
        )
    rgb, notes = design.decode_upload(data, file.filename or "", field=field)
    with s.changing():
        name = file.filename or f"{slot}.png"
        s.remember(f"upload of picture {slot.upper()} ({name})")  # the design as it is, for Undo
        s.images[slot] = UploadedImage(name, len(data), rgb, notes)
        s.bump()
        state = state_json(s)
    del data
    store_of(request).trim(keep=s.id)
    return state


@router.get("/images/{slot}", summary="The uploaded picture at the working grid (PNG)")
def get_image(s: SessionDep, slot: str) -> Response:
    check_slot(slot)
    with s.lock:
        im = s.images.get(slot)
    if im is None:
        raise AppRequestError(
            f"no picture {slot.upper()} uploaded",
            field=f"image_{slot}",
            code="missing",
            status=404,
        )
    return Response(
        design.png_bytes(im.rgb), media_type="image/png", headers={"Cache-Control": "no-store"}
    )


@router.delete("/images/{slot}", summary="Remove a picture")
def delete_image(s: SessionDep, slot: str) -> dict[str, Any]:
    check_slot(slot)
    with s.changing():
        if slot in s.images:
            s.remember(f"removal of picture {slot.upper()}")
            del s.images[slot]
            s.bump()
        return state_json(s)


@router.get("/inputs", summary="Quantise the pictures under the settings: sizes and legends")
def get_inputs(s: SessionDep) -> dict[str, Any]:
    from illuknit.app.inputs import design_gauge
    from illuknit.core.gauge import finished_size
    from illuknit.core.machine import get_machine

    with s.lock:
        p = prepared_of(s)
        rev = s.revision
        gauge = design_gauge(s.settings)
        by_hand = s.settings.made_for == "hands"
        machine = get_machine(s.settings.machine)
    n, m = p.shape
    size = finished_size((n, m), gauge)
    return {
        "revision": rev,
        "mode": p.mode,
        "rows": n,
        "cols": m,
        # the grid keeps the pictures' proportions at this gauge (units 0.7 as tall as wide)
        # unless the settings ask for square units
        # made for hands, the size by hand at the hand pattern's estimated gauge
        "finished_size": {
            **size.as_dict(),
            "text": size.describe(),
            "by_hand": by_hand,
            "estimate": by_hand and gauge.estimate,
        },
        "yarns": [{"name": y.name, "rgb": y.hex} for y in p.yarns],
        "legend": p.legend(),
        # and what the designer should know about the bed (fits only a generic one, ...)
        "notes": [*p.notes, *filter(None, [machine.fit_note(m)])],
        "images": {slot: f"/api/sessions/{s.id}/inputs/{slot}.png?r={rev}" for slot in p.quantised},
    }


@router.get("/inputs/{slot}.png", summary="A quantised picture")
def get_input_png(s: SessionDep, slot: str) -> Response:
    check_slot(slot)
    p = prepared_of(s)
    if slot not in p.quantised:
        raise AppRequestError(
            f"no quantised picture {slot.upper()} in this mode",
            field=f"image_{slot}",
            code="missing",
            status=404,
        )
    from illuknit.app.inputs import design_gauge
    from illuknit.pictures.sizing import grid_picture

    # on the unit grid: drawn in the fabric's proportions (units unit_aspect as tall as wide),
    # as the renders beside it are, not one square pixel a unit (1.43x too tall)
    rgb = p.quantised[slot].rgb()
    aspect = design_gauge(s.settings).unit_aspect
    scale = max(2, min(8, 1600 // max(1, rgb.shape[1])))
    return Response(
        design.png_bytes(grid_picture(rgb, unit_aspect=aspect, scale=scale)),
        media_type="image/png",
        headers={"Cache-Control": "no-store"},
    )
