"""How each candidate reads and knits: the measures the designer ranks candidates by.

The numbers are the benchmark's own (:mod:`illuknit.bench.metrics`), so the app and the bench
agree on them:

* ``readability_a`` / ``readability_b``: correlation of the blurred angled render of each side
  with its target (the quantised picture; in single view both sides show picture A);
* ``readability``: the worse of the two, what a candidate is only as good as;
* ``ghosting_a`` / ``ghosting_b`` (double view): how much of the other picture shows through;
  ``ghosting`` the worse (larger) of the two;
* ``knit_minutes`` and ``machine_passes``: the machine's time and passes for the pattern on the
  chosen machine (None with a ``knit_note`` when it cannot be scheduled).

Orders (:data:`ORDERS`): ``rank`` (the search's own), ``readability`` (best worse-view first,
ties by ghosting), ``ghosting`` (least first), ``knit_time`` (fastest first).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

__all__ = ["ORDERS", "measure_candidate", "order_candidates"]

#: Ways the page can order candidates.
ORDERS = ("rank", "readability", "ghosting", "knit_time")


def _clean(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(x) else round(float(x), 4)


def measure_candidate(pattern: Any, prepared: Any, *, machine: str) -> dict[str, Any]:
    """Readability, ghosting and knitting time of one candidate's pattern."""
    from illuknit.bench.metrics import angled_renders, knit_stats, picture_scores

    out: dict[str, Any] = {}
    if prepared.mode in ("single", "double"):
        renders, _ = angled_renders(pattern)
        ta = prepared.quantised["a"].rgb().astype(np.float64) / 255.0
        double = prepared.mode == "double"
        tb = prepared.quantised["b"].rgb().astype(np.float64) / 255.0 if double else ta
        s = picture_scores(renders, ta, tb, double=double)
        ra, rb = _clean(s["render_corr_a"]), _clean(s["render_corr_b"])
        ga, gb = _clean(s["ghost_a"]), _clean(s["ghost_b"])
        out.update(
            readability_a=ra,
            readability_b=rb,
            readability=None if ra is None or rb is None else min(ra, rb),
            ghosting_a=ga,
            ghosting_b=gb,
            ghosting=None if ga is None or gb is None else max(abs(ga), abs(gb)),
        )
    k = knit_stats(pattern, machine=machine)
    out.update(
        knit_minutes=_clean(k["knit_time_min"]),
        machine_passes=k["carriage_passes"],
        knit_note=k["knit_note"],
    )
    return out


def order_candidates(candidates: Sequence[Any], order: str) -> list[Any]:
    """``candidates`` (with ``.rank`` and ``.measures``) in ``order``; unmeasured ones last."""
    if order == "rank":
        return sorted(candidates, key=lambda c: c.rank)
    big = float("inf")

    def value(c: Any, key: str, sign: float) -> float:
        v = (c.measures or {}).get(key)
        return big if v is None else sign * float(v)

    keys: dict[str, Callable[[Any], tuple[float, ...]]] = {
        "readability": lambda c: (value(c, "readability", -1), value(c, "ghosting", 1), c.rank),
        "ghosting": lambda c: (value(c, "ghosting", 1), value(c, "readability", -1), c.rank),
        "knit_time": lambda c: (value(c, "knit_minutes", 1), c.rank),
    }
    return sorted(candidates, key=keys[order])
