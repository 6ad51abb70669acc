"""Catching: join colour regions knit by different carriers (tuck joins, or plating: Alg. 2).

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

**Tuck joins** (the default, :func:`plan_joins`). A plated pair is a pass of its own, and its
second yarn has to travel from wherever that carrier was parked -- across the piece, beyond
the float limit -- to the boundary. Machine knitters join intarsia regions with a *tuck*
instead: in its own pass, one carrier tucks on the neighbouring region's edge needle (one
needle beyond its run); the neighbour's next stitch on that needle knits through the tuck, so
the two yarns interlock with no extra pass and no yarn travelling anywhere. The tuck must end
up behind a face stitch: it goes on a front needle whose stitch in this course is a knit and
whose next stitch (this course's, if the tuck comes first, or else the next course's) is a
knit too -- never where a purl would pull it through from the back, which would show the
tucked colour inside the purl bump on the face. Of a boundary's two edge needles the first safe
one is used (the intarsia side tucks onto the crossing neighbour, as plating chooses); a
boundary with no safe needle falls back to a plated stitch.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from itertools import pairwise

from illuknit.knit.color_runs import CoursePlan

__all__ = ["JOIN_METHODS", "JoinTuck", "PlatedStitch", "plan_catches", "plan_joins"]

#: How colour regions are joined: ``tuck`` (tuck joins, plating where no tuck is safe) or
#: ``plate`` (the paper's plated stitches everywhere).
JOIN_METHODS: tuple[str, ...] = ("tuck", "plate")


@dataclass(frozen=True, order=True)
class PlatedStitch:
    """One plated catching stitch: ``carriers = (primary, secondary)`` at ``wale``."""

    wale: int
    carriers: tuple[str, str]


@dataclass(frozen=True, order=True)
class JoinTuck:
    """One tuck join: ``carrier`` tucks on the front needle of ``wale`` (a neighbour's stitch).

    ``first``: the tuck must be made before this course's stitch on ``wale`` (which then pulls
    it through from the front); otherwise either order is safe.
    """

    wale: int
    carrier: str
    first: bool = False


def _boundaries(
    plan: CoursePlan,
) -> list[tuple[int, int, str, str, bool, bool]]:
    """Boundaries to catch: ``(hi, lo, left, right, left_crosses, right_crosses)``.

    ``hi`` is the left run's last wale, ``lo`` the right run's first. Boundaries that both
    carriers cross (stranded colourwork: the yarns already interlock there) are left out.
    """
    runs = sorted(
        ((lo, hi, s.carrier) for s in plan.segments for lo, hi in s.runs), key=lambda r: r[0]
    )
    span = {s.carrier: (s.lo, s.hi) for s in plan.segments}
    out = []
    for (_, hi, left), (lo, _, right) in pairwise(runs):
        if left == right:
            continue
        left_crosses = span[left][1] > hi  # the left carrier also knits right of the boundary
        right_crosses = span[right][0] < lo  # the right carrier also knits left of it
        if not (left_crosses and right_crosses):
            out.append((hi, lo, left, right, left_crosses, right_crosses))
    return out


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
    own_count = {s.carrier: len(s.wales) for s in plan.segments}
    out: list[PlatedStitch] = []
    for hi, lo, left, right, left_crosses, right_crosses in _boundaries(plan):
        wale, prim, sec = _plated(hi, lo, left, right, left_crosses, right_crosses)
        if any(p.wale == wale for p in out) or (prim in new_carriers and own_count[prim] <= 1):
            continue
        out.append(PlatedStitch(wale, (prim, sec)))
        own_count[prim] -= 1
    return sorted(out)


def _plated(
    hi: int, lo: int, left: str, right: str, left_crosses: bool, right_crosses: bool
) -> tuple[int, str, str]:
    """(wale, primary, secondary) of the plated stitch catching one boundary.

    Plate the stitch of the carrier that stays on its side of the boundary (the intarsia one)
    with the neighbour that crosses it: a region's two edges then share one carrier pair, hence
    one pass. Between two intarsia carriers, Algorithm 2's choice: the first stitch of the new
    colour (walking left to right) with the previous colour.
    """
    if left_crosses and not right_crosses:
        return lo, right, left
    if right_crosses and not left_crosses:
        return hi, left, right
    return lo, right, left


def plan_joins(
    plan: CoursePlan,
    *,
    knit_now: Sequence[bool],
    knit_next: Sequence[bool],
    new_carriers: frozenset[str] = frozenset(),
    ordered: bool = True,
) -> tuple[list[JoinTuck], list[PlatedStitch]]:
    """Tuck joins for one course's boundaries; plated stitches where no tuck is safe.

    Parameters
    ----------
    plan : CoursePlan
        The course's segments.
    knit_now, knit_next : sequence of bool, length W
        Whether each wale's stitch is a knit (front bed) in this course and in the next one
        (the bind-off counts as knits). A tuck on wale ``w`` is safe only when both are knits:
        whichever stitch knits through the tuck then pulls it behind a face stitch.
    new_carriers : frozenset of str
        Carriers first used in this course (for the plated fallback, see :func:`plan_catches`).
    ordered : bool
        Also tuck where only this course knits the wale, as a tuck that must be made before
        that stitch (``JoinTuck.first``; the course's passes are then ordered so). The tucks'
        orders never form a cycle.

    Returns
    -------
    tucks : list of JoinTuck
        Ascending by wale; at most one per wale.
    plated : list of PlatedStitch
        The fallback plated stitches, ascending by wale. A boundary whose two edge wales are
        both purled in this course gets neither (the knit courses around it join it).
    """
    own_count = {s.carrier: len(s.wales) for s in plan.segments}
    owner = {w: s.carrier for s in plan.segments for w in s.wales}
    tucks: list[JoinTuck] = []
    plated: list[PlatedStitch] = []
    used: set[int] = set()
    follows: dict[str, set[str]] = {}  # carrier -> carriers whose tucks must come before it
    for hi, lo, left, right, left_crosses, right_crosses in _boundaries(plan):
        # The intarsia side tucks onto the crossing neighbour's stitch first (as plating picks
        # the intarsia side's stitch); between two intarsia carriers the left one tucks first.
        options = [(lo, left), (hi, right)]
        if left_crosses and not right_crosses:
            options.reverse()
        free = [(w, c) for w, c in options if w not in used and bool(knit_now[w])]
        pick = next((JoinTuck(w, c) for w, c in free if knit_next[w]), None)
        if pick is None and ordered:
            # Next course purls the wale: safe only if this course's knit there comes after
            # the tuck (pulling it through from the front before the loop moves to the back),
            # an order that must not contradict the other tucks' orders.
            pick = next(
                (JoinTuck(w, c, first=True) for w, c in free if not _reaches(follows, c, owner[w])),
                None,
            )
            if pick is not None:
                follows.setdefault(owner[pick.wale], set()).add(pick.carrier)
        if pick is not None:
            used.add(pick.wale)
            tucks.append(pick)
            continue
        if not (knit_now[lo] or knit_now[hi]):
            # Both edges purl in this course (a bump row joined every course): the course's
            # knit neighbours join it; a plated purl would float its second yarn across purls
            # of its own pass, which float avoidance cannot move out of the way.
            continue
        wale, prim, sec = _plated(hi, lo, left, right, left_crosses, right_crosses)
        if any(p.wale == wale for p in plated) or (prim in new_carriers and own_count[prim] <= 1):
            continue
        plated.append(PlatedStitch(wale, (prim, sec)))
        own_count[prim] -= 1
    return sorted(tucks), sorted(plated)


def _reaches(follows: dict[str, set[str]], a: str, b: str) -> bool:
    """True when ``a`` must already come after ``b`` (``a == b`` included), so ``a`` -> ``b``
    would close a cycle. ``follows[x]`` are the carriers that must come before ``x``."""
    seen: set[str] = set()
    todo = [a]
    while todo:
        x = todo.pop()
        if x == b:
            return True
        if x not in seen:
            seen.add(x)
            todo.extend(follows.get(x, ()))
    return False
