"""The designer's pictures: uploads decoded to the working grid, then sized and quantised to yarns.

    uploaded file -> decode_upload (header checks, reduction while decoding)
                  -> prepare_inputs (the library's pair sizing, quantisation, the legend)
                  -> Prepared (what the page shows as "quantised inputs")

A problem is an :class:`~illuknit.core.errors.AppRequestError` naming the page control at fault.
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from illuknit.app.controls import blame
from illuknit.core.errors import AppRequestError, IlluknitError, PictureSizeMismatchError
from illuknit.core.pattern import Yarn, parse_yarns
from illuknit.pictures.images import MAX_PIXELS

if TYPE_CHECKING:
    from illuknit.app.schemas import DesignSettings
    from illuknit.core.gauge import Gauge

__all__ = [
    "MAX_UPLOAD_BYTES",
    "MAX_UPLOAD_PIXELS",
    "MAX_WORKING_SIDE",
    "Prepared",
    "decode_upload",
    "design_gauge",
    "prepare_inputs",
    "size_inputs",
    "sizing_aspect",
    "slots_for",
    "too_large_message",
    "width_of",
    "yarns_for_colors",
]

#: Default of the one upload limit (bytes), ``AppConfig.max_upload_bytes``: a full-size photograph
#: from a phone or camera. It is reduced to the working grid on upload and not kept.
MAX_UPLOAD_BYTES = 32 * 1024 * 1024
#: Largest accepted picture (pixels), checked from the header before decoding: half the library's
#: cap (50 megapixels), since the server decodes uploads of many sessions.
MAX_UPLOAD_PIXELS = MAX_PIXELS // 2
#: Pictures with a longer side are reduced to it on upload (twice the widest piece in units).
MAX_WORKING_SIDE = 2000


def decode_upload(
    data: bytes, filename: str, *, field: str
) -> tuple[NDArray[np.uint8], tuple[str, ...]]:
    """Decode an uploaded picture to uint8 RGB (H, W, 3) at the working grid, with its notes.

    The library's reader decodes it (:func:`illuknit.pictures.decode.read_picture`: 16-bit, palettes,
    CMYK, EXIF orientation, alpha on white, the first frame of an animation), reducing pictures
    over ``MAX_WORKING_SIDE`` pixels while decoding, so no full-size copy (let alone a float one)
    is ever kept. The notes say what was done (e.g. "reduced from ... while reading").

    The size of the file is not checked here: the server's configured limit
    (``AppConfig.max_upload_bytes``) is, once, before the file is read (:func:`too_large_message`).

    Raises AppRequestError (``field``) for an empty, non-image, too-small file or one of too many
    pixels.
    """
    from illuknit.pictures.decode import read_picture

    if not data:
        raise AppRequestError("the file is empty", field=field, code="empty")
    _check_header(data, field)
    try:
        pic = read_picture(data, max_side=MAX_WORKING_SIDE, name=repr(filename or "the file"))
    except IlluknitError as e:
        raise AppRequestError(str(e), field=field, code="not_an_image", status=415) from None
    return pic.rgb, pic.notes


def too_large_message(limit: int) -> str:
    """What the designer is told about a file over the upload limit of ``limit`` bytes (the one
    message, whichever check finds it: the request's size or the file's)."""
    from illuknit.core.pattern import MAX_UNITS

    return (
        f"the file is over {_size_text(limit)}, the limit for pictures; save a smaller copy (a "
        f"knitted piece is at most {MAX_UNITS} units across, so a few hundred pixels are plenty)"
    )


def _size_text(n: int) -> str:
    """``n`` bytes for a reader: ``"32 MB"``, ``"195.3 kB"``, ``"900 bytes"`` (binary units)."""
    for unit, size in (("MB", 2**20), ("kB", 2**10)):
        if n >= size:
            return f"{n / size:.1f}".removesuffix(".0") + f" {unit}"
    return f"{n} bytes"


def _check_header(data: bytes, field: str) -> tuple[int, int]:
    """Refuse non-images and decompression bombs from the header alone (before decoding)."""
    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(io.BytesIO(data)) as im:
            w, h = im.size
    except UnidentifiedImageError:
        raise AppRequestError(
            "this file is not a picture; upload a PNG, JPEG, GIF or BMP image",
            field=field,
            code="not_an_image",
            status=415,
        ) from None
    except Exception as e:  # truncated headers and the like
        raise AppRequestError(
            f"cannot read this picture: {e}", field=field, code="not_an_image", status=415
        ) from None
    if w * h > MAX_UPLOAD_PIXELS:
        raise AppRequestError(
            f"the picture is {w} x {h} pixels; the limit is {MAX_UPLOAD_PIXELS // 1_000_000} megapixels",
            field=field,
            code="too_large",
            status=413,
        )
    return int(w), int(h)


@dataclass(frozen=True, eq=False)
class Prepared:
    """The inputs resized to the grid and quantised to yarns (what the page shows as "quantised")."""

    mode: str
    yarns: tuple[Yarn, ...]
    quantised: dict[str, Any]  # slot -> QuantisedImage
    notes: tuple[str, ...] = ()

    @property
    def shape(self) -> tuple[int, int]:
        """(rows N, cols M) of the grid (every slot has picture A's)."""
        shape: tuple[int, int] = self.quantised["a"].shape
        return shape

    def legend(self) -> dict[str, list[dict[str, Any]]]:
        return {slot: q.legend() for slot, q in self.quantised.items()}


def slots_for(mode: str, present: Any = ("a", "b")) -> tuple[str, ...]:
    """Image slots a mode uses: one picture for single view, two for double view; head-on takes
    the front picture and, optionally, a picture seen at an angle (else a plain side)."""
    if mode == "single":
        return ("a",)
    if mode == "headon":
        return ("a", "b") if "b" in present else ("a",)
    return ("a", "b")


def prepare_inputs(images: dict[str, Any], settings: DesignSettings) -> Prepared:
    """Resize and quantise the session's pictures under ``settings`` (a DesignSettings).

    Raises AppRequestError naming the control at fault: a missing picture (``image_a``/``image_b``),
    pictures of different sizes in double view (``image_b``, code ``size_mismatch``, with the
    offer to resize), a width out of range (``width_units``/``width_cm``), bad yarns (``yarns``),
    colour count issues (``n_colors``).
    """
    from illuknit.pictures.images import quantise_image

    mode = settings.mode
    slots = _require_pictures(images, mode)
    with blame("yarns"):
        yarns = parse_yarns(list(settings.yarns))
    _check_colors(mode, settings.n_colors, len(yarns))
    resized, notes = size_inputs(images, settings)
    if mode == "single":
        q, note = _single_view_input(resized["a"], yarns, settings.n_colors)
        return Prepared(mode=mode, yarns=yarns, quantised={"a": q}, notes=(*notes, *note))
    quantised = {}
    for slot in slots:
        with blame("n_colors"):
            quantised[slot] = quantise_image(resized[slot], n_colors=settings.n_colors, yarns=yarns)
    return Prepared(mode=mode, yarns=yarns, quantised=quantised, notes=notes)


def _require_pictures(images: dict[str, Any], mode: str) -> tuple[str, ...]:
    """The slots ``mode`` uses; AppRequestError on the first one without a picture."""
    slots = slots_for(mode, images)
    for slot in slots:
        if slot not in images:
            which = "the picture" if len(slots) == 1 else f"picture {slot.upper()}"
            raise AppRequestError(f"upload {which} first", field=f"image_{slot}", code="missing")
    return slots


def size_inputs(
    images: dict[str, Any], settings: DesignSettings
) -> tuple[dict[str, NDArray[np.float64]], tuple[str, ...]]:
    """The pictures ``settings.mode`` uses on the piece's grid, before quantising, with the notes
    of the library's pair sizing (:func:`illuknit.pictures.sizing.size_pair`, the command line's policy).

    Raises AppRequestError for a missing picture, a width out of range and pictures of
    different shapes (``image_b``, code ``size_mismatch``).
    """
    from illuknit.pictures.sizing import size_pair

    slots = _require_pictures(images, settings.mode)
    width, size_field = width_of(settings, images)
    a = images["a"].rgb
    b = images["b"].rgb if "b" in slots else None
    with blame(size_field):
        try:
            pair = size_pair(
                a,
                b,
                width=width,
                stretch=settings.resize,
                # an accepted edit is a grid picture (illuknit.pictures.sizing.grid_picture): smoothing
                # would blend its units' colours
                smooth=False if any(_is_grid(images[k]) for k in slots) else settings.smooth,
                unit_aspect=sizing_aspect(settings),
            )
        except PictureSizeMismatchError:
            assert b is not None
            raise AppRequestError(
                f"picture A is {a.shape[1]} x {a.shape[0]} pixels but picture B is "
                f"{b.shape[1]} x {b.shape[0]}; both pictures must cover the same piece (one "
                "aspect ratio). Resize B to A's size, or upload pictures of one shape.",
                field="image_b",
                code="size_mismatch",
                status=409,
            ) from None
    n = pair.shape[0]
    if n < 2:
        raise AppRequestError(
            f"the picture is only {n} unit tall at this width; use a wider piece",
            field=size_field,
            code="range",
        )
    resized = {"a": pair.a} if pair.b is None else {"a": pair.a, "b": pair.b}
    return resized, tuple(pair.notes)


#: the note an accepted suggested edit leaves on a picture (its pixels are on the unit grid)
ACCEPTED_EDIT_NOTE = "suggested edit accepted"


def _is_grid(image: Any) -> bool:
    return any(n.startswith(ACCEPTED_EDIT_NOTE) for n in getattr(image, "notes", ()))


def _check_colors(mode: str, n_colors: int, n_yarns: int) -> None:
    """Colour count against yarn count: what the CLI accepts, refused next to the control."""
    if mode != "single":
        if n_colors > n_yarns:
            raise AppRequestError(
                f"{n_colors} colours need at least {n_colors} yarns; add a yarn or use fewer "
                "colours",
                field="n_colors",
                code="too_few_yarns",
            )
        return
    if n_colors not in (2, 3):
        raise AppRequestError(
            "a single-view illusion shows 2 or 3 colours (the third as a mix of two yarns)",
            field="n_colors",
            code="range",
        )
    if n_yarns not in (2, 3) or n_yarns > n_colors:
        raise AppRequestError(
            f"a single-view illusion of {n_colors} colours is knitted with 2 yarns"
            + (" (or 3, one per colour)" if n_colors == 3 else "")
            + f"; remove {n_yarns - 2 if n_colors == 2 else n_yarns - 3} yarn(s)",
            field="yarns",
            code="range",
        )


def width_of(settings: DesignSettings, images: dict[str, Any] | None = None) -> tuple[int, str]:
    """The piece's width in units under ``settings``, and the control that sets it.

    ``size_mode`` "picture" sizes as the command line does with no width given
    (:func:`~illuknit.pictures.sizing.grid_width`: picture A's width in pixels, at most
    :data:`~illuknit.pictures.sizing.DEFAULT_MAX_WIDTH` units; that bound before a picture is
    there), and never wider than the chosen bed.

    Raises AppRequestError (on that control) for a width outside 2..MAX_UNITS or wider than the
    chosen machine's bed.
    """
    from illuknit.core.machine import get_machine
    from illuknit.core.pattern import MAX_UNITS
    from illuknit.pictures.images import units_for_width
    from illuknit.pictures.sizing import DEFAULT_MAX_WIDTH, grid_width

    if settings.size_mode == "physical":
        with blame("width_cm"):
            width = units_for_width(width_cm=settings.width_cm, gauge=settings.gauge)
        size_field = "width_cm"
    elif settings.size_mode == "picture":
        a = (images or {}).get("a")
        width = DEFAULT_MAX_WIDTH if a is None else grid_width(a.rgb.shape[1]) or DEFAULT_MAX_WIDTH
        width = max(2, min(width, get_machine(settings.machine).max_units))
        size_field = "width_units"
    else:
        width, size_field = settings.width_units, "width_units"
    if width < 2 or width > MAX_UNITS:
        raise AppRequestError(
            f"the piece would be {width} units wide; it must be 2..{MAX_UNITS} units",
            field=size_field,
            code="range",
        )
    machine = get_machine(settings.machine)
    if width > machine.max_units:
        # refused before any work: a pattern that cannot go on the chosen bed is not designed
        raise AppRequestError(
            f"the piece would be {width} units = {2 * width} stitches wide, but "
            f"{machine.bed_text} holds at most {machine.max_units} "
            "units; make it narrower or choose a wider machine",
            field=size_field,
            code="too_wide",
        )
    return width, size_field


def _single_view_input(
    rgb: NDArray[np.float64], yarns: tuple[Yarn, ...], n_colors: int
) -> tuple[Any, tuple[str, ...]]:
    """The picture mapped for the single-view compiler, as ``illuknit single`` maps it.

    With two yarns and three colours the middle colour is a mix: rows of the two yarns side by
    side, which the eye blends. The legend shows it as that, in the colour of the blend.
    """
    from illuknit.design.single_view import prepare_single_view_image, single_view_roles
    from illuknit.pictures.images import QuantisedImage

    n, m = rgb.shape[:2]
    with blame("n_colors"):
        q = prepare_single_view_image(rgb, yarns=yarns, n_colors=n_colors, width=m, height=n)
    mixes = [i for i, y in enumerate(q.yarns) if y not in yarns]
    if len(yarns) != 2 or not mixes:
        return q, ()
    dark, light, _ = single_view_roles(yarns)
    blend = tuple(
        round((u + v) / 2) for u, v in zip(yarns[dark].rgb, yarns[light].rgb, strict=True)
    )
    name = f"mix of {yarns[dark].name} and {yarns[light].name}"
    mapped = tuple(Yarn(name, blend) if i in mixes else y for i, y in enumerate(q.yarns))  # type: ignore[arg-type]
    note = (
        f"the middle colour is knitted as a mix: rows of {yarns[dark].name} and "
        f"{yarns[light].name}, which read as their blend",
    )
    return QuantisedImage(q.indices, mapped, q.colors, q.counts), note


def design_gauge(settings: DesignSettings) -> Gauge:
    """The gauge the session's design is drawn for: the machine's fabric gauge, or made for
    hands the gauge the hand pattern gives (:func:`~illuknit.core.gauge.hand_gauge`), as the
    command line sizes and describes it; the finished size, the grid's pictures, the renders and
    the documents are at it."""
    from illuknit.core.gauge import drawn_gauge
    from illuknit.core.machine import get_machine

    return drawn_gauge(get_machine(settings.machine).fabric_gauge, settings.made_for)


def sizing_aspect(settings: DesignSettings) -> float:
    """Height over width of a unit when sizing the pictures to the grid: 1.0 with
    ``square_units``, else :func:`design_gauge`'s (so the finished piece keeps the picture's
    proportions)."""
    if settings.square_units:
        return 1.0
    return design_gauge(settings).unit_aspect


#: Yarns added when no picture is there to choose from (the page's "Add yarn" offers the same).
SPARE_YARNS = ("#8a8a8a", "#b3202a", "#1d2b53", "#d9a62e", "#1f4d3a", "#c97b84")
#: Pixels of each picture the yarn choice looks at (every k-th: the colours, not the detail).
_YARN_SAMPLE = 40_000


def yarns_for_colors(settings: DesignSettings, images: dict[str, Any]) -> tuple[str, ...]:
    """The yarns of ``settings``, with yarns added when a two-picture mode asks for more colours
    than there are yarns (``illuknit double --colors 3`` chooses 3 yarns; the app would
    otherwise stop at "add a yarn").

    The yarns the designer has are kept; the new ones are chosen from the pictures as the
    command line chooses them (:func:`~illuknit.design.tiles.yarn_choice.choose_yarns`: each
    picture's darkest and lightest colour first), each time the one farthest (CIELAB) from
    the yarns there; :data:`SPARE_YARNS` when the pictures offer no other colour.
    """
    from illuknit.core.colors import lab_from_rgb
    from illuknit.design.tiles.yarn_choice import SAME_COLOUR_LAB, choose_yarns

    have = list(settings.yarns)
    need = settings.n_colors - len(have)
    if settings.mode == "single" or need <= 0:
        return tuple(have)
    with blame("yarns"):
        rgb = [list(y.rgb) for y in parse_yarns(have)]
    # the colours only, not the layout: every k-th pixel, two to a row (pictures of any shapes
    # go into one joint clustering)
    flat = [im.rgb.reshape(-1, 3) for im in images.values()]
    flat = [p[:: max(1, len(p) // _YARN_SAMPLE)] for p in flat]
    pictures = [p[: len(p) // 2 * 2].reshape(-1, 2, 3) for p in flat if len(p) >= 4]
    offered = [list(y.rgb) for y in choose_yarns(pictures, settings.n_colors)] if pictures else []
    spares = [list(parse_yarns([c])[0].rgb) for c in SPARE_YARNS]
    for pool, least in ((offered, SAME_COLOUR_LAB), (spares, 0.0)):
        while need > 0 and pool:
            far = np.linalg.norm(
                lab_from_rgb(np.array(pool, float))[:, None]
                - lab_from_rgb(np.array(rgb, float))[None],
                axis=2,
            ).min(axis=1)
            best = int(np.argmax(far))
            if far[best] <= least:
                break
            rgb.append(pool.pop(best))
            have.append("#{:02x}{:02x}{:02x}".format(*rgb[-1]))
            need -= 1
    return tuple(have)
