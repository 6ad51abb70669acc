"""The tile stages: double-view designs (paper section 6) and head-on designs (paper Fig. 17),
from pictures (:func:`design_double`, :func:`design_headon`) or from pictures already quantised
(:func:`design_tiles`, what the app calls)."""

from __future__ import annotations

import os
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Literal

from illuknit.core.errors import ImageInputError, OptionError, YarnSpecError
from illuknit.core.machine import MachineSpec
from illuknit.design.options import RankOptions, SearchOptions
from illuknit.pipeline.designs import Picture, Progress, TileDesign
from illuknit.pipeline.inputs import (
    PictureOptions,
    check_bank,
    check_fits,
    check_picture,
    check_sizes,
    check_type,
    check_yarns,
    fit_machine,
    fit_notes,
    picture_options,
    unit_aspect_or_default,
)
from illuknit.pipeline.tile_search import TileJob, rank_tiles, search_tiles

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from illuknit.core.pattern import Yarn
    from illuknit.design.tiles.bank import TileBank, ViewPair
    from illuknit.pictures.images import QuantisedImage

__all__ = ["TILE_PICTURE_OPTIONS", "design_double", "design_headon", "design_tiles"]


def _tile_yarns(
    yarns: Sequence[Yarn] | int | None, n_colors: int, pictures: list[NDArray[np.float64]]
) -> tuple[Yarn, ...]:
    """The bank's yarns: given, or ``yarns`` (default ``n_colors``) chosen from the pictures."""
    if yarns is not None and not isinstance(yarns, int):
        from illuknit.core.pattern import Yarn

        ys = tuple(yarns)
        if not ys or not all(isinstance(y, Yarn) for y in ys):
            raise YarnSpecError("`yarns` must be a number of yarns or a sequence of Yarn")
        return ys
    n = n_colors if yarns is None else yarns
    if isinstance(n, bool) or not 1 <= n <= 8:
        raise YarnSpecError(f"`yarns` must be between 1 and 8 yarns, got {n}")
    from illuknit.design.tiles.yarn_choice import choose_yarns

    return choose_yarns(pictures, n)


#: What the tile stages read of :class:`~illuknit.pipeline.inputs.PictureOptions`.
TILE_PICTURE_OPTIONS = ("width", "stretch", "unit_aspect", "n_colors", "yarns")


@dataclass(frozen=True, eq=False)
class _TileSearch:
    """What a tile stage hands on to :func:`design_tiles` unchanged: the bank, the search and
    ranking options, and who hears progress."""

    bank: TileBank | str | os.PathLike[str] | None
    search: SearchOptions | None
    ranking: RankOptions | None
    progress: Progress | None


def design_double(
    picture_a: Picture,
    picture_b: Picture,
    *,
    pictures: PictureOptions | None = None,
    bank: TileBank | str | os.PathLike[str] | None = None,
    search: SearchOptions | None = None,
    ranking: RankOptions | None = None,
    knit_on: str | MachineSpec | None = None,
    progress: Progress | None = None,
    **knobs: Any,
) -> TileDesign:
    """Ranked double-view tile designs: ``picture_a`` seen from above, ``picture_b`` from below.

    The pictures (``pictures``, :class:`~illuknit.pipeline.inputs.PictureOptions`, or its fields
    as keywords: ``width``, ``stretch``, ``unit_aspect``, ``n_colors``, ``yarns``) are sized to
    one unit grid (:func:`~illuknit.pictures.sizing.size_pair`: ``width`` units, at most 80 by
    default; ``stretch`` a B of another shape onto A's), each quantised to ``n_colors`` colours
    (default 2); the bank (default: the canonical bank) is made of ``yarns`` (a sequence of
    Yarn, or how many to choose from the pictures; default ``n_colors``). Tile assignments are
    searched (``search``) and ranked (``ranking``). With ``knit_on`` (a machine name or spec) a
    pattern wider than its bed is refused before any design work.

    Raises
    ------
    TileAssignmentError
        No assignment exists (the message says which overlap pairs cannot be realised).
    SchedulingError
        The pattern is wider than ``knit_on``'s bed.
    """
    opts = picture_options(pictures, knobs, takes=TILE_PICTURE_OPTIONS)
    tiles = _TileSearch(bank, search, ranking, progress)
    return _design_pictures("double", (picture_a, picture_b), opts, knit_on, tiles)


