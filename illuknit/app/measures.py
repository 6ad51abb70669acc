"""How each candidate reads and knits, and the orders the designer ranks candidates by.

The measures and the default ranking are the library's (:mod:`illuknit.design.tiles.perception`), so
the app, ``illuknit double --rank-by`` and the bench agree:

* per side: **readability** (correlation of the blurred angled render with the quantised
  picture), **contrast** (how much of its light/dark difference survives) and, in a double view,
  **ghosting** (how much of the other picture shows through);
* the **perceptual score**: the worse side's readability, penalised for contrast below a floor
  and for how much of the other picture shows (the documented default order);
* the machine's **knitting time** and passes on the chosen machine.

In a single view both sides show picture A and nothing can ghost. A head-on design is measured in
all three views: head-on against the front picture, from above and from below against the side
picture (the worse of the two), or, with no side picture, against the plain field the design
shows there: nothing to read, and its ghosting is how much of the front picture is left.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, Literal, get_args

__all__ = ["ORDERS", "Order", "measure_all", "measure_candidate", "order_candidates"]

#: Ways the page can order candidates: the search's own rank, or a perception.RANK_KEYS order
#: (``legibility``: most sides the reader reads first, then the perceptual score; ``hand_time``:
#: the estimated hours of hand knitting, quickest first).
Order = Literal[
    "rank",
    "perception",
    "legibility",
    "readability",
    "contrast",
    "ghosting",
    "knit_time",
    "hand_time",
]
ORDERS: tuple[str, ...] = get_args(Order)


def measure_candidate(
    pattern: Any,
    prepared: Any,
    *,
    machine: str,
    knit_time: bool = True,
    viewpoint: tuple[float, float] = (30.0, 3.0),
) -> Any:
    """The candidate's :class:`~illuknit.design.tiles.perception.CandidateMeasures`, measured by
    the stage :func:`~illuknit.pipeline.stages.measure_design` on the page's machine, seen from
    ``viewpoint`` (angle in degrees, distance in metres; the session's settings), without the
    machine's time and passes when not ``knit_time``: how it reads only, in a fraction of a
    second, for a tile edit measured at once."""
    from illuknit.design.options import RankOptions
    from illuknit.pipeline.stages import measure_design

    q = prepared.quantised
    angle, distance = viewpoint
    ranking = RankOptions(machine=machine, knit_time=knit_time, angle=angle, distance=distance)
    return measure_design(pattern, prepared.mode, q["a"], q.get("b"), ranking=ranking)


def measure_all(
    patterns: Sequence[Any],
    prepared: Any,
    machine: str,
    viewpoint: tuple[float, float] = (30.0, 3.0),
    progress: Callable[[float, str], None] | None = None,
) -> list[Any]:
    """:func:`measure_candidate` of every pattern from ``viewpoint``, saying before each how far
    it is (the measures job runs this in its worker process, killed by Cancel)."""
    out = []
    for k, pattern in enumerate(patterns):
        if progress is not None:
            progress(k / len(patterns), f"measuring candidate {k + 1} of {len(patterns)}")
        out.append(measure_candidate(pattern, prepared, machine=machine, viewpoint=viewpoint))
    return out


def order_candidates(candidates: Sequence[Any], order: str, *, hands: bool = False) -> list[Any]:
    """``candidates`` in ``order`` (see :data:`ORDERS`); by rank until all are measured. Made
    for ``hands``: first by the share of rows a hand knitter can work, as the search ranks.
    By ``legibility``, the sides each card's verdict says read (none when not read). When the
    search itself ranked by the reader (two pictures of words), "perception" (how it reads) does
    too: the sides that read first, as the search did, then the perceptual score."""
    from dataclasses import replace

    from illuknit.design.tiles.perception import rank_candidates

    by_rank = sorted(candidates, key=lambda c: c.rank)
    if order == "rank" or not by_rank or any(c.measured is None for c in by_rank):
        return by_rank
    scores = [c.score if c.score is not None else float(c.rank) for c in by_rank]
    by = order.replace("_", "-")  # knit_time, hand_time: the library's knit-time, hand-time
    measured = [c.measured for c in by_rank]
    searched_by_reader = all(
        (getattr(c, "details", None) or {}).get("ranked_by") == "legibility" for c in by_rank
    )
    if by == "perception" and searched_by_reader and all(c.legibility for c in by_rank):
        by = "legibility"
    if by == "legibility":
        # the cards' verdicts; a design not read (no reader) has no side known to read
        measured = [
            replace(m, sides_read=0 if c.legibility is None else c.legibility.sides_read)
            for m, c in zip(measured, by_rank, strict=True)
        ]
    picks = rank_candidates(measured, scores, by=by, hands=hands)
    return [by_rank[i] for i in picks]
