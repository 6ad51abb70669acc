"""How tile candidates are ranked: the default ranking on their perceptual measures, other
orders a user may choose, and the whole step from assignments to ranked designs
(:func:`rank_designs`).

The measures themselves (readability, contrast, ghosting, visible ghosting, knitting time, and
where a view fails) are :mod:`illuknit.design.tiles.candidate_measures`; every public name of it
is importable from here too.


**The default ranking** (``rank_by="perception"``) orders candidates by the *perceptual score*

    worse-view readability - CONTRAST_PENALTY * max(0, CONTRAST_FLOOR - worse-view contrast)

higher first, ties broken by the worst visible ghosting (less first), then by knitting time
(when measured) and then by the assignment's own score. Contrast only costs below a floor, so
among candidates that keep a usable contrast the one whose worse view reads best leads; a
candidate whose picture survives only as a faint correlation falls behind. Ghosting is not
subtracted: a ghost that shows is part of what the picture does not explain, so it lowers the
readability already, and a second charge would prefer a design that reads worse because its
larger error is less structured. (On the bundled double-view instances a further 0.25 x visible
ghosting changes one default in eight: heart / ECG at 100 units, readability 0.985 with visible
ghosting 0.012 instead of 0.988 with 0.036; the raw ghosting correlation, charged at 0.25, also
passed over a design reading 0.983 for one reading 0.962 on the photo pair, whose ghost showed
at 0.038 against 0.024.) ``rank_by`` may also be ``score`` (the assignment's order),
``readability``, ``contrast``, ``ghosting`` (least visible ghosting first), ``knit-time`` (the
machine's minutes) or ``hand-time`` (the estimated hours of hand knitting,
:attr:`illuknit.design.hand_cost.HandCost.hours`; quickest first however it reads, then the
perceptual score).

**Made for hands** (``made_for="hands"``): every candidate also carries its hand knitter's cost
(:func:`illuknit.design.hand_cost.hand_cost`: colour changes a row, floats, yarns and blocks a
row), and the ranking sorts first by the share of rows a hand knitter can work (stranded with 2
yarns and floats of at most 7 stitches, or intarsia with at most 6 blocks), then by ``rank_by``'s
key: among the designs most knittable by hand, the one that reads best (``hand-time``: the
quickest by hand).

"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from numpy.typing import ArrayLike

from illuknit.core.errors import OptionError
from illuknit.core.pattern import LogicalPattern
from illuknit.design.options import DEFAULT_POOL, POOL_SECONDS
from illuknit.design.tiles.candidate_measures import (
    ACUITY_ARCMIN,
    CONTRAST_FLOOR,
    CONTRAST_PENALTY,
    GHOST_THRESHOLD,
    WRONG_THRESHOLD,
    CandidateMeasures,
    KnitMeasure,
    _with_knit_time,
    diagnostic_rgb,
    eye_blur_units,
    measure_candidate,
    seen_blur,
    seen_from,
    seen_targets,
)

__all__ = [
    "ACUITY_ARCMIN",
    "CLEANER_GHOSTING_MARGIN",
    "CLEANER_SCORE_ALLOWANCE",
    "CONTRAST_FLOOR",
    "CONTRAST_PENALTY",
    "DEFAULT_POOL",
    "GHOST_THRESHOLD",
    "POOL_SECONDS",
    "QUICKER_HOURS_SHARE",
    "RANK_KEYS",
    "WRONG_THRESHOLD",
    "CandidateMeasures",
    "KnitMeasure",
    "MeasureContext",
    "RankedCandidate",
    "RankedDesigns",
    "cleaner_alternative",
    "diagnostic_rgb",
    "eye_blur_units",
    "measure_candidate",
    "quicker_alternative",
    "rank_candidates",
    "rank_designs",
    "rank_key",
    "seen_blur",
    "seen_from",
    "seen_targets",
]

#: The orders a user may rank candidates by.
RANK_KEYS = (
    "perception",
    "score",
    "readability",
    "contrast",
    "ghosting",
    "knit-time",
    "hand-time",
    "legibility",
)
#: Judges compiled candidates of one pair: for each pattern (with its measures), how many of its
#: sides read (:func:`illuknit.design.legibility.read_designs` bound to the pair and viewpoint).
ReadMeasure = Callable[[Sequence[LogicalPattern], Sequence["CandidateMeasures"]], Sequence[Any]]


def rank_key(
    m: CandidateMeasures, score: float, by: str, *, hands: bool = False
) -> tuple[float, ...]:
    """Ascending key: the best candidate sorts first. ``hands``: first the share of rows a hand
    knitter can work, more first (``m.hand`` is needed, as for ``hand-time``)."""
    if (hands or by == "hand-time") and m.hand is None:
        why = "for hands" if hands else "by hand-time"
        raise OptionError(f"ranking {why} needs the hand cost of every candidate")
    if hands:
        assert m.hand is not None
        return (-m.hand.knittable_share, *rank_key(m, score, by))
    if by == "hand-time":
        assert m.hand is not None
        return (m.hand.hours, -m.perceptual_score, score)
    time = m.knit_minutes if m.knit_minutes is not None else float("inf")
    if by == "perception":
        return (-m.perceptual_score, m.worst_visible_ghosting, time, score)
    if by == "score":
        return (score,)
    if by == "readability":
        return (-m.worse_readability, m.worst_ghosting, score)
    if by == "contrast":
        return (-m.worse_contrast, -m.worse_readability, score)
    if by == "ghosting":
        return (m.worst_visible_ghosting, -m.worse_readability, score)
    if by == "legibility":
        read = -float(m.sides_read) if m.sides_read is not None else 0.0
        return (read, -m.perceptual_score, m.worst_visible_ghosting, time, score)
    return (time, -m.perceptual_score, score)  # knit-time


#: A candidate is named as cleaner than the default (:func:`cleaner_alternative`) when the other
#: picture shows in it at most half as much and at least this much less: a share of its worse
#: view's variation (``CandidateMeasures.worst_visible_ghosting``)...
CLEANER_GHOSTING_MARGIN = 0.10
#: ... and its perceptual score is at most this much lower (issue #37's readability allowance;
#: :func:`quicker_alternative` too).
CLEANER_SCORE_ALLOWANCE = 0.05
#: A candidate is named as quicker by hand (:func:`quicker_alternative`) when it takes at most
#: this share of the default's estimated hours.
QUICKER_HOURS_SHARE = 0.75


def _nearly_as_good(m: CandidateMeasures, d: CandidateMeasures, *, hands: bool) -> bool:
    """``m`` reads nearly as well as ``d`` (:data:`CLEANER_SCORE_ALLOWANCE`), no fewer sides
    where both were read, and with ``hands`` has at least as many rows knittable by hand."""
    if m.perceptual_score < d.perceptual_score - CLEANER_SCORE_ALLOWANCE:
        return False
    if m.sides_read is not None and d.sides_read is not None and m.sides_read < d.sides_read:
        return False
    if hands and m.hand is not None and d.hand is not None:
        return m.hand.knittable_share >= d.hand.knittable_share
    return True


def _best_of(
    measures: Sequence[CandidateMeasures], found: list[int], *more: Callable[[int], float]
) -> int | None:
    """Of the indices ``found``, the best perceptual score (then ``more``'s keys, then the
    first); None when there is none."""
    if not found:
        return None
    return min(found, key=lambda k: (-measures[k].perceptual_score, *(f(k) for f in more), k))


def cleaner_alternative(
    measures: Sequence[CandidateMeasures], default: int, *, hands: bool = False
) -> int | None:
    """The index of a candidate in which the other picture shows much less than in
    ``measures[default]`` (:data:`CLEANER_GHOSTING_MARGIN`, and at most half) and that reads
    nearly as well (:data:`CLEANER_SCORE_ALLOWANCE`), neither reading fewer sides (where both
    were read) nor, with ``hands``, having fewer rows knittable by hand; of those, the best
    perceptual score. None when there is none: the order already put the cleanest first, or
    cleaner designs read worse.

    The orders rank by what reads (ghosting breaks ties only), so a design solved for the views
    alone, like the constraint model's design made for hands, can rank first with much of the
    other picture in it; the summaries name the alternative (``--pick``)."""
    d = measures[default]
    worst = d.worst_visible_ghosting
    found = [
        k
        for k, m in enumerate(measures)
        if k != default
        and m.worst_visible_ghosting <= min(worst / 2, worst - CLEANER_GHOSTING_MARGIN)
        and _nearly_as_good(m, d, hands=hands)
    ]
    return _best_of(measures, found, lambda k: measures[k].worst_visible_ghosting)


def quicker_alternative(
    measures: Sequence[CandidateMeasures], hours: Sequence[float], default: int
) -> int | None:
    """For a design made for hands: the index of a candidate that takes at most
    :data:`QUICKER_HOURS_SHARE` of the default's estimated hours of hand knitting (``hours``,
    one a candidate: :func:`illuknit.design.hand_cost.hand_hours`, the cover's estimate), has as
    many rows knittable by hand, and reads nearly as well (:data:`CLEANER_SCORE_ALLOWANCE`);
    of those, the best perceptual score. None when there is none.

    The order for hands ranks by the rows knittable, then by what reads: two designs every row
    of which a hand knitter can work rank by readability alone, however much more colour work
    one of them is."""
    d = measures[default]
    found = [
        k
        for k, m in enumerate(measures)
        if k != default
        and hours[k] <= QUICKER_HOURS_SHARE * hours[default]
        and _nearly_as_good(m, d, hands=True)
    ]
    return _best_of(measures, found, lambda k: hours[k])


def rank_candidates(
    measures: Sequence[CandidateMeasures],
    scores: Sequence[float],
    *,
    by: str = "perception",
    hands: bool = False,
) -> list[int]:
    """Indices of the candidates, best first, by the order ``by`` (one of :data:`RANK_KEYS`),
    first by the share of rows knittable by hand when ``hands``.

    ``scores`` are the assignment's scores (lower is better), the last tie-break everywhere.
    """
    if by not in RANK_KEYS:
        raise OptionError(f"rank by one of {', '.join(RANK_KEYS)}, got {by!r}")
    if by == "knit-time" and any(m.knit_minutes is None for m in measures):
        raise OptionError("ranking by knit-time needs the knitting time of every candidate")
    if by == "hand-time" and any(m.hand is None for m in measures):
        raise OptionError("ranking by hand-time needs the hand cost of every candidate")
    if by == "legibility" and any(m.sides_read is None for m in measures):
        raise OptionError("ranking by legibility needs the reader's verdict on every candidate")
    keys = [rank_key(m, s, by, hands=hands) for m, s in zip(measures, scores, strict=True)]
    return sorted(range(len(measures)), key=lambda i: (keys[i], i))


@dataclass(frozen=True)
class RankedCandidate:
    """A compiled candidate with its measures, in the order of a ranking.

    ``assignment.rank`` is its place in that ranking; ``score_rank`` its place by the
    assignment's own score.
    """

    assignment: Any
    pattern: LogicalPattern
    report: Any
    measures: CandidateMeasures
    score_rank: int
    legibility: Any = None


class RankedDesigns(list[RankedCandidate]):
    """What :func:`rank_designs` returns: the ranked candidates (a list, best first) and, when
    ranked for hands, ``machine_first``: the measures of the design the same order ranks first
    for a machine (among every design searched; ``perception`` in place of ``hand-time``), the
    comparison a hand knitter is shown; None when ranked for a machine."""

    machine_first: CandidateMeasures | None = None


@dataclass(frozen=True)
class MeasureContext:
    """How :func:`rank_designs` compiles and measures each design: everything but the ranking's
    own choices (``rank_by``, ``made_for``, ``keep``). Its fields may also be given to
    :func:`rank_designs` as keywords (``rank_designs(found, pictures, angle=40.0)``).

    Parameters
    ----------
    views : sequence of str
        ``("A", "B")`` (double view: ghosting is measured) or ``("headon", "side")``.
    overrides : dict, optional
        Per-pair tile overrides for :func:`illuknit.design.tiles.compile.compile_tiles`.
    angle, blur : float, optional
        The viewing angle and the blur (units) each design is measured at, as
        :func:`measure_candidate` (e.g. :func:`seen_blur` of a viewing distance).
    params : RenderParams, optional
        The renderer's parameters the designs are measured with (e.g. a measured split share).
    knit_time : KnitMeasure, optional
        Knits a design and measures it on a machine (:func:`measure_candidate`); ranking by
        ``"knit-time"`` needs it. Only the designs that can reach the ``keep`` best are knit.
    read : ReadMeasure, optional
        Judges whether each side of a design reads (a reader's verdict,
        :func:`illuknit.design.legibility.read_designs` bound to the pictures and viewpoint);
        ranking by ``"legibility"`` needs it and reads every design, otherwise only the kept
        ones are read. Each returned candidate's ``legibility`` holds the verdict.
    """

    views: Sequence[str] = ("A", "B")
    overrides: Any = None
    angle: float | None = None
    blur: float | None = None
    params: Any = None
    knit_time: KnitMeasure | None = None
    read: ReadMeasure | None = None


def rank_designs(
    found: Sequence[Any],
    pictures: Sequence[ArrayLike],
    *,
    rank_by: str = "perception",
    made_for: str = "machine",
    keep: int | None = None,
    progress: Callable[[float, str], None] | None = None,
    context: MeasureContext | None = None,
    **knobs: Any,
) -> RankedDesigns:
    """Compile every tile candidate, measure how it reads and rank the lot (the best ``keep``).

    Parameters
    ----------
    found : sequence of TileAssignment
        Candidates from :func:`illuknit.design.tiles.assign.assign_tiles`.
    pictures : sequence of ndarray of shape (N, M, 3)
        The designer's quantised picture per view.
    rank_by : str
        One of :data:`RANK_KEYS` (see :func:`rank_candidates`).
    made_for : {"machine", "hands"}
        ``"hands"``: rank first by the share of rows knittable by hand (module docstring).
        Every candidate's measures carry its hand cost either way.
    keep : int, optional
        Return only the best ``keep`` of the ranking (a pool searched wider than it is shown:
        :func:`~illuknit.design.tiles.assign.assign_tiles` ``pool=``).
    progress : callable, optional
        ``progress(fraction, message)`` before each design is compiled and measured; whatever
        it raises stops the ranking (a user interface's cancel).
    context : MeasureContext, optional
        How each design is compiled and measured (views, overrides, angle, blur, renderer
        parameters, the knitting-time and reading measures); defaults: ``MeasureContext()``.
    **knobs
        Shorthand for fields of ``context`` (``rank_designs(f, p, knit_time=measure)`` is
        ``rank_designs(f, p, context=MeasureContext(knit_time=measure))``); they replace those
        fields of ``context`` when both are given.
    """
    from dataclasses import replace

    ctx = _measure_context(context, knobs)
    hands = _check_ranking(rank_by, keep, ctx.knit_time, ctx.read, made_for)
    compiled, measures = _compile_and_measure(found, pictures, ctx, progress)
    scores = [c.score for c in found]
    if ctx.knit_time is not None:
        for i in _to_knit(measures, scores, rank_by=rank_by, keep=keep, hands=hands):
            measures[i] = _with_knit_time(measures[i], compiled[i][0], ctx.knit_time)
    verdicts: dict[int, Any] = {}
    if rank_by == "legibility" and ctx.read is not None:
        verdicts = _read_all(ctx.read, range(len(found)), compiled, measures, progress)
    order = rank_candidates(measures, scores, by=rank_by, hands=hands)
    if ctx.read is not None and rank_by != "legibility":
        verdicts = _read_all(ctx.read, order[:keep], compiled, measures, progress)
    out = RankedDesigns(
        RankedCandidate(
            assignment=replace(found[i], rank=k + 1),
            pattern=compiled[i][0],
            report=compiled[i][1],
            measures=measures[i],
            score_rank=found[i].rank,
            legibility=verdicts.get(i),
        )
        for k, i in enumerate(order[:keep])
    )
    if hands and order:
        # a machine knitter's order ranks by how it reads or knits, never by hours by hand
        machine_by = "perception" if rank_by == "hand-time" else rank_by
        out.machine_first = measures[rank_candidates(measures, scores, by=machine_by)[0]]
    return out


def _measure_context(context: MeasureContext | None, knobs: dict[str, Any]) -> MeasureContext:
    """``context`` with the shorthand ``knobs`` in place of its fields."""
    from dataclasses import fields, replace

    if context is not None and not isinstance(context, MeasureContext):
        raise OptionError(f"`context` must be a MeasureContext, got {type(context).__name__}")
    base = MeasureContext() if context is None else context
    names = [f.name for f in fields(MeasureContext)]
    unknown = sorted(set(knobs) - set(names))
    if unknown:
        raise OptionError(f"unknown ranking option {unknown[0]!r}; valid: {', '.join(names)}")
    return replace(base, **knobs) if knobs else base


def _compile_and_measure(
    found: Sequence[Any],
    pictures: Sequence[ArrayLike],
    ctx: MeasureContext,
    progress: Callable[[float, str], None] | None,
) -> tuple[list[Any], list[CandidateMeasures]]:
    """Each candidate compiled (pattern, report) and measured, in ``found``'s order."""
    from illuknit.design.tiles.compile import compile_tiles

    compiled = []
    measures = []
    for k, c in enumerate(found):
        if progress is not None:
            progress(k / max(1, len(found)), f"measuring tile design {k + 1} of {len(found)}")
        compiled.append(compile_tiles(c, overrides=ctx.overrides or {}))
        measures.append(
            measure_candidate(
                compiled[-1][0],
                pictures,
                views=ctx.views,
                ghost=len(pictures) == 2,
                angle=ctx.angle,
                blur=ctx.blur,
                params=ctx.params,
            )
        )
    return compiled, measures


def _check_ranking(
    rank_by: str, keep: int | None, knit_time: Any, read: Any, made_for: str
) -> bool:
    """:func:`rank_designs`' arguments checked; whether the ranking is for hands."""
    if rank_by not in RANK_KEYS:
        raise OptionError(f"rank by one of {', '.join(RANK_KEYS)}, got {rank_by!r}")
    if keep is not None and keep < 1:
        raise OptionError(f"keep at least one candidate, got keep={keep}")
    if rank_by == "knit-time" and knit_time is None:
        raise OptionError("ranking by knit-time needs knit_time, a function that knits a pattern")
    if rank_by == "legibility" and read is None:
        raise OptionError("ranking by legibility needs read, a reader's verdict on each side")
    if made_for not in ("machine", "hands"):
        raise OptionError(f"`made_for` must be machine or hands, got {made_for!r}")
    return made_for == "hands"


def _read_all(
    read: ReadMeasure,
    which: Sequence[int],
    compiled: Sequence[Any],
    measures: list[CandidateMeasures],
    progress: Callable[[float, str], None] | None,
) -> dict[int, Any]:
    """The reader's verdict on the designs ``which``; their measures get ``sides_read``."""
    from dataclasses import replace

    idx = list(which)
    if progress is not None:
        progress(1.0, f"reading both sides of {len(idx)} design(s)")
    got = read([compiled[i][0] for i in idx], [measures[i] for i in idx])
    for i, verdict in zip(idx, got, strict=True):
        measures[i] = replace(measures[i], sides_read=int(verdict.sides_read))
    return dict(zip(idx, got, strict=True))


def _to_knit(
    measures: Sequence[CandidateMeasures],
    scores: Sequence[float],
    *,
    rank_by: str,
    keep: int | None,
    hands: bool = False,
) -> list[int]:
    """The candidates whose knitting time can matter: all of them when ranking by it or keeping
    all; otherwise the ``keep`` best, and under ``perception`` (where the time breaks ties) any
    other with the perceptual score of the last one kept."""
    if rank_by == "knit-time" or keep is None or keep >= len(measures):
        return list(range(len(measures)))
    order = rank_candidates(measures, scores, by=rank_by, hands=hands)
    kept = set(order[:keep])
    if rank_by == "perception" and not hands:
        edge = measures[order[keep - 1]].perceptual_score
        kept |= {i for i, m in enumerate(measures) if m.perceptual_score == edge}
    return sorted(kept)