def design_headon(
    front: Picture,
    side: Picture | None = None,
    *,
    pictures: PictureOptions | None = None,
    bank: TileBank | str | os.PathLike[str] | None = None,
    search: SearchOptions | None = None,
    ranking: RankOptions | None = None,
    knit_on: str | MachineSpec | None = None,
    progress: Progress | None = None,
    **knobs: Any,
) -> TileDesign:
    """Ranked head-on tile designs: ``front`` seen looking straight at the fabric, ``side`` (or
    a plain field when None) at an angle from either end. Options as :func:`design_double`."""
    opts = picture_options(pictures, knobs, takes=TILE_PICTURE_OPTIONS)
    tiles = _TileSearch(bank, search, ranking, progress)
    return _design_pictures("headon", (front, side), opts, knit_on, tiles)


def _design_pictures(
    mode: Literal["double", "headon"],
    given: tuple[Picture, Picture | None],
    opts: PictureOptions,
    knit_on: str | MachineSpec | None,
    tiles: _TileSearch,
) -> TileDesign:
    """Size, quantise and choose the yarns, then :func:`design_tiles`."""
    from illuknit.core.arguments import check_bool, check_callable, check_int
    from illuknit.pictures.images import quantise_image
    from illuknit.pictures.sizing import size_pair

    picture_a, picture_b = given
    n_colors = 2 if opts.n_colors is None else opts.n_colors
    check_callable(tiles.progress, "progress")
    names = ("picture_a", "picture_b") if mode == "double" else ("front", "side")
    check_picture(picture_a, names[0])
    check_picture(picture_b, names[1], optional=mode == "headon")
    check_int(n_colors, "n_colors", min=1, max=8)
    check_yarns(opts.yarns, count_ok=True)
    check_sizes(width=opts.width)
    check_bool(opts.stretch, "stretch")
    check_bank(tiles.bank)
    machine = fit_machine(knit_on)
    check_fits(machine, opts.width)
    pair = size_pair(
        picture_a,
        picture_b,
        width=opts.width,
        stretch=opts.stretch,
        unit_aspect=unit_aspect_or_default(opts.unit_aspect),
    )
    a, b = pair.a, pair.b
    check_fits(machine, a.shape[1])
    sized = [a] if b is None else [a, b]
    ys = _tile_yarns(opts.yarns, n_colors, sized)
    qa = quantise_image(a, n_colors=n_colors)
    qb = quantise_image(b, n_colors=n_colors) if b is not None else None
    design = design_tiles(
        qa,
        qb,
        mode=mode,
        yarns=ys,
        sources=(a, b) if b is not None else None,
        edit_colors=min(4, max(n_colors, len(ys))),
        bank=tiles.bank,
        search=tiles.search,
        ranking=tiles.ranking,
        progress=tiles.progress,
    )
    notes = fit_notes(knit_on if knit_on is not None else design.ranking.machine, a.shape[1])
    return replace(_with_pictures(design, tuple(sized)), notes=notes)


def _with_pictures(design: TileDesign, pictures: tuple[NDArray[np.float64], ...]) -> TileDesign:
    return replace(design, pictures=pictures)


