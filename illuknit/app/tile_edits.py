"""Tile edits: the overlap pairs of a tile candidate, the bank's alternatives for each, and the
candidate recompiled with the designer's per-pair choices.

    Candidate + overrides {(a, b): tile} -> pattern_for -> LogicalPattern
    Candidate + overrides                -> pairs_json  -> what the page's tile table shows
"""

from __future__ import annotations

from typing import Any
from urllib.parse import urlencode

import numpy as np

from illuknit.app.candidates import Candidate
from illuknit.app.controls import blame
from illuknit.app.exports import png_bytes
from illuknit.core.colors import hex_color
from illuknit.core.errors import AppRequestError
from illuknit.core.pattern import LogicalPattern, Yarn

__all__ = ["pairs_json", "pattern_for", "tile_png"]


def _override_tile(assignment: Any, tile_id: str) -> Any:
    """A bank tile by its number (as the page sends it), or any tile by its rows (``"0/1^"``)."""
    from illuknit.design.tiles.tile import Tile

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
    """The candidate's pattern with the designer's per-pair tile overrides applied (the stage
    :func:`~illuknit.pipeline.stages.retile_design`; a bank number is looked up here, since
    the page names bank tiles by number)."""
    if not overrides:
        return candidate.pattern
    if candidate.source is None:
        raise AppRequestError(
            "this candidate has no tiles to edit", field="tiles", code="not_editable", status=409
        )
    from illuknit.core.errors import UnknownNameError
    from illuknit.pipeline.stages import retile_design

    assignment = candidate.source
    chosen = {pair: _override_tile(assignment, t) for pair, t in overrides.items()}
    with blame("tiles"):
        try:
            pattern, _ = retile_design(assignment, chosen)
        except UnknownNameError as e:  # a pair the pictures do not have
            raise AppRequestError(str(e), field="tiles", code="no_pair", status=404) from None
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
    """The overlap pairs of a candidate with their tiles and the bank's alternatives, grouped.

    ``pairs`` lists every pair once, in the order of ``groups`` then ``rare``
    (:func:`illuknit.design.tiles.overlaps.group_overlaps`): the pairs grouped by the fill the
    candidate shows from its first view, largest first, and the rare ones (each under 2 % of the
    units) folded into one line. Options per pair, best first: tiles showing exactly the assigned fills, then tiles keeping
    one side's fill, then the rest of the bank (each labelled with what it shows from each view).
    """
    if candidate.source is None:
        return {
            "editable": False,
            "pairs": [],
            "reason": "Single-view patterns are compiled row by row (paper Fig. 7), not from tiles.",
        }
    from illuknit.design.tiles.assign import overlap_pairs
    from illuknit.design.tiles.overlaps import group_overlaps

    assignment = candidate.source
    counts = overlap_pairs(assignment.indices_a, assignment.indices_b)
    total = max(1, sum(counts.values()))
    # grouped by the candidate's own fills, not the edited ones: a row stays where it is while
    # the designer tries tiles for it
    table = group_overlaps(assignment)
    out = [
        _pair_json(assignment, r.a, r.b, overrides, share=counts.get((r.a, r.b), 0) / total)
        for r in table.rows
    ]
    return {
        "editable": True,
        "views": list(assignment.views),
        "pairs": out,
        "groups": [
            {
                "fill": g.fill,
                "fill_color": g.fill_color,
                "share": round(g.share, 4),
                "pairs": [f"{r.a}/{r.b}" for r in g.rows],
            }
            for g in table.groups
        ],
        "rare": {
            "below": table.rare_share,
            "share": round(table.rare_fraction, 4),
            "pairs": [f"{r.a}/{r.b}" for r in table.rare],
        },
    }


def _pair_json(
    assignment: Any, a: int, b: int, overrides: dict[tuple[int, int], str], *, share: float
) -> dict[str, Any]:
    """One row of the tile table: overlap pair (a, b), its tile and the options for it."""
    views = assignment.views
    fa, fb = assignment.fills_a[a], assignment.fills_b[b]
    default_tile = assignment.tiles[a, b]
    default_id = _bank_number(assignment.bank, default_tile) or default_tile.code()
    current = overrides.get((a, b), default_id)
    return {
        "a": a,
        "b": b,
        "a_color": hex_color(assignment.colors_a[a]),
        "b_color": hex_color(assignment.colors_b[b]),
        "share": round(share, 4),
        "fills": _fills_label(views, fa, fb, assignment.yarns),
        "tile": current,
        "tile_picture": f"tile.png?{urlencode({'tile': current})}",
        "default": default_id,
        "overridden": (a, b) in overrides,
        "options": _pair_options(assignment, fa, fb, current=current, default_id=default_id),
    }


def _pair_options(
    assignment: Any, fa: Any, fb: Any, *, current: str, default_id: str
) -> list[dict[str, Any]]:
    """Tiles for a pair whose assigned fills are ``fa`` (from A) and ``fb`` (from B), best first:
    exact fills (starred), then one side's fill kept, then the rest; at most 80 from the bank,
    plus the candidate's own and the designer's typed tile when they are not bank tiles."""
    bank, yarns = assignment.bank, assignment.yarns
    v0, v1 = assignment.views
    exact = set(bank.index(assignment.views).get((fa, fb), ()))
    ranked: list[tuple[int, int]] = []
    for k, fills in enumerate(bank.fills):
        f0, f1 = fills.get(v0), fills.get(v1)
        if f0 is None or f1 is None:
            continue
        ranked.append((0 if k in exact else 1 if (f0 == fa or f1 == fb) else 2, k))
    ranked.sort()
    options = []
    for tier, k in ranked[:80]:
        fills = bank.fills[k]
        options.append(
            {
                "id": str(k),
                "label": f"{'★ ' if tier == 0 else ''}{bank.tiles[k].code()} — "
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
    return options


def tile_png(tile_id: str, candidate: Candidate | None = None) -> bytes:
    """A picture of one tile: its units in yarn colours, raised units marked, a few periods."""
    from illuknit.outputs.previews import chart_rgb

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
