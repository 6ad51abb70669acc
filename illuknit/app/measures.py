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

import functools
from collections.abc import Sequence
from typing import Any

from illuknit.bench.metrics import knit_stats

__all__ = ["ORDERS", "measure_candidate", "order_candidates"]

#: Ways the page can order candidates: the search's own rank, or a perception.RANK_KEYS order.
ORDERS = ("rank", "perception", "readability", "contrast", "ghosting", "knit_time")


def measure_candidate(pattern: Any, prepared: Any, *, machine: str, knit_time: bool = True) -> Any:
    """The candidate's :class:`~illuknit.design.tiles.perception.CandidateMeasures` (without the
    machine's time and passes when not ``knit_time``: how it reads only, in a fraction of a
    second, for a tile edit measured at once)."""
    from illuknit.design.tiles import perception

    q = prepared.quantised
    if prepared.mode == "double":
        pictures, views, ghost = [q["a"].rgb(), q["b"].rgb()], ("A", "B"), True
    elif prepared.mode == "headon":
        # all three views: head-on against the front picture, and from above and from below
        # against the side picture -- or the plain field that stands for it (nothing to read
        # there; how much of the front picture is left at an angle is its ghosting)
        from illuknit.design.tiles.perception import seen_targets

        pictures, views, ghost = seen_targets(q["a"], q.get("b")), ("headon", "side"), True
    elif prepared.mode == "single":
        pictures, views, ghost = [q["a"].rgb(), q["a"].rgb()], ("A", "B"), False
    else:  # pragma: no cover - every mode is measured above
        k: dict[str, Any] = (
            knit_stats(pattern, machine=machine)
            if knit_time
            else {"knit_time_min": None, "carriage_passes": None, "knit_note": ""}
        )
        return perception.CandidateMeasures(
            views=(),
            readability=(),
            contrast=(),
            ghosting=(),
            knit_minutes=k["knit_time_min"],
            machine_passes=k["carriage_passes"],
            knit_note=k["knit_note"],
        )
    return perception.measure_candidate(
        pattern,
        pictures,
        views=views,
        ghost=ghost,
        knit_time=functools.partial(knit_stats, machine=machine) if knit_time else None,
    )


def order_candidates(candidates: Sequence[Any], order: str) -> list[Any]:
    """``candidates`` in ``order`` (see :data:`ORDERS`); by rank until all are measured."""
    from illuknit.design.tiles.perception import rank_candidates

    by_rank = sorted(candidates, key=lambda c: c.rank)
    if order == "rank" or not by_rank or any(c.measured is None for c in by_rank):
        return by_rank
    scores = [c.score if c.score is not None else float(c.rank) for c in by_rank]
    picks = rank_candidates(
        [c.measured for c in by_rank], scores, by="knit-time" if order == "knit_time" else order
    )
    return [by_rank[i] for i in picks]
