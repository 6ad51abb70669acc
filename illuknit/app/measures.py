"""How each candidate reads and knits, and the orders the designer ranks candidates by.

The measures and the default ranking are the library's (:mod:`illuknit.design.tiles.perception`), so
the app, ``illuknit double --rank-by`` and the bench agree:

* per side: **readability** (correlation of the blurred angled render with the quantised
  picture), **contrast** (how much of its light/dark difference survives) and, in a double view,
  **ghosting** (how much of the other picture shows through);
* the **perceptual score**: the worse side's readability, penalised for contrast below a floor
  and for how much of the other picture shows (the documented default order);
* the machine's **knitting time** and passes on the chosen machine.

In a single view both sides show picture A and nothing can ghost. A head-on design with no side
picture gets its knitting time only.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from typing import Any

from illuknit.bench.metrics import knit_stats

__all__ = ["ORDERS", "measure_candidate", "order_candidates"]

#: Ways the page can order candidates: the search's own rank, or a perception.RANK_KEYS order.
ORDERS = ("rank", "perception", "readability", "contrast", "ghosting", "knit_time")


def measure_candidate(pattern: Any, prepared: Any, *, machine: str) -> Any:
    """The candidate's :class:`~illuknit.design.tiles.perception.CandidateMeasures`."""
    from illuknit.design.tiles import perception

    q = prepared.quantised
    if prepared.mode == "double":
        pictures, views, ghost = [q["a"].rgb(), q["b"].rgb()], ("A", "B"), True
    elif prepared.mode == "headon" and "b" in q:
        pictures, views, ghost = [q["a"].rgb(), q["b"].rgb()], ("headon", "side"), True
    elif prepared.mode == "single":
        pictures, views, ghost = [q["a"].rgb(), q["a"].rgb()], ("A", "B"), False
    else:
        k = knit_stats(pattern, machine=machine)
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
        knit_time=functools.partial(knit_stats, machine=machine),
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
