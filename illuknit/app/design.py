"""The app's design pipeline: the library stages the page drives, in the order a designer uses them.

    uploaded file -> decode_upload -> prepare_inputs (resize to units, quantise to yarns, legend)
                  -> make_candidates (single view: both stripe orders; double view / head-on:
                     ranked tile mappings) -> pattern_for (with per-pair tile overrides)
                  -> render_view (the angled renderer)
                  -> downloads (pattern JSON, previews, chart, instructions, knitout + check)

Each job has its module: :mod:`~illuknit.app.inputs` (uploads, sizing, quantisation),
:mod:`~illuknit.app.candidates`, :mod:`~illuknit.app.tile_edits` (the tile table and overrides),
:mod:`~illuknit.app.suggestions` (suggested edits of the pictures), :mod:`~illuknit.app.exports`
(renders and downloads). This module is their one front door, as the routers and scripts use it.

Everything here is a plain function of its inputs (no session, no HTTP), so the server stays a thin
layer and these functions are testable on their own. Library errors are re-raised as
:class:`AppRequestError` naming the page control (``field``) that caused them
(:func:`~illuknit.app.controls.blame`), which is what lets the page show the message next to
that control.

Every library part used here is imported directly: an import error in illuknit's own code is a
bug to see, never a feature to grey out.
"""

from __future__ import annotations

import importlib

from illuknit.app.candidates import Candidate, Progress, make_candidates
from illuknit.app.controls import blame
from illuknit.app.exports import (
    View,
    chart_png,
    instructions_text,
    pattern_json_bytes,
    pattern_key,
    png_bytes,
    previews_zip,
    render_view,
)
from illuknit.app.inputs import (
    MAX_UPLOAD_BYTES,
    MAX_UPLOAD_PIXELS,
    MAX_WORKING_SIDE,
    Prepared,
    decode_upload,
    prepare_inputs,
    size_inputs,
    slots_for,
    too_large_message,
    width_of,
    yarns_for_colors,
)
from illuknit.app.tile_edits import pairs_json, pattern_for, tile_png
from illuknit.core.errors import AppRequestError
from illuknit.core.pattern import pattern_to_json

__all__ = [
    "MAX_UPLOAD_BYTES",
    "MAX_UPLOAD_PIXELS",
    "MAX_WORKING_SIDE",
    "YARN_PRESETS",
    "AppRequestError",
    "Candidate",
    "Prepared",
    "Progress",
    "View",
    "blame",
    "capabilities",
    "chart_png",
    "decode_upload",
    "instructions_text",
    "make_candidates",
    "pairs_json",
    "pattern_for",
    "pattern_json_bytes",
    "pattern_key",
    "pattern_to_json",
    "png_bytes",
    "prepare_inputs",
    "previews_zip",
    "render_view",
    "size_inputs",
    "slots_for",
    "tile_png",
    "too_large_message",
    "warm_up",
    "width_of",
    "yarns_for_colors",
]

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
        "illuknit.pictures.images",
        "skimage.transform",
        "scipy.optimize",
        "illuknit.design.single_view",
        "illuknit.outputs.previews",
        "illuknit.design.render",
        "illuknit.design.tiles.assign",
        "illuknit.design.tiles.compile",
        "illuknit.design.tiles.headon",
        "ortools.sat.python.cp_model",
    ):
        importlib.import_module(name)
