"""Candidates: the ranked designs the designer picks from.

Prepared -> make_candidates -> [Candidate]  (single view: both stripe orders; double view
                                             and head-on: the best-reading tile mappings of
                                             the pool ``illuknit double`` searches, compiled)
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from illuknit.app.controls import blame
from illuknit.app.inputs import Prepared
from illuknit.app.reading import NOT_INSTALLED, legibility_json, reader_failed
from illuknit.core.errors import AppRequestError, IlluknitError
from illuknit.core.pattern import LogicalPattern

if TYPE_CHECKING:
    from illuknit.design.legibility import Legibility
    from illuknit.pipeline.stages import Stripe

__all__ = ["Candidate", "Progress", "Runner", "make_candidates"]


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
    #: whether each side reads, by the reader (design.legibility.Legibility; double view only)
    legibility: Legibility | None = None
    #: why the sides were not read (no reader, or it failed); None when read or not a double view
    not_read: str | None = None

    def __setstate__(self, state: dict[str, Any]) -> None:
        # a candidate stored (pickled with its session) before the hand cost counted its
        # stitches and hours gets its hand cost counted again from its pattern
        self.__dict__.update(state)
        hand = getattr(self.measured, "hand", None)
        if hand is not None and not hasattr(hand, "stitches"):
            from dataclasses import replace

            from illuknit.design.hand_cost import hand_cost

            self.measured = replace(self.measured, hand=hand_cost(self.pattern))

    def to_json(self) -> dict[str, Any]:
        n, m = self.pattern.shape
        details = dict(self.details)
        if self.legibility is not None or self.not_read is not None:
            details["legibility"] = legibility_json(self.legibility, self.not_read)
        return {
            "rank": self.rank,
            "label": self.label,
            "score": None if self.score is None else round(float(self.score), 4),
            "rows": n,
            "cols": m,
            "yarns": [{"name": y.name, "rgb": y.hex} for y in self.pattern.yarns],
            "raised": int(self.pattern.raised.sum()),
            "details": details,
            "measures": None if self.measured is None else self.measured.to_json(),
            "editable": self.source is not None,
        }


#: ``progress(fraction, message)``: reports a job's progress (and raises when it was cancelled).
Progress = Callable[[float, str], None]


#: ``run(fn)`` calls ``fn()`` and answers its result: in a killable process for the app's jobs
#: (:meth:`illuknit.app.jobs.Job.run_isolated`), so Cancel stops a long solve at once.
Runner = Callable[[Callable[[], Any]], Any]


def make_candidates(
    prepared: Prepared,
    *,
    count: int,
    progress: Progress,
    run: Runner | None = None,
    split_bumps: bool = False,
    made_for: str = "machine",
    machine: str | None = None,
    viewpoint: tuple[float, float] = (30.0, 3.0),
) -> list[Candidate]:
    """Ranked candidates for the prepared inputs; ``progress(fraction, message)`` may cancel.

    ``run`` runs the tile search (double view and head-on), by default in this thread;
    ``split_bumps`` lets its tiles hold split bumps; ``made_for="hands"`` ranks first the
    designs a hand knitter can work (:class:`~illuknit.design.options.RankOptions`). The
    designs are ranked as seen from ``viewpoint`` (angle in degrees, distance in metres) on
    ``machine`` (its gauge; the default machine when None), and a double view's kept designs
    are read there when the reader is installed (:mod:`illuknit.app.reading`).
    """
    if prepared.mode == "single":
        return _single_candidates(prepared, progress)
    return _tile_candidates(
        prepared, count=count, progress=progress, run=run, split_bumps=split_bumps,
        made_for=made_for, machine=machine, viewpoint=viewpoint,
    )  # fmt: skip


def _single_candidates(prepared: Prepared, progress: Progress) -> list[Candidate]:
    """Both stripe orders (:func:`~illuknit.pipeline.stages.design_single`), dark first."""
    from illuknit.pipeline.stages import design_single

    stripes: tuple[Stripe, Stripe] = ("dark", "light")

    progress(0.0, "compiling single view (both stripe orders)")
    with blame("n_colors"):
        design = design_single(prepared.quantised["a"])
    out = []
    for k, first in enumerate(stripes):
        d = design.first(first)
        err = [round(d.measures["mismatch_A"], 4), round(d.measures["mismatch_B"], 4)]
        out.append(
            Candidate(
                rank=k + 1,
                label=d.label,
                score=None,
                pattern=d.pattern,
                details={"first": first, "mismatch_A": err[0], "mismatch_B": err[1]},
            )
        )
    return out


def _tile_candidates(
    prepared: Prepared,
    *,
    count: int,
    progress: Progress,
    run: Runner | None = None,
    split_bumps: bool = False,
    made_for: str = "machine",
    machine: str | None = None,
    viewpoint: tuple[float, float] = (30.0, 3.0),
) -> list[Candidate]:
    """The best-reading ``count`` of the tile designs ``illuknit double`` searches by default,
    ranked as it ranks them: one call of :func:`~illuknit.pipeline.stages.design_tiles`, inside
    ``run`` (a killable process, so Cancel stops it at once) when one is given. A double view's
    designs are read as ``double`` reads them when tesseract is installed; when it is missing or
    fails, the search is not lost: the cards say the sides were not read, and why."""
    from illuknit.design.legibility import reader_available
    from illuknit.design.options import MadeFor, RankBy, RankOptions, SearchOptions
    from illuknit.pipeline.stages import design_tiles

    angle, distance = viewpoint
    double = prepared.mode == "double"

    def search(read: bool, order: RankBy = RankBy.AUTO) -> Any:
        stage = functools.partial(
            design_tiles,
            prepared.quantised["a"],
            prepared.quantised.get("b"),
            mode="headon" if prepared.mode == "headon" else "double",
            yarns=prepared.yarns,
            search=SearchOptions(
                candidates=count, split_bumps=split_bumps, hand_model_seconds=hand_model_seconds()
            ),
            ranking=RankOptions(
                made_for=MadeFor(made_for), machine=machine, angle=angle, distance=distance,
                read=read, rank_by=order,
            ),
        )  # fmt: skip
        return stage(progress=progress) if run is None else run(stage)

    read = double and reader_available()
    not_read = NOT_INSTALLED if double and not read else None
    with blame("n_colors"):
        try:
            try:
                design = search(read)
            except (AppRequestError, IlluknitError) as e:
                if not (read and reader_failed(e)):
                    raise
                not_read = str(e)  # the reader is broken: the designs stand, unread
                # by the correlation: the default order would ask the broken reader whether
                # the pictures are words (choose_order)
                design = search(False, RankBy.PERCEPTION)
        except AppRequestError as e:  # raised in the search's own process: name the control
            e.field = e.field or "n_colors"
            raise
    instead = _alternative_details(design)
    return [
        Candidate(
            rank=d.rank,
            label=d.label,
            score=None if d.assignment is None else float(d.assignment.score),
            pattern=d.pattern,
            details={
                **_assignment_details(d.assignment, d.report),
                **_hand_details(d, made_for),
                **_order_details(design.order),
                **(instead if d.rank == 1 else {}),
            },
            source=d.assignment,
            legibility=d.legibility,
            not_read=not_read,
        )
        for d in design.designs
    ]


#: Names the seconds the app's searches made for hands give the constraint model made for hands
#: (``SearchOptions.hand_model_seconds``; default :data:`~illuknit.design.options.HAND_MODEL_SECONDS`).
HAND_MODEL_ENV = "ILLUKNIT_HAND_MODEL_SECONDS"


def hand_model_seconds() -> float:
    """``$ILLUKNIT_HAND_MODEL_SECONDS`` (0 leaves the constraint model out), else the default.

    Raises
    ------
    OptionError
        The variable is set to something that is not a number of seconds in range.
    """
    import os

    from illuknit.core.errors import OptionError
    from illuknit.design.options import HAND_MODEL_SECONDS, SearchOptions

    text = os.environ.get(HAND_MODEL_ENV, "").strip()
    if not text:
        return HAND_MODEL_SECONDS
    try:
        seconds = float(text)
    except ValueError:
        raise OptionError(f"${HAND_MODEL_ENV} must be a number of seconds, got {text!r}") from None
    return SearchOptions(hand_model_seconds=seconds).hand_model_seconds


def _hand_details(design: Any, made_for: str) -> dict[str, Any]:
    """What a hand knitter needs of a candidate made for hands (:class:`~illuknit.design.
    hand_cost.HandCost`): rows knittable by hand and the longest float; nothing otherwise."""
    hand = getattr(design.measures, "hand", None) if made_for == "hands" else None
    if hand is None:
        return {}
    from illuknit.design.tiles.stripes import STRIPE_BANK_NAME

    model = design.assignment is None  # the constraint model's design
    stripes = not model and design.assignment.bank.name == STRIPE_BANK_NAME
    return {
        "made_for": made_for,
        "hand": {
            "rows": hand.rows,
            "knittable_rows": hand.knittable_rows,
            "longest_float": hand.longest_float,
            "max_blocks": hand.max_blocks,
            "text": hand.describe()
            + ("; shared stripes: every row in one yarn" if stripes else "")
            + ("; the constraint model made for hands: no tiles" if model else ""),
            "shared_stripes": stripes,
        },
    }


def _alternative_details(design: Any) -> dict[str, Any]:
    """On the first card: the candidates a user may prefer to it and why
    (:func:`~illuknit.pipeline.alternatives.alternatives`), each ``{"rank", "text"}``;
    nothing when there are none."""
    from illuknit.pipeline.alternatives import alternative_sentences, alternatives

    said = alternative_sentences(alternatives(design))
    return {"alternatives": [{"rank": r, "text": t} for r, t in said]} if said else {}


def _order_details(order: Any) -> dict[str, Any]:
    """The order the search ranked by and why (the search's default: the reader's order for
    two pictures of words, :func:`~illuknit.pipeline.tile_search.choose_order`); the verdict
    on each candidate's sides is its :attr:`Candidate.legibility`."""
    if order is None:
        return {}
    return {"order": order.sentence(), "ranked_by": order.by.value}


def _assignment_details(assignment: Any, report: Any) -> dict[str, Any]:
    if assignment is None:  # the constraint model's design made for hands: no tiles
        return {"method": "constraint model made for hands"}
    rep = report.to_json()
    return {
        "views": list(assignment.views),
        "fills": assignment.describe(),
        "error_original": rep["error_original"],
        "delta_e_original": rep["delta_e_original"],
        "color_changes_per_course": rep["color_changes_per_course"],
        "cost": {k: round(float(v), 3) for k, v in assignment.cost.items()},
    }
