"""Catching by plating (paper Algorithm 2): join colour regions knit by different carriers.

Carriers ride on separate rails so that their yarns never tangle; two regions knit back and forth
by different carriers therefore never touch, and the piece falls apart along the join (paper
Fig. 15, Fig. 20 right). The paper's cure is a *plated* stitch at the colour change: the first
stitch of the new colour is knit with both yarns, pulled through one loop together, so the yarns
interlock there. The yarn laid first shows most on the face, so the stitch's own yarn is the
**primary** and is listed first -- consistently, for every plated stitch -- and the neighbouring
yarn is the secondary.

Walking each course from left to right (Algorithm 2's ``loopNeighborPairs``), at every boundary
between two runs knit by different carriers, one edge stitch is plated with the carrier on the
other side: when one carrier crosses the boundary (stranded) and the other stays on its side
(intarsia), the intarsia carrier's edge stitch is plated with the crossing neighbour -- the
stitch of a colour change in one direction or the other -- so that both edges of an intarsia
region use the same carrier pair and share a pass; between two intarsia carriers, the right-hand
run's first stitch becomes ``(own carrier, left neighbour's carrier)``, as in Algorithm 2. A boundary is left alone when both carriers already
cross it in that course (stranded colourwork: each yarn floats behind the other's stitches there,
so the yarns already interlock and a plated stitch would only add a pass); every intarsia boundary
and every boundary where one side's yarn stops is caught.

The SWG backend merges only operations with the identical carrier list into one pass, so the
plated stitches of a course are grouped by their carrier pair: each pair costs one pass per
course, not one per stitch. A carrier comes in with ``inhook`` of exactly the set of its first use;
the scheduler makes that first use the carrier's own (unplated) pass, so a plated stitch never
involves a carrier that has not knit yet.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import pairwise

from illuknit.knit.color_runs import CoursePlan

__all__ = ["PlatedStitch", "plan_catches"]


@dataclass(frozen=True, order=True)
class PlatedStitch:
    """One plated catching stitch: ``carriers = (primary, secondary)`` at ``wale``."""

    wale: int
    carriers: tuple[str, str]


def plan_catches(
    plan: CoursePlan, *, new_carriers: frozenset[str] = frozenset()
) -> list[PlatedStitch]:
    """Plated stitches that join the carriers of one course (Algorithm 2).

    Parameters
    ----------
    plan : CoursePlan
        The course's segments.
    new_carriers : frozenset of str
        Carriers first used in this course. A plated stitch needs both carriers to have knit
        before; a boundary whose right-hand run is a new carrier's whole work is skipped.

    Returns
    -------
    list of PlatedStitch
        Ascending by wale.
    """
    runs = sorted(
        ((lo, hi, s.carrier) for s in plan.segments for lo, hi in s.runs), key=lambda r: r[0]
    )
    span = {s.carrier: (s.lo, s.hi) for s in plan.segments}
    own_count = {s.carrier: len(s.wales) for s in plan.segments}
    out: list[PlatedStitch] = []
    for (_, hi, left), (lo, _, right) in pairwise(runs):
        if left == right:
            continue
        l_hi = span[left][1]
        r_lo = span[right][0]
        left_crosses = l_hi > hi  # the left carrier also knits right of the boundary
        right_crosses = r_lo < lo  # the right carrier also knits left of it
        if left_crosses and right_crosses:
            continue
        # Plate the stitch of the carrier that stays on its side of the boundary (the intarsia
        # one) with the neighbour that crosses it: a region's two edges then share one carrier
        # pair, hence one pass. Between two intarsia carriers, Algorithm 2's choice: the first
        # stitch of the new colour (walking left to right) with the previous colour.
        if left_crosses and not right_crosses:
            wale, prim, sec = lo, right, left
        elif right_crosses and not left_crosses:
            wale, prim, sec = hi, left, right
        else:
            wale, prim, sec = lo, right, left
        if any(p.wale == wale for p in out) or (prim in new_carriers and own_count[prim] <= 1):
            continue
        out.append(PlatedStitch(wale, (prim, sec)))
        own_count[prim] -= 1
    return sorted(out)