def design_tiles(
    qa: QuantisedImage,
    qb: QuantisedImage | None = None,
    *,
    mode: Literal["double", "headon"] = "double",
    yarns: Sequence[Yarn] | None = None,
    bank: TileBank | str | os.PathLike[str] | None = None,
    search: SearchOptions | None = None,
    ranking: RankOptions | None = None,
    progress: Progress | None = None,
    **edit_inputs: Any,
) -> TileDesign:
    """Ranked tile designs of pictures already quantised (:func:`~illuknit.pictures.images.quantise_image`).

    ``mode="double"``: ``qa`` from above, ``qb`` from below; ``"headon"``: ``qa`` head-on,
    ``qb`` (or a plain field when None) at an angle. ``bank`` is a TileBank, a bank file
    (:func:`~illuknit.design.tiles.bank.load_bank`, read with ``yarns``) or None: the canonical bank of
    ``yarns`` (default: the pictures' yarns) for those views. Simplifying edits
    (``search.edits``) take two keywords more: they need the unquantised ``sources`` (the
    pictures A and B) and re-quantise to at most ``edit_colors`` colours (default: the number
    of yarns, at most 4).
    """
    from illuknit.core.arguments import check_callable, check_choice, check_int
    from illuknit.design.tiles.bank import canonical_bank, load_bank
    from illuknit.design.tiles.headon import HEADON_VIEWS
    from illuknit.pictures.images import QuantisedImage

    search = SearchOptions() if search is None else search
    ranking = RankOptions() if ranking is None else ranking
    check_type("search", search, SearchOptions)
    check_type("ranking", ranking, RankOptions)
    check_choice(mode, "mode", ("double", "headon"))
    check_callable(progress, "progress")
    for name, q in (("qa", qa), ("qb", qb)):
        if (q is not None or name == "qa") and not isinstance(q, QuantisedImage):
            raise ImageInputError(f"`{name}` must be a QuantisedImage, got {type(q).__name__}")
    check_yarns(yarns, count_ok=False)
    check_bank(bank)
    sources, edit_colors = _edit_inputs(edit_inputs)
    if sources is not None and not (isinstance(sources, (tuple, list)) and len(sources) == 2):
        raise ImageInputError("`sources` must be the two unquantised pictures (A, B)")
    if edit_colors is not None:
        check_int(edit_colors, "edit_colors", min=1, max=8)
    if mode == "double" and qb is None:
        raise ImageInputError("`qb` is needed: a double-view design has two pictures (A and B)")
    say = progress or (lambda _f, _m: None)
    views: ViewPair = ("A", "B") if mode == "double" else HEADON_VIEWS
    ys = tuple(yarns) if yarns is not None else _picture_yarns(qa, qb)
    say(0.05, "building the tile bank")
    if bank is not None and search.split_bumps:
        raise OptionError(
            "split bumps extend the canonical bank; a bank of your own lists its tiles "
            "(write a split bump as 1^0: yarn 1, then yarn 0)"
        )
    own_bank = bank is None
    if bank is None:
        bank = canonical_bank(
            ys,
            views=views,
            one_sided_stripes=search.one_sided,
            split_bumps=search.split_bumps,
            split_share=search.split_share,
        )
    elif isinstance(bank, (str, os.PathLike)):
        bank = load_bank(bank, yarns=ys)
    job = TileJob(qa, qb, mode, views, ys, bank, search, ranking, say, own_bank)
    t0 = time.perf_counter()
    found, edits = search_tiles(job, sources, edit_colors or len(ys))
    t1 = time.perf_counter()
    design = rank_tiles(job, found, edits)
    seconds = {"search": t1 - t0, "rank": time.perf_counter() - t1}
    return replace(design, seconds=MappingProxyType(seconds))


def _edit_inputs(given: dict[str, Any]) -> tuple[Any, Any]:  # checked by design_tiles
    """``sources`` and ``edit_colors`` of :func:`design_tiles` (None when not given); any other
    keyword is refused by name."""
    unknown = sorted(set(given) - {"sources", "edit_colors"})
    if unknown:
        raise OptionError(f"unknown option {unknown[0]!r} of design_tiles; valid: sources, edit_colors "
                          "besides its parameters")  # fmt: skip
    return given.get("sources"), given.get("edit_colors")


def _picture_yarns(qa: QuantisedImage, qb: QuantisedImage | None) -> tuple[Yarn, ...]:
    ys = dict.fromkeys((*qa.yarns, *(qb.yarns if qb is not None else ())))
    return tuple(ys)
