"""Searching and ranking tile designs: the tile assignments of a pair of quantised pictures
(after the simplifying edits), compiled, measured and ranked into a
:class:`~illuknit.pipeline.designs.TileDesign`."""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Literal

from illuknit.core.errors import OptionError
from illuknit.core.machine import resolve_machine
from illuknit.design.options import MadeFor, PictureEdits, RankBy, RankOptions, SearchOptions
from illuknit.design.rank_choice import RankChoice
from illuknit.design.tiles.perception import KnitMeasure
from illuknit.pipeline.designs import Progress, RankedDesign, TileDesign

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import ArrayLike, NDArray

    from illuknit.core.pattern import LogicalPattern, Yarn
    from illuknit.design.legibility import Legibility
    from illuknit.design.render.params import RenderParams
    from illuknit.design.tiles.assignment import Regions, TileAssignment
    from illuknit.design.tiles.bank import TileBank, ViewPair
    from illuknit.design.tiles.perception import CandidateMeasures, ReadMeasure
    from illuknit.design.tiles.simplify import EditResult
    from illuknit.pictures.images import QuantisedImage

__all__ = ["TileJob", "choose_order", "knit_measure", "rank_tiles", "search_tiles"]


def knit_measure(ranking: RankOptions) -> KnitMeasure | None:
    """What knitting a design costs on ``ranking.machine``, when the ranking needs it (knitting
    time asked for, or the order is by knitting time)."""
    from illuknit.knitting.stats import knit_stats

    if not (ranking.knit_time or ranking.rank_by is RankBy.KNIT_TIME):
        return None
    return functools.partial(knit_stats, machine=ranking.machine)


def choose_order(
    mode: str, targets: Sequence[NDArray[np.uint8]], ranking: RankOptions
) -> RankChoice:
    """The order the designs of this pair are ranked in, and why: ``ranking.rank_by`` as given,
    or for :attr:`~illuknit.design.options.RankBy.AUTO` the reader's order
    (``LEGIBILITY``) when both pictures of a double view are words and tesseract is installed,
    ``PERCEPTION`` otherwise. The one place ``AUTO`` is resolved; the pictures are read (one
    run of the reader) only when it decides."""
    asked = ranking.rank_by
    if asked is not RankBy.AUTO:
        return RankChoice(asked, asked, "as asked")
    perception = RankBy.PERCEPTION
    if mode != "double":
        return RankChoice(perception, asked, "a head-on design (the reader judges double views)")
    from illuknit.design.legibility import reader_available, words_of

    if not reader_available():
        return RankChoice(
            perception, asked, "the reader (tesseract) is not installed, so no side was read "
            "while ranking; with it (apt-get install tesseract-ocr) word pairs are ranked by "
            "whether their sides read",
        )  # fmt: skip
    words = tuple(words_of(targets))
    if all(w is not None for w in words):
        said = ", ".join(str(w) for w in words)
        return RankChoice(RankBy.LEGIBILITY, asked, f"both pictures are words ({said})", words)
    which = [v for v, w in zip("AB", words, strict=True) if w is None]
    what = "neither picture is words (the reader reads no text in them)"
    if len(which) == 1:
        what = f"picture {which[0]} is not words (the reader reads no text in it)"
    return RankChoice(perception, asked, what, words)


def _reader(
    mode: str,
    targets: Sequence[NDArray[np.uint8]],
    ranking: RankOptions,
    choice: RankChoice,
    view: tuple[float, RenderParams | None],
) -> ReadMeasure | None:
    """The reader's verdict on designs of this pair (:func:`~illuknit.design.legibility.read_designs`
    bound to its pictures and viewpoint, on the machine's ``gauge`` with the renderer's
    ``params``: ``view``), when the ranking asks for it; None otherwise."""
    from illuknit.design.legibility import read_designs, reader_available, words_of

    legible = choice.by is RankBy.LEGIBILITY
    if mode != "double":
        if legible:
            raise OptionError("ranking by legibility judges double-view designs (two pictures)")
        return None
    if not (ranking.read or legible):
        return None
    if not reader_available():
        from illuknit.core.errors import BackendUnavailableError

        raise BackendUnavailableError(
            "reading the sides needs the tesseract OCR program (apt-get install tesseract-ocr); "
            "rank by perception to design without it"
        )
    words = list(choice.words) if choice.words is not None else words_of(targets)
    gauge, params = view

    def read(
        patterns: Sequence[LogicalPattern], measures: Sequence[CandidateMeasures]
    ) -> list[Legibility]:
        return read_designs(
            patterns, targets, correlations=[m.readability for m in measures], words=words,
            angle=ranking.angle, distance=ranking.distance, gauge=gauge, params=params,
        )  # fmt: skip

    return read


@dataclass(frozen=True, eq=False)
class TileJob:
    """What searching and ranking the tile designs of one pair of pictures share: the
    quantised pictures (``qb`` None: a head-on design without a side picture), the kind of
    design and its views, the bank's yarns and the bank, the options, and who hears progress;
    ``own_bank``: the bank is the one the design stage built (not the caller's), so a design made
    for hands may also be sought in the shared-stripe bank."""

    qa: QuantisedImage
    qb: QuantisedImage | None
    mode: Literal["double", "headon"]
    views: ViewPair
    yarns: tuple[Yarn, ...]
    bank: TileBank
    search: SearchOptions
    ranking: RankOptions
    say: Progress
    own_bank: bool = True


