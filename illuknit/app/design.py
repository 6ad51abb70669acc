"""The app's design pipeline: the library stages the page drives, in the order a designer uses them.

    uploaded file -> decode_upload -> prepare_inputs (resize to units, quantise to yarns, legend)
                  -> make_candidates (single view: both stripe orders; double view / head-on:
                     ranked tile mappings) -> pattern_for (with per-pair tile overrides)
                  -> render_view (the angled renderer)
                  -> downloads (pattern JSON, previews, chart, instructions, knitout + check)

Everything here is a plain function of its inputs (no session, no HTTP), so the server stays a thin
layer and these functions are testable on their own. Library errors are re-raised as
:class:`AppRequestError` naming the page control (``field``) that caused them, which is what lets
the page show the message next to that control.

Every library part used here is imported directly: an import error in illuknit's own code is a
bug to see, never a feature to grey out.
"""

from __future__ import annotations

import importlib
import io
import os
import tempfile
import zipfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any, Literal
from urllib.parse import urlencode

import numpy as np
from numpy.typing import NDArray

from illuknit.colors import hex_color
from illuknit.errors import AppRequestError, IlluknitError, PictureSizeMismatchError
from illuknit.images import MAX_PIXELS
from illuknit.pattern import LogicalPattern, Yarn, parse_yarns, pattern_to_json

__all__ = [
    "MAX_UPLOAD_BYTES",
    "Candidate",
    "Prepared",
    "capabilities",
    "decode_upload",
    "make_candidates",
    "pattern_for",
    "prepare_inputs",
    "render_view",
]

#: Largest accepted upload (bytes): a full-size photograph from a phone or camera. It is reduced to
#: the working grid on upload and not kept.
MAX_UPLOAD_BYTES = 32 * 1024 * 1024
#: Largest accepted picture (pixels), checked from the header before decoding: half the library's
#: cap (50 megapixels), since the server decodes uploads of many sessions.
MAX_UPLOAD_PIXELS = MAX_PIXELS // 2
#: Pictures with a longer side are reduced to it on upload (twice the widest piece in units).
MAX_WORKING_SIDE = 2000

YARN_PRESETS: dict[str, tuple[str, ...]] = {
    "Charcoal & cream": ("#1b1b1b", "#f4f0e8"),
    "Navy & white": ("#1d2b53", "#f7f7f2"),
    "Red & ecru": ("#a4161a", "#efe6d2"),
    "Forest & oat": ("#1f4d3a", "#e9e1cc"),
    "Black, grey, white": ("#1b1b1b", "#8a8a8a", "#f4f0e8"),
    "Plum, rose, cream": ("#4a1942", "#c97b84", "#f6efe4"),
    "Teal, mustard, cream": ("#0f5257", "#d9a62e", "#f4f0e8"),
    "Black, red, grey, white": ("#1b1b1b", "#b3202a", "#9a9a9a", "#f4f0e8"),
}


@contextmanager
def blame(field_name: str | None) -> Iterator[None]:
    """Re-raise library errors inside the block as AppRequestError naming the page control."""
    try:
        yield
    except AppRequestError:
        raise
    except IlluknitError as e:
        raise AppRequestError(str(e), field=field_name, code=type(e).__name__) from None


def capabilities() -> dict[str, bool]:
    """What this install can do (the page greys out the rest).

    Every part the page drives is illuknit's own and always installed.
    """
    return {
        "single": True,
        "double": True,
        "headon": True,
        "render": True,
        "knit": True,
        "check": True,
        "chart": True,
        "dat": True,
    }


def warm_up() -> None:
    """Import the modules the first request would otherwise wait for (run in a thread)."""
    for name in (
        "illuknit.images",
        "skimage.transform",
        "scipy.optimize",
        "illuknit.single_view",
        "illuknit.previews",
        "illuknit.render",
        "illuknit.tiles.assign",
        "illuknit.tiles.compile",
        "illuknit.tiles.headon",
        "ortools.sat.python.cp_model",
    ):
        importlib.import_module(name)


# -- input -------------------------------------------------------------------------------------


