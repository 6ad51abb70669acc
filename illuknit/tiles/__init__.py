"""Tiles, tile banks, tile assignment and compilation: the double-view design framework.

Pipeline (paper sections 4.2 and 6)::

    canonical_bank(yarns) -> assign_tiles(qa, qb, bank=...) -> [TileAssignment, ...]
                          -> compile_tiles(assignment) -> (LogicalPattern, TileReport)

The head-on variant (Fig. 17) is :func:`illuknit.tiles.headon.assign_headon`.
"""

from __future__ import annotations

from illuknit.lazy import lazy_api

_API: dict[str, str] = {
    "Fill": "illuknit.tiles.tile",
    "Tile": "illuknit.tiles.tile",
    "tile_fills": "illuknit.tiles.tile",
    "tile_seen": "illuknit.tiles.tile",
    "TileBank": "illuknit.tiles.bank",
    "canonical_bank": "illuknit.tiles.bank",
    "extend_bank": "illuknit.tiles.bank",
    "load_bank": "illuknit.tiles.bank",
    "save_bank": "illuknit.tiles.bank",
    "bank_from_json": "illuknit.tiles.bank",
    "bank_to_json": "illuknit.tiles.bank",
    "TileAssignment": "illuknit.tiles.assignment",
    "assign_tiles": "illuknit.tiles.assign",
    "TileReport": "illuknit.tiles.compile",
    "compile_tiles": "illuknit.tiles.compile",
    "repainted_indices": "illuknit.tiles.compile",
    "repainted_rgb": "illuknit.tiles.compile",
    "align_phases": "illuknit.tiles.phases",
    "AssignmentWeights": "illuknit.tiles.assignment",
    "assign_headon": "illuknit.tiles.headon",
    "headon_bank": "illuknit.tiles.headon",
    "Suggestion": "illuknit.tiles.simplify",
    "suggest_edits": "illuknit.tiles.simplify",
    "review_edits": "illuknit.tiles.simplify",
}

__all__ = list(_API)


__getattr__, __dir__ = lazy_api(__name__, _API)
