"""Compile a tile assignment into a logical pattern, and measure how well it shows the inputs.

Every pixel ``(r, c)`` belongs to an overlap pair ``(a, b)`` and takes the unit
``tile[r mod h, c mod w]`` of that pair's tile. The phase comes from the *global* row and column,
so a region's stripes continue across the whole piece and form unbroken courses, and two regions
that use tiles of the same height stay in step.

The *repainted* inputs are what the assignment promises: for each pixel, the yarn its pair's
bank tile shows in that view at that phase (a stripe, course by course), or, for pictures, the
average colour of the colour's fill. Inside a region the compiled pattern reproduces the
repainted images exactly; it can differ only within one tile height of a vertical region
boundary, where a unit sees its neighbour from another region. :class:`TileReport` gives the
logical error against the repainted images (everywhere and away from boundaries), against the
original inputs (nearest yarn of each picture colour, and mean CIELAB ΔE), and the colour changes
per course that the knitting will need.
"""

from __future__ import annotations

import numbers
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from illuknit.core.arguments import check_instance, check_mapping, check_str, got
from illuknit.core.colors import lab_from_rgb
from illuknit.core.errors import TileAssignmentError
from illuknit.core.pattern import LogicalPattern
from illuknit.core.views import can_see, logical_error
from illuknit.design.tiles.assignment import TileAssignment
from illuknit.design.tiles.tile import Tile, tile_seen

__all__ = [
    "TileReport",
    "boundary_mask",
    "compile_tiles",
    "repainted_indices",
    "repainted_rgb",
    "view_inputs",
]

SeenView = Literal["A", "B", "headon"]


def view_inputs(views: tuple[str, str]) -> dict[SeenView, int]:
    """Which input (0 or 1) each physical view should show: ``("A","B") -> {A: 0, B: 1}``,
    ``("headon","side") -> {headon: 0, A: 1, B: 1}``."""
    out: dict[SeenView, int] = {}
    for k, v in enumerate(views):
        if v == "side":
            out["A"] = k
            out["B"] = k
        else:
            out[v] = k  # type: ignore[index]
    return out


def _pair_code(assignment: TileAssignment) -> tuple[NDArray[np.int64], int]:
    kb = len(assignment.colors_b)
    return assignment.indices_a.astype(np.int64) * kb + assignment.indices_b, kb


def _place(
    shape: tuple[int, int],
    code: NDArray[np.int64],
    kb: int,
    per_pair: Mapping[tuple[int, int], NDArray[Any]],
) -> NDArray[Any]:
    """Lay each pair's (h, w) block periodically over its pixels, phase from global row/col."""
    n, m = shape
    first = next(iter(per_pair.values()))
    out = np.zeros((n, m), dtype=first.dtype)
    rows = np.broadcast_to(np.arange(n)[:, None], (n, m))
    cols = np.broadcast_to(np.arange(m)[None, :], (n, m))
    for (a, b), block in per_pair.items():
        mask = code == a * kb + b
        if not mask.any():
            continue
        h, w = block.shape
        out[mask] = block[rows[mask] % h, cols[mask] % w]
    return out


def _bank_tiles(assignment: TileAssignment) -> dict[tuple[int, int], Tile]:
    """The tile each pair was assigned before overrides (what the repainted images promise)."""
    return {p: assignment.promised.get(p, assignment.tiles[p]) for p in assignment.pairs}


def repainted_indices(assignment: TileAssignment, view: SeenView) -> NDArray[np.int16]:
    """ndarray of shape (N, M): the yarn each pixel should show from ``view`` ("A", "B" or
    "headon"), stripes included, as promised by the assigned fills."""
    if view not in ("A", "B", "headon"):
        raise TileAssignmentError(f"`view` must be 'A', 'B' or 'headon', got {view!r}")
    code, kb = _pair_code(assignment)
    seen = {p: tile_seen(t, view) for p, t in _bank_tiles(assignment).items()}
    return _place(assignment.shape, code, kb, seen).astype(np.int16)