def decode_upload(
    data: bytes, filename: str, *, field: str
) -> tuple[NDArray[np.uint8], tuple[str, ...]]:
    """Decode an uploaded picture to uint8 RGB (H, W, 3) at the working grid, with its notes.

    The library's reader decodes it (:func:`illuknit.pictures.read_picture`: 16-bit, palettes,
    CMYK, EXIF orientation, alpha on white, the first frame of an animation), reducing pictures
    over ``MAX_WORKING_SIDE`` pixels while decoding, so no full-size copy (let alone a float one)
    is ever kept. The notes say what was done (e.g. "reduced from ... while reading").

    Raises AppRequestError (``field``) for an empty, oversized, non-image or too-small file.
    """
    from illuknit.pictures import read_picture

    if not data:
        raise AppRequestError("the file is empty", field=field, code="empty")
    if len(data) > MAX_UPLOAD_BYTES:
        raise AppRequestError(
            f"the file is {len(data) / 1e6:.1f} MB; the limit is {MAX_UPLOAD_BYTES / 1e6:.0f} MB",
            field=field,
            code="too_large",
            status=413,
        )
    _check_header(data, field)
    try:
        pic = read_picture(data, max_side=MAX_WORKING_SIDE, name=repr(filename or "the file"))
    except IlluknitError as e:
        raise AppRequestError(str(e), field=field, code="not_an_image", status=415) from None
    return pic.rgb, pic.notes


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


def prepare_inputs(images: dict[str, Any], settings: Any) -> Prepared:
    """Resize and quantise the session's pictures under ``settings`` (a DesignSettings).

    Raises AppRequestError naming the control at fault: a missing picture (``image_a``/``image_b``),
    pictures of different sizes in double view (``image_b``, code ``size_mismatch``, with the
    offer to resize), a width out of range (``width_units``/``width_cm``), bad yarns (``yarns``),
    colour count issues (``n_colors``).
    """
    from illuknit.images import quantise_image
    from illuknit.sizing import size_pair

    mode = settings.mode
    slots = slots_for(mode, images)
    for slot in slots:
        if slot not in images:
            which = "the picture" if len(slots) == 1 else f"picture {slot.upper()}"
            raise AppRequestError(f"upload {which} first", field=f"image_{slot}", code="missing")
    with blame("yarns"):
        yarns = parse_yarns(list(settings.yarns))
    _check_colors(mode, settings.n_colors, len(yarns))
    width, size_field = width_of(settings)
    a = images["a"].rgb
    b = images["b"].rgb if "b" in slots else None
    with blame(size_field):  # the same sizing policy as the command line (illuknit.sizing)
        try:
            pair = size_pair(a, b, width=width, stretch=settings.resize, smooth=settings.smooth)
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
    resized = {"a": pair.a} if pair.b is None else {"a": pair.a, "b": pair.b}
    notes = list(pair.notes)
    n = pair.shape[0]
    if n < 2:
        raise AppRequestError(
            f"the picture is only {n} unit tall at this width; use a wider piece",
            field=size_field,
            code="range",
        )
    if mode == "single":
        q, note = _single_view_input(resized["a"], yarns, settings.n_colors)
        return Prepared(mode=mode, yarns=yarns, quantised={"a": q}, notes=(*notes, *note))
    quantised = {}
    for slot in slots:
        with blame("n_colors"):
            quantised[slot] = quantise_image(resized[slot], n_colors=settings.n_colors, yarns=yarns)
    return Prepared(mode=mode, yarns=yarns, quantised=quantised, notes=tuple(notes))


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


def width_of(settings: Any) -> tuple[int, str]:
    """The piece's width in units under ``settings``, and the control that sets it.

    Raises AppRequestError (on that control) for a width outside 2..MAX_UNITS or wider than the
    chosen machine's bed.
    """
    from illuknit.images import units_for_width
    from illuknit.knit.machine import get_machine
    from illuknit.pattern import MAX_UNITS

    if settings.size_mode == "physical":
        with blame("width_cm"):
            width = units_for_width(width_cm=settings.width_cm, gauge=settings.gauge)
        size_field = "width_cm"
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
            f"the piece would be {width} units = {2 * width} stitches wide, but the "
            f"{machine.name} bed of {machine.needles} needles holds at most {machine.max_units} "
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
    from illuknit.images import QuantisedImage
    from illuknit.single_view import prepare_single_view_image, single_view_roles

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


# -- candidates --------------------------------------------------------------------------------


