"""Tiles, tile banks, tile assignment and compilation: the double-view design framework.

Pipeline (paper sections 4.2 and 6)::

    canonical_bank(yarns) -> assign_tiles(qa, qb, bank=...) -> [TileAssignment, ...]
                          -> compile_tiles(assignment) -> (LogicalPattern, TileReport)

The head-on variant (Fig. 17) is :func:`illuknit.design.tiles.headon.assign_headon`; designs a
hand knitter works one yarn a row come from :func:`illuknit.design.tiles.stripes.stripe_bank`.
"""

from __future__ import annotations

from illuknit.core.lazy import lazy_api

_API: dict[str, str] = {
    "Fill": "illuknit.design.tiles.tile",
    "Tile": "illuknit.design.tiles.tile",
    "tile_fills": "illuknit.design.tiles.tile",
    "tile_seen": "illuknit.design.tiles.tile",
    "TileBank": "illuknit.design.tiles.bank",
    "canonical_bank": "illuknit.design.tiles.bank",
    "extend_bank": "illuknit.design.tiles.bank",
    "load_bank": "illuknit.design.tiles.bank",
    "save_bank": "illuknit.design.tiles.bank",
    "bank_from_json": "illuknit.design.tiles.bank",
    "bank_to_json": "illuknit.design.tiles.bank",
    "TileAssignment": "illuknit.design.tiles.assignment",
    "assign_tiles": "illuknit.design.tiles.assign",
    "AssignOptions": "illuknit.design.tiles.assign",
    "TileReport": "illuknit.design.tiles.compile",
    "compile_tiles": "illuknit.design.tiles.compile",
    "repainted_indices": "illuknit.design.tiles.compile",
    "repainted_rgb": "illuknit.design.tiles.compile",
    "align_phases": "illuknit.design.tiles.phases",
    "AssignmentWeights": "illuknit.design.tiles.assignment",
    "assign_headon": "illuknit.design.tiles.headon",
    "headon_bank": "illuknit.design.tiles.headon",
    "stripe_bank": "illuknit.design.tiles.stripes",
    "search_stripes": "illuknit.design.tiles.stripes",
    "Suggestion": "illuknit.design.tiles.simplify",
    "suggest_edits": "illuknit.design.tiles.simplify",
    "review_edits": "illuknit.design.tiles.simplify",
}

__all__ = list(_API)


__getattr__, __dir__ = lazy_api(__name__, _API)