def repainted_rgb(
    assignment: TileAssignment, which: int, *, mode: Literal["stripes", "average"] = "stripes"
) -> NDArray[np.uint8]:
    """The repainted input ``which`` (0 = first input, 1 = second) as an (N, M, 3) uint8 picture.

    ``mode="stripes"`` shows the yarns course by course; ``"average"`` paints each colour with
    its fill's average colour (linear-light mix), as the eye sees it from afar.
    """
    if which not in (0, 1):
        raise TileAssignmentError(f"`which` must be 0 or 1, got {which!r}")
    idx = assignment.indices_a if which == 0 else assignment.indices_b
    fills = assignment.fills_a if which == 0 else assignment.fills_b
    if mode == "average":
        pal = np.array(
            [np.round(f.rgb) if f is not None else (0, 0, 0) for f in fills], dtype=np.uint8
        )
        return pal[idx]
    if mode != "stripes":
        raise TileAssignmentError(f"`mode` must be 'stripes' or 'average', got {mode!r}")
    view = assignment.views[which]
    seen: SeenView = "A" if view == "side" else view
    pal = np.array([y.rgb for y in assignment.yarns], dtype=np.uint8)
    return pal[repainted_indices(assignment, seen)]


def boundary_mask(assignment: TileAssignment, *, reach: int | None = None) -> NDArray[np.bool_]:
    """ndarray of shape (N, M), True where a pixel lies within ``reach`` rows (default: the
    tallest tile used) of a pixel of another overlap pair in the same column, or of the top or
    bottom edge (where the first and last rows have no neighbour to be hidden by)."""
    code, _ = _pair_code(assignment)
    if reach is None:
        reach = max(t.height for t in assignment.tiles.values())
    near = np.zeros(code.shape, dtype=bool)
    near[:reach] = True
    near[-reach:] = True
    for d in range(1, reach + 1):
        diff = code[d:] != code[:-d]
        near[d:] |= diff
        near[:-d] |= diff
    return near


@dataclass(frozen=True)
class TileReport:
    """How a compiled tile pattern reproduces its inputs.

    Attributes
    ----------
    error_repainted : mapping view -> float
        Fraction of units whose seen yarn differs from the repainted image, per view.
    error_repainted_interior : mapping view -> float
        The same, away from region boundaries (zero for a correct compile without overrides).
    error_original : mapping view -> float
        Fraction of units whose seen yarn is not the yarn nearest to the original colour.
    delta_e_original : mapping view -> float
        Mean CIELAB ΔE between seen yarn colour and original colour.
    color_changes : ndarray of shape (N,)
        Yarn changes along each course (row), left to right.
    yarns_per_course : ndarray of shape (N,)
        Distinct yarns in each course.
    overrides : tuple of dict
        Per overridden pair: the tile and whether it still shows the assigned fills.
    """

    error_repainted: Mapping[str, float]
    error_repainted_interior: Mapping[str, float]
    error_original: Mapping[str, float]
    delta_e_original: Mapping[str, float]
    color_changes: NDArray[np.int64]
    yarns_per_course: NDArray[np.int64]
    tiles: Mapping[str, str] = field(default_factory=dict)
    overrides: tuple[Mapping[str, Any], ...] = ()

    def __post_init__(self) -> None:
        for k in (
            "error_repainted",
            "error_repainted_interior",
            "error_original",
            "delta_e_original",
            "tiles",
        ):
            object.__setattr__(self, k, MappingProxyType(dict(getattr(self, k))))

    def to_json(self) -> dict[str, Any]:
        return {
            "error_repainted": {k: round(v, 5) for k, v in self.error_repainted.items()},
            "error_repainted_interior": {
                k: round(v, 5) for k, v in self.error_repainted_interior.items()
            },
            "error_original": {k: round(v, 5) for k, v in self.error_original.items()},
            "delta_e_original": {k: round(v, 3) for k, v in self.delta_e_original.items()},
            "color_changes_per_course": {
                "max": int(self.color_changes.max(initial=0)),
                "mean": round(
                    float(self.color_changes.mean()) if self.color_changes.size else 0.0, 3
                ),
            },
            "yarns_per_course": {
                "max": int(self.yarns_per_course.max(initial=0)),
                "mean": round(
                    float(self.yarns_per_course.mean()) if self.yarns_per_course.size else 0.0, 3
                ),
            },
            "tiles": dict(self.tiles),
            "overrides": [dict(o) for o in self.overrides],
        }