@dataclass(eq=False)
class Candidate:
    """One ranked design the designer can pick: a pattern plus what produced it.

    ``source`` is what :func:`pattern_for` needs to recompile with tile overrides (the tile
    assignment for double view; None for single view, which has no tiles).
    """

    rank: int
    label: str
    score: float | None
    pattern: LogicalPattern
    details: dict[str, Any] = field(default_factory=dict)
    source: Any = None
    #: how it reads and knits (tiles.perception.CandidateMeasures), once the measures job ran
    measured: Any = None

    def to_json(self) -> dict[str, Any]:
        n, m = self.pattern.shape
        return {
            "rank": self.rank,
            "label": self.label,
            "score": None if self.score is None else round(float(self.score), 4),
            "rows": n,
            "cols": m,
            "yarns": [{"name": y.name, "rgb": y.hex} for y in self.pattern.yarns],
            "raised": int(self.pattern.raised.sum()),
            "details": self.details,
            "measures": None if self.measured is None else self.measured.to_json(),
            "editable": self.source is not None,
        }


Progress = Callable[[float, str], None]
#: The sides a pattern is seen from: A (from above), B (from below), or head-on.
View = Literal["A", "B", "headon"]


def make_candidates(prepared: Prepared, *, count: int, progress: Progress) -> list[Candidate]:
    """Ranked candidates for the prepared inputs; ``progress(fraction, message)`` may cancel."""
    if prepared.mode == "single":
        return _single_candidates(prepared, progress)
    return _tile_candidates(prepared, count=count, progress=progress)


def _single_candidates(prepared: Prepared, progress: Progress) -> list[Candidate]:
    from illuknit.single_view import compile_single_view, single_view_errors

    q = prepared.quantised["a"]
    out = []
    for k, first in enumerate(("dark", "light")):
        progress(k / 2, f"compiling single view ({first} stripe first)")
        with blame("n_colors"):
            pattern = compile_single_view(q, first=first)  # type: ignore[arg-type]
        err = [round(e, 4) for e in single_view_errors(q, pattern)]
        out.append(
            Candidate(
                rank=k + 1,
                label=f"{first} stripe first",
                score=None,
                pattern=pattern,
                details={"first": first, "mismatch_A": err[0], "mismatch_B": err[1]},
            )
        )
    return out


def _tile_candidates(prepared: Prepared, *, count: int, progress: Progress) -> list[Candidate]:
    mode = prepared.mode
    from illuknit import tiles

    qa = prepared.quantised["a"]
    qb = prepared.quantised.get("b")
    progress(0.05, "building the tile bank")
    if mode == "headon":
        bank = tiles.headon_bank(prepared.yarns)
        progress(0.15, "finding tile mappings (head-on)")
        with blame("n_colors"):
            found = tiles.assign_headon(qa, qb, bank=bank, candidates=count)
    else:
        bank = tiles.canonical_bank(prepared.yarns)
        progress(0.15, f"finding tile mappings ({len(bank)} tiles in the bank)")
        with blame("n_colors"):
            found = tiles.assign_tiles(qa, qb, bank=bank, candidates=count)
    out = []
    for k, assignment in enumerate(found):
        progress(0.6 + 0.4 * k / max(1, len(found)), f"compiling candidate {k + 1} of {len(found)}")
        with blame("tiles"):
            pattern, report = tiles.compile_tiles(assignment)
        out.append(
            Candidate(
                rank=k + 1,
                label=_assignment_label(assignment),
                score=float(assignment.score),
                pattern=pattern,
                details=_assignment_details(assignment, report),
                source=assignment,
            )
        )
    return out


def _assignment_label(assignment: Any) -> str:
    kinds = [f.kind for f in (*assignment.fills_a, *assignment.fills_b) if f is not None]
    stripes = sum(k != "solid" for k in kinds)
    return (
        "all solid fills" if not stripes else f"{stripes} striped fill{'s' if stripes > 1 else ''}"
    )


def _assignment_details(assignment: Any, report: Any) -> dict[str, Any]:
    rep = report.to_json()
    return {
        "views": list(assignment.views),
        "fills": assignment.describe(),
        "error_original": rep["error_original"],
        "delta_e_original": rep["delta_e_original"],
        "color_changes_per_course": rep["color_changes_per_course"],
        "cost": {k: round(float(v), 3) for k, v in assignment.cost.items()},
    }


def _override_tile(assignment: Any, tile_id: str) -> Any:
    """A bank tile by its number (as the page sends it), or any tile by its rows (``"0/1^"``)."""
    from illuknit.tiles.tile import Tile

    bank = assignment.bank
    if tile_id.isdigit():
        k = int(tile_id)
        if not 0 <= k < len(bank.tiles):
            raise AppRequestError(
                f"tile {tile_id} is not in the bank (it has {len(bank.tiles)} tiles)",
                field="tiles",
                code="unknown",
                status=404,
            )
        return bank.tiles[k]
    with blame("tiles"):
        return Tile.from_rows(tile_id.split("/"))


