"""One design measured or changed by hand: how a pattern reads, as the ranking measures it
(:func:`measure_design`), and a tile design compiled again with tile overrides
(:func:`retile_design`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Literal

from illuknit.core.errors import ImageInputError, OptionError
from illuknit.core.machine import resolve_machine
from illuknit.design.options import RankOptions
from illuknit.pipeline.inputs import check_type
from illuknit.pipeline.tile_search import knit_measure

if TYPE_CHECKING:
    from illuknit.core.pattern import LogicalPattern
    from illuknit.design.render.params import RenderParams
    from illuknit.design.tiles.assignment import TileAssignment
    from illuknit.design.tiles.compile import TileReport
    from illuknit.design.tiles.perception import CandidateMeasures
    from illuknit.design.tiles.tile import Tile
    from illuknit.pictures.images import QuantisedImage

__all__ = ["measure_design", "retile_design"]


def measure_design(
    pattern: LogicalPattern,
    mode: Literal["double", "headon", "single"],
    picture_a: QuantisedImage,
    picture_b: QuantisedImage | None = None,
    *,
    ranking: RankOptions | None = None,
    params: RenderParams | None = None,
) -> CandidateMeasures:
    """How one pattern reads, measured as the ranking of the tile stages measures its designs.

    The measures (:class:`~illuknit.design.tiles.perception.CandidateMeasures`) are taken at
    ``ranking.angle`` and ``ranking.distance`` against what each view should show: a double
    view side A ``picture_a`` and side B ``picture_b``, ghosting measured; a head-on design the
    front ``picture_a`` head-on and at an angle ``picture_b`` (or the plain field standing for
    it); a single view ``picture_a`` from both sides, nothing to ghost. With
    ``ranking.knit_time`` the machine's knitting time and passes on ``ranking.machine`` too.
    A user interface measuring a design edited by hand (a tile override) calls this.
    ``params`` (:class:`~illuknit.design.render.params.RenderParams`) are the renderer's, as a
    split-bump search measures its designs with its split share (default: the calibrated ones).
    """
    from illuknit.core.pattern import check_pattern
    from illuknit.design.tiles.perception import measure_candidate, seen_blur, seen_targets
    from illuknit.pictures.images import QuantisedImage

    check_pattern(pattern)
    ranking = RankOptions() if ranking is None else ranking
    check_type("ranking", ranking, RankOptions)
    if not isinstance(mode, str) or mode not in ("double", "headon", "single"):
        raise OptionError(f"`mode` must be double, headon or single, got {mode!r}")
    for name, q in (("picture_a", picture_a), ("picture_b", picture_b)):
        if (q is not None or name == "picture_a") and not isinstance(q, QuantisedImage):
            raise ImageInputError(f"`{name}` must be a QuantisedImage, got {type(q).__name__}")
        if q is not None and q.shape != pattern.shape:
            raise ImageInputError(
                f"`{name}` is {q.shape[0]} x {q.shape[1]} units, the pattern {pattern.shape}"
            )
    if mode == "double" and picture_b is None:
        raise ImageInputError("`picture_b`: a double-view design is measured against two pictures")
    views: tuple[str, ...] = ("A", "B")
    if mode == "double":
        pictures = [picture_a.rgb(), picture_b.rgb()]  # type: ignore[union-attr]
    elif mode == "headon":
        pictures, views = seen_targets(picture_a, picture_b), ("headon", "side")
    else:
        pictures = [picture_a.rgb(), picture_a.rgb()]
    return measure_candidate(
        pattern,
        pictures,
        views=views,
        ghost=mode != "single",
        knit_time=knit_measure(ranking),
        angle=ranking.angle,
        blur=seen_blur(ranking.distance, gauge=resolve_machine(ranking.machine).gauge),
        params=params,
    )


def retile_design(
    assignment: TileAssignment, overrides: Mapping[tuple[int, int], Tile | str]
) -> tuple[LogicalPattern, TileReport]:
    """A tile design compiled again with per-pair tile overrides: ``{(colour of A, colour of B):
    tile}``, a tile being a :class:`~illuknit.design.tiles.tile.Tile` or its rows (``"0/1/0^"``).

    Returns the pattern and the compiler's report (which says whether each override keeps the
    fills assigned to its pair).

    Raises
    ------
    UnknownNameError
        An override names a pair that never occurs in the pictures.
    TileBankError
        An override's rows are not a tile.
    """
    from illuknit.core.arguments import check_mapping
    from illuknit.design.tiles.assignment import TileAssignment
    from illuknit.design.tiles.compile import compile_tiles
    from illuknit.design.tiles.tile import Tile

    check_type("assignment", assignment, TileAssignment)
    chosen = {}
    for pair, tile in check_mapping(overrides, "overrides").items():
        if not (
            isinstance(pair, tuple)
            and len(pair) == 2
            and all(isinstance(v, int) and not isinstance(v, bool) for v in pair)
        ):
            raise OptionError(f"`overrides` keys are (colour of A, colour of B), got {pair!r}")
        if not isinstance(tile, Tile | str):
            raise OptionError(f"`overrides` tiles are Tiles or rows like '0/1^', got {tile!r}")
        if pair not in assignment.tiles:
            from illuknit.core.errors import UnknownNameError

            raise UnknownNameError(
                "overlap pair (colour of A / colour of B) in these pictures",
                f"{pair[0]}/{pair[1]}",
                [f"{a}/{b}" for a, b in assignment.pairs],
            )
        chosen[pair] = tile if isinstance(tile, Tile) else Tile.from_rows(tile.split("/"))
    return compile_tiles(assignment, overrides=chosen)