def compile_tiles(
    assignment: TileAssignment,
    *,
    overrides: Mapping[tuple[int, int], Tile | str] | None = None,
    name: str = "tiles",
) -> tuple[LogicalPattern, TileReport]:
    """Lay the tiles of ``assignment`` over the overlap map.

    Parameters
    ----------
    assignment : TileAssignment
        From :func:`~illuknit.design.tiles.assign.assign_tiles` (possibly with overrides of its own).
    overrides : mapping (a, b) -> Tile or rows string like ``"0/1/0^"``, optional
        Per-pair tiles chosen by the designer; applied on top of the assignment's.
    name : str
        Recorded in the pattern's meta.

    Returns
    -------
    pattern : LogicalPattern
        Of shape (N, M), over the bank's yarns.
    report : TileReport
    """
    check_instance(assignment, TileAssignment, "assignment", error=TileAssignmentError)
    if overrides is not None:
        _check_overrides(check_mapping(overrides, "overrides"))
    check_str(name, "name")
    if not isinstance(assignment, TileAssignment):
        raise TileAssignmentError(
            f"`assignment` must be a TileAssignment, got {type(assignment).__name__}"
        )
    for pair, tile in (overrides or {}).items():
        assignment = assignment.with_tile(pair, tile)
    code, kb = _pair_code(assignment)
    shape = assignment.shape
    yarn = _place(shape, code, kb, {p: t.yarn for p, t in assignment.tiles.items()})
    raised = _place(shape, code, kb, {p: t.raised for p, t in assignment.tiles.items()})
    upper = None
    if any(t.upper is not None for t in assignment.tiles.values()):
        upper = _place(shape, code, kb, {p: t.upper_yarn for p, t in assignment.tiles.items()})
    meta = {
        "compiler": name,
        "views": list(assignment.views),
        "assignment": assignment.to_json(),
    }
    pattern = LogicalPattern(yarn, raised, assignment.yarns, meta, upper=upper)
    return pattern, _report(assignment, pattern)


def _check_overrides(overrides: Mapping[Any, Any]) -> None:
    """Each override an overlap pair of colour indices mapped to a Tile or a rows string."""
    for pair, tile in overrides.items():
        if not (
            isinstance(pair, tuple)
            and len(pair) == 2
            and all(isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in pair)
        ):
            raise TileAssignmentError(
                f"`overrides` keys must be overlap pairs (colour of A, colour of B), got {got(pair)}"
            )
        if not isinstance(tile, (Tile, str)):
            raise TileAssignmentError(
                f"`overrides` values must be a Tile or rows like '0/1/0^', got {got(tile)}"
            )


def _report(assignment: TileAssignment, pattern: LogicalPattern) -> TileReport:
    near = boundary_mask(assignment)
    pal = pattern.palette
    ylab = lab_from_rgb(pal.astype(np.float64))
    err_r: dict[str, float] = {}
    err_i: dict[str, float] = {}
    err_o: dict[str, float] = {}
    de_o: dict[str, float] = {}
    for view, which in view_inputs(assignment.views).items():
        seen = can_see(pattern, view)
        target = repainted_indices(assignment, view)
        err_r[view] = logical_error(seen, target)
        err_i[view] = logical_error(seen, target, mask=~near)
        idx = assignment.indices_a if which == 0 else assignment.indices_b
        colors = assignment.colors_a if which == 0 else assignment.colors_b
        clab = lab_from_rgb(colors.astype(np.float64))
        dist = np.sqrt(((clab[:, None, :] - ylab[None, :, :]) ** 2).sum(-1))  # (K, Y)
        err_o[view] = logical_error(seen, dist.argmin(axis=1)[idx])
        de_o[view] = float(dist[idx, seen].mean())
    y = pattern.yarn
    changes = (y[:, 1:] != y[:, :-1]).sum(axis=1).astype(np.int64)
    per_course = np.array([len(np.unique(row)) for row in y], dtype=np.int64)
    over = []
    for a, b in assignment.overridden:
        t = assignment.tiles[a, b]
        f = assignment.bank.fills_of(t)
        v0, v1 = assignment.views
        keeps = f.get(v0) == assignment.fills_a[a] and f.get(v1) == assignment.fills_b[b]
        over.append({"a": a, "b": b, "tile": t.code(), "keeps_fills": bool(keeps)})
    return TileReport(
        err_r,
        err_i,
        err_o,
        de_o,
        changes,
        per_course,
        {f"{a},{b}": t.code() for (a, b), t in sorted(assignment.tiles.items())},
        tuple(over),
    )