def pattern_for(candidate: Candidate, overrides: dict[tuple[int, int], str]) -> LogicalPattern:
    """The candidate's pattern with the designer's per-pair tile overrides applied."""
    if not overrides:
        return candidate.pattern
    if candidate.source is None:
        raise AppRequestError(
            "this candidate has no tiles to edit", field="tiles", code="not_editable", status=409
        )
    from illuknit import tiles

    assignment = candidate.source
    chosen = {pair: _override_tile(assignment, t) for pair, t in overrides.items()}
    for pair in chosen:
        if pair not in assignment.tiles:
            raise AppRequestError(
                f"colour {pair[0]} of A never lies over colour {pair[1]} of B in these pictures; "
                f"occurring pairs: {', '.join(f'{a}/{b}' for a, b in assignment.pairs)}",
                field="tiles",
                code="no_pair",
                status=404,
            )
    with blame("tiles"):
        pattern, _ = tiles.compile_tiles(assignment, overrides=chosen)
    return pattern


def _bank_number(bank: Any, tile: Any) -> str | None:
    for k, t in enumerate(bank.tiles):
        if t == tile:
            return str(k)
    return None


def _fills_label(views: tuple[str, str], f0: Any, f1: Any, yarns: tuple[Yarn, ...]) -> str:
    """What a tile shows from each view, e.g. ``"A: black · B: 1/1 stripes"``."""
    labels = ["—" if f is None else str(f.label(yarns)) for f in (f0, f1)]
    return f"{views[0]}: {labels[0]} · {views[1]}: {labels[1]}"


def pairs_json(candidate: Candidate, overrides: dict[tuple[int, int], str]) -> dict[str, Any]:
    """The overlap pairs of a candidate with their tiles and the bank's alternatives.

    Options per pair, best first: tiles showing exactly the assigned fills, then tiles keeping
    one side's fill, then the rest of the bank (each labelled with what it shows from each view).
    """
    if candidate.source is None:
        return {
            "editable": False,
            "pairs": [],
            "reason": "Single-view patterns are compiled row by row (paper Fig. 7), not from tiles.",
        }
    assignment = candidate.source
    bank = assignment.bank
    v0, v1 = assignment.views
    yarns = assignment.yarns
    from illuknit.tiles.assign import overlap_pairs

    counts = overlap_pairs(assignment.indices_a, assignment.indices_b)
    total = max(1, sum(counts.values()))
    index = bank.index(assignment.views)
    out = []
    for a, b in assignment.pairs:
        fa, fb = assignment.fills_a[a], assignment.fills_b[b]
        default_tile = assignment.tiles[a, b]
        default_id = _bank_number(bank, default_tile) or default_tile.code()
        current = overrides.get((a, b), default_id)
        exact = set(index.get((fa, fb), ()))
        ranked: list[tuple[int, int]] = []
        for k, fills in enumerate(bank.fills):
            f0, f1 = fills.get(v0), fills.get(v1)
            if f0 is None or f1 is None:
                continue
            tier = 0 if k in exact else 1 if (f0 == fa or f1 == fb) else 2
            ranked.append((tier, k))
        ranked.sort()
        options = []
        for tier, k in ranked[:80]:
            fills = bank.fills[k]
            mark = "★ " if tier == 0 else ""
            options.append(
                {
                    "id": str(k),
                    "label": f"{mark}{bank.tiles[k].code()} — "
                    + _fills_label((v0, v1), fills.get(v0), fills.get(v1), yarns),
                    "exact": tier == 0,
                }
            )
        for tid in dict.fromkeys((current, default_id)):
            # the candidate's own tile, or the designer's typed one, may not be a bank tile
            if tid not in {o["id"] for o in options}:
                tile = _override_tile(assignment, tid)
                fills = bank.fills_of(tile)
                own = tid == default_id
                options.insert(
                    0,
                    {
                        "id": tid,
                        "label": f"{'★ ' if own else ''}{tile.code()} — "
                        + _fills_label((v0, v1), fills.get(v0), fills.get(v1), yarns)
                        + ("" if own else " (typed)"),
                        "exact": own,
                    },
                )
        out.append(
            {
                "a": a,
                "b": b,
                "a_color": hex_color(assignment.colors_a[a]),
                "b_color": hex_color(assignment.colors_b[b]),
                "share": round(counts.get((a, b), 0) / total, 4),
                "fills": _fills_label((v0, v1), fa, fb, yarns),
                "tile": current,
                "tile_picture": f"tile.png?{urlencode({'tile': current})}",
                "default": default_id,
                "overridden": (a, b) in overrides,
                "options": options,
            }
        )
    return {"editable": True, "views": [v0, v1], "pairs": out}