def search_tiles(
    job: TileJob, sources: Sequence[ArrayLike] | None, edit_colors: int
) -> tuple[list[TileAssignment], list[EditResult]]:
    """The tile assignments (by score), after the simplifying edits (and those edits)."""
    from illuknit.design.tiles.assign import assign_tiles
    from illuknit.design.tiles.headon import uniform_side
    from illuknit.design.tiles.simplify import review_edits

    qa, qb, search, bank = job.qa, job.qb, job.search, job.bank
    kw = {"bank": bank, **search.assign_kwargs()}
    # what the assignment is made for: the pictures, or the edited regions of them
    first: QuantisedImage | Regions = qa
    second: QuantisedImage | Regions | tuple[NDArray[Any], NDArray[Any]] = (
        qb if qb is not None else uniform_side(qa)
    )
    edits: list[EditResult] = []
    if search.edits is not PictureEdits.NONE:
        if job.mode != "double" or sources is None:
            raise OptionError(
                "picture edits work on double-view designs of two pictures (give `sources`)"
            )
        assert qb is not None  # a double view has two pictures (design_tiles checks)
        review = review_edits(
            qa,
            qb,
            apply=search.edits is PictureEdits.APPLY,
            targets=[qa.rgb(), qb.rgb()],
            sources=list(sources),
            max_colors=edit_colors,
            **kw,
        )
        first, second, edits = review.a, review.b, list(review.results)
    what = "head-on" if job.mode == "headon" else f"{len(bank)} tiles in the bank"
    job.say(0.1, f"finding tile mappings ({what})")
    found = assign_tiles(
        first,
        second,
        bank=bank,
        views=job.views,
        candidates=search.candidates,
        pool=search.pool,
        pool_seconds=search.pool_seconds,
        solver=search.solver,
        brightness=search.brightness.value,
        time_limit=search.time_limit,
    )
    if job.ranking.made_for is MadeFor.HANDS and job.own_bank and job.mode == "double":
        from illuknit.design.tiles.assign import with_candidates
        from illuknit.design.tiles.stripes import search_stripes

        # and every row in one yarn: the classic shadow-knitting design (issue #37)
        job.say(0.3, "finding shared-stripe designs (every row one yarn)")
        stripes = search_stripes(first, second, yarns=job.yarns, **search.assign_kwargs())
        found = with_candidates(found, stripes)
    return found, edits


def rank_tiles(
    job: TileJob, found: Sequence[TileAssignment], edits: Sequence[EditResult]
) -> TileDesign:
    """Compile, measure and rank the assignments into a :class:`TileDesign`."""
    from dataclasses import replace

    from illuknit.design.tiles.perception import rank_designs, rank_key, seen_blur, seen_targets

    qa, qb, mode, search = job.qa, job.qb, job.mode, job.search
    targets = seen_targets(qa, qb)
    choice = choose_order(mode, targets, job.ranking)
    ranking = replace(job.ranking, rank_by=choice.by)
    gauge = resolve_machine(ranking.machine).gauge
    ranked = rank_designs(
        found,
        targets,
        views=("A", "B") if mode == "double" else ("headon", "side"),
        overrides=ranking.override_map,
        rank_by=ranking.rank_by.value,
        knit_time=knit_measure(ranking),
        keep=search.candidates,
        progress=lambda f, message: job.say(0.4 + 0.6 * f, message),
        angle=ranking.angle,
        blur=seen_blur(ranking.distance, gauge=gauge),
        params=split_params(search),
        read=_reader(mode, targets, ranking, choice, (gauge, split_params(search))),
        made_for=ranking.made_for.value,
    )
    by = ranking.rank_by
    hands = ranking.made_for.value == "hands"
    designs = tuple(
        RankedDesign(
            rank=k + 1,
            pattern=rc.pattern,
            measures=rc.measures,
            rank_key=tuple(
                float(v) for v in rank_key(rc.measures, rc.assignment.score, by.value, hands=hands)
            ),
            rank_fields=ranking.key_fields,
            assignment=rc.assignment,
            report=rc.report,
            score_rank=rc.score_rank,
            label=_assignment_label(rc.assignment),
            legibility=rc.legibility,
        )
        for k, rc in enumerate(ranked)
    )
    hand_model = None
    if hands and mode == "double" and search.hand_model_seconds > 0:
        from illuknit.pipeline.hand_model import hand_model_design, with_hand_model

        extra, solved = hand_model_design(
            job,
            targets,
            ranking,
            blur=seen_blur(ranking.distance, gauge=gauge),
            params=split_params(search),
            read=_reader(mode, targets, ranking, choice, (gauge, split_params(search))),
        )
        designs, place = with_hand_model(designs, extra, search.candidates)
        hand_model = MappingProxyType({**solved, "rank": place})
    quantised = {"A": qa} if qb is None else {"A": qa, "B": qb}
    return TileDesign(
        mode=mode,
        yarns=job.yarns,
        quantised=MappingProxyType(quantised),
        views=job.views,
        bank=job.bank,
        targets=tuple(targets),
        designs=designs,
        searched=len(found),
        edits=tuple(edits),
        search=search,
        ranking=ranking,
        machine_first=ranked.machine_first,
        order=choice,
        hand_model=hand_model,
    )


def split_params(search: SearchOptions) -> RenderParams | None:
    """The renderer's parameters the designs are measured with: the default ones, with the
    search's split share when split bumps are on (None: the defaults)."""
    if not search.split_bumps:
        return None
    from illuknit.design.render.params import RenderParams

    return RenderParams(split_share=search.split_share)


def _assignment_label(assignment: TileAssignment) -> str:
    kinds = [f.kind for f in (*assignment.fills_a, *assignment.fills_b) if f is not None]
    stripes = sum(k != "solid" for k in kinds)
    return (
        "all solid fills" if not stripes else f"{stripes} striped fill{'s' if stripes > 1 else ''}"
    )