def tile_png(tile_id: str, candidate: Candidate | None = None) -> bytes:
    """A picture of one tile: its units in yarn colours, raised units marked, a few periods."""
    from illuknit.previews import chart_rgb

    if candidate is None or candidate.source is None:
        raise AppRequestError(
            "pick a tile-based candidate first", field="tiles", code="not_editable", status=409
        )
    tile = _override_tile(candidate.source, tile_id)
    yarns = candidate.source.yarns
    reps = (max(1, 6 // tile.height), max(1, 6 // tile.width))
    yarn = np.tile(tile.yarn, reps)
    raised = np.tile(tile.raised, reps)
    pat = LogicalPattern(yarn, raised, yarns)
    return png_bytes(chart_rgb(pat, scale=8))


# -- rendering ---------------------------------------------------------------------------------


def render_view(pattern: LogicalPattern, view: View, *, angle: float) -> NDArray[np.uint8]:
    """(H, W, 3) uint8 picture of ``view`` ("A", "B", "headon") at elevation ``angle`` degrees.

    The angled renderer, supersampled along the wales and widened by the same factor so that the
    picture has square pixels and shows sub-unit coverage.
    """
    if not 0 < angle <= 90:
        raise AppRequestError(
            f"the viewing angle must be in (0, 90] degrees, got {angle}",
            field="angle",
            code="range",
        )
    if view not in ("A", "B", "headon"):
        raise AppRequestError(
            f"view must be A, B or headon, got {view!r}", field="view", code="range"
        )
    from illuknit.render import render_pattern

    ss = int(min(6, max(1, round(360 / max(pattern.shape)))))
    with blame("angle"):
        img = render_pattern(pattern, view=view, angle=angle, supersample=ss)
    return np.repeat(np.asarray(img, dtype=np.uint8), ss, axis=1)


def png_bytes(rgb: NDArray[np.uint8]) -> bytes:
    """Fast PNG encoding for live previews (low compression: these are tiny and short-lived)."""
    from illuknit.previews import png_bytes as encode

    return encode(rgb, compress_level=1)


# -- downloads ---------------------------------------------------------------------------------


def pattern_json_bytes(pattern: LogicalPattern) -> bytes:
    import json

    return (json.dumps(pattern_to_json(pattern), indent=1) + "\n").encode()


def previews_zip(pattern: LogicalPattern, prepared: Prepared | None, *, angle: float) -> bytes:
    """A zip of the library's previews (chart, side views, contact sheet) plus angled renders."""
    from illuknit.previews import upscale, write_previews

    targets = {}
    if prepared is not None:
        for slot, q in prepared.quantised.items():
            targets[f"quantised {slot.upper()}"] = q.rgb()
    buf = io.BytesIO()
    with tempfile.TemporaryDirectory(prefix="illuknit-previews-") as tmp:
        paths = write_previews(pattern, tmp, targets=targets)
        with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as zf:
            for name, path in paths.items():
                zf.write(path, f"previews/{os.path.basename(path) or name}")
            # write_previews renders at the calibrated angle; add the angle the page shows
            for view in ("A", "B"):
                img = render_view(pattern, view, angle=angle)
                s = max(1, 640 // max(img.shape[:2]))
                zf.writestr(f"previews/render_{view}_{angle:g}deg.png", png_bytes(upscale(img, s)))
    return buf.getvalue()


def chart_png(pattern: LogicalPattern) -> bytes:
    from illuknit.chart import chart_png_rgb

    return png_bytes(chart_png_rgb(pattern))


def instructions_text(pattern: LogicalPattern) -> str:
    from illuknit.chart import written_instructions

    return written_instructions(pattern)


def pattern_key(pattern: LogicalPattern) -> str:
    import hashlib

    h = hashlib.sha1()
    h.update(np.ascontiguousarray(pattern.yarn).tobytes())
    h.update(np.ascontiguousarray(pattern.raised).tobytes())
    h.update(repr(pattern.shape).encode())
    h.update(repr([y.rgb for y in pattern.yarns]).encode())
    return h.hexdigest()[:16]
