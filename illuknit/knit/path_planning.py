"""Yarn path planning (paper Algorithm 3): every stitch made with its carrier behind the carriage.

A carrier lays yarn only when it trails the carriage: for a rightward (``+``) pass it must sit
left of the first needle, for a leftward pass right of it (Fig. 16). In mixed colourwork carriers
do not move together: an intarsia carrier stays *anchored* where it last knit, possibly in the
middle of its next work. Knitting that work in one pass from either end then starts with the
carrier ahead of the carriage, no yarn is laid and the stitches drop (Fig. 21).

State per carrier (:class:`CarrierState`): its position (just right of the needle of its last
``+`` operation, just left after ``-``, as in knitout), the direction it last moved and the needle
of its last loop. :func:`plan_item` turns one piece of work of a course -- a carrier's segment or
a group of plated stitches -- into passes:

* **direction from the anchor**: a carrier left of its work knits rightward, right of it
  leftward;
* **anchor inside the work**: ``split`` knits the part on one side of the anchor first, turns and
  knits the other part (two passes, Algorithm 3 *Split*); ``anchor`` knits the one stitch at the
  far end of the work first, in the opposite direction, which carries the yarn to that end, then
  the rest (two passes, Algorithm 3 *Anchor*). Either way the first pass runs opposite to the
  carrier's last move;
* **plated stitches** need both carriers behind the carriage. When a carrier is on the wrong side
  (the two plated carriers on opposite sides) or last moved in the pass direction, it is first
  moved on its own with a ``miss`` pass in the opposite direction -- the anchoring move. (The paper
  anchors with a knit; a miss carries the yarn the same way without adding a loop to the fabric.)
  The same correction is applied before any pass whose carrier last moved in the same direction:
  that is the kickback pass the SWG backend would otherwise insert silently.

``none`` switches the planning off (the ablation of Fig. 20, middle): every pass runs in the
course's parity direction from wherever its carriers are, as a naive program would.
"""

from __future__ import annotations

from bisect import bisect_left, bisect_right
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Literal

from illuknit.core.errors import OptionError

__all__ = [
    "STRATEGIES",
    "CarrierState",
    "Park",
    "PlannedPass",
    "WorkItem",
    "advance",
    "is_behind",
    "move_is_free",
    "pass_cost",
    "plan_item",
]

Direction = Literal["+", "-"]
Strategy = Literal["anchor", "split", "none"]
STRATEGIES: tuple[str, ...] = ("anchor", "split", "none")


@dataclass(frozen=True)
class CarrierState:
    """Where a carrier is: ``needle`` and ``direction`` of its last operation, ``last_loop`` needle.

    A carrier never used has ``needle is None``; it enters from the right (the inserting hook
    needs its first stitches to go leftward), so it counts as right of everything. ``solo`` says
    its last pass carried it alone, so a following move in the same direction can be folded into
    that pass as a trailing ``miss`` (see :func:`move_is_free`).
    """

    needle: int | None = None
    direction: Direction | None = None
    last_loop: int | None = None
    solo: bool = False

    @property
    def position(self) -> float:
        """Location on the needle axis: half a needle past the last operation."""
        if self.needle is None:
            return float("inf")
        return self.needle + (0.5 if self.direction == "+" else -0.5)


@dataclass(frozen=True)
class WorkItem:
    """Work of one carrier set in one course: ``stitches`` are ``(needle, bed)``, ascending.

    ``tucks`` are needles among ``stitches`` that the pass tucks (front-bed tuck joins on a
    neighbouring region's edge needle) instead of knitting; ``follows`` are carriers whose own
    items must come before this one in the course (their tucks on its needles must be made
    before its stitches there). A ``pretuck`` item is the tall-bump tucks of its carrier: every
    stitch a tuck on a needle the carrier's own item then knits, so it comes right before that
    item.
    """

    carriers: tuple[str, ...]
    stitches: tuple[tuple[int, str], ...]
    plated: bool = False
    tucks: frozenset[int] = frozenset()
    follows: frozenset[str] = frozenset()
    pretuck: bool = False


@dataclass(frozen=True)
class PlannedPass:
    """A pass to emit: ``stitches`` in execution order; ``kind`` ``"knit"`` or ``"move"``.

    A ``move`` pass is a single ``miss`` at ``stitches[0][0]`` that carries one carrier to the
    side it must start from (an anchoring move / explicit kickback). ``tucks`` are the needles
    of ``stitches`` that are tucked rather than knit (tuck joins). ``park``, when set, is the
    needle of a trailing ``miss`` that carries the pass's carriers out beyond the fabric edge
    (see :data:`Park`): the carriers end there instead of at the last stitch.
    """

    carriers: tuple[str, ...]
    direction: Direction
    stitches: tuple[tuple[int, str], ...]
    kind: str = "knit"
    park: int | None = None
    tucks: frozenset[int] = frozenset()
    #: The pass holds a carrier's tall-bump tucks (a :attr:`WorkItem.pretuck` item).
    pretuck: bool = False

    @property
    def end(self) -> int:
        """Needle where the pass leaves its carriers."""
        return self.park if self.park is not None else self.stitches[-1][0]


#: Parking needles (left, right) just beyond the fabric edges. When the planner is given them,
#: every pass ends with its carriers parked beyond the edge it runs towards, so no carrier is
#: ever left inside the fabric where the machine would have to move it out of another pass's
#: way (the SWG backend kicks a carrier whenever anything happens on the side it last moved to).
Park = tuple[int, int]


def _flip(d: Direction) -> Direction:
    return "-" if d == "+" else "+"


def is_behind(state: CarrierState, direction: Direction, needle: int) -> bool:
    """True when a ``direction`` stitch at ``needle`` finds the carrier behind the carriage."""
    x = state.position
    return x < needle if direction == "+" else x > needle


def _move(
    car: str, state: CarrierState, direction: Direction, first: int, park: Park | None
) -> PlannedPass | None:
    """A miss pass placing ``car`` behind ``first`` for a ``direction`` pass, or None if fine.

    With parking the carrier moves all the way to the parking needle on the far side.
    """
    if state.needle is None:
        return None
    if is_behind(state, direction, first) and state.direction != direction:
        return None
    if park is not None:
        if direction == "+":
            return PlannedPass((car,), "-", ((park[0], "f"),), "move")
        return PlannedPass((car,), "+", ((park[1], "f"),), "move")
    if direction == "+":
        target = min(state.needle, first - 1)
        return PlannedPass((car,), "-", ((target, "f"),), "move")
    target = max(state.needle, first + 1)
    return PlannedPass((car,), "+", ((target, "f"),), "move")


def advance(states: Mapping[str, CarrierState], p: PlannedPass) -> dict[str, CarrierState]:
    """Carrier states after pass ``p``."""
    out = dict(states)
    last_needle = p.stitches[-1][0]
    for car in p.carriers:
        st = out.get(car, CarrierState())
        loop = st.last_loop if p.kind == "move" else last_needle
        solo = len(p.carriers) == 1 and st.needle is not None
        out[car] = CarrierState(p.end, p.direction, loop, solo)
    return out


def move_is_free(p: PlannedPass, states: Mapping[str, CarrierState]) -> bool:
    """True when move ``p`` continues its carrier's last solo pass (it folds into that pass)."""
    if p.kind != "move":
        return False
    st = states.get(p.carriers[0], CarrierState())
    if not st.solo or st.needle is None or st.direction != p.direction:
        return False
    target = p.stitches[0][0]
    return target > st.needle if p.direction == "+" else target < st.needle


def pass_cost(passes: Sequence[PlannedPass], states: Mapping[str, CarrierState]) -> int:
    """Carriage passes ``passes`` cost from ``states``: moves that fold away are free."""
    n = 0
    st = states
    for p in passes:
        if not move_is_free(p, st):
            n += 1
            # A pass in the direction its carrier last moved costs the backend a kickback.
            n += any(st.get(c, CarrierState()).direction == p.direction for c in p.carriers)
        st = advance(st, p)
    return n


def _parked(p: PlannedPass, park: Park | None) -> PlannedPass:
    """``p`` ending with its carriers parked beyond the edge it runs towards (if parking)."""
    if park is None or p.kind == "move":
        return p
    return replace(p, park=park[1] if p.direction == "+" else park[0])


def _with_moves(
    carriers: Sequence[str],
    direction: Direction,
    stitches: Sequence[tuple[int, str]],
    states: Mapping[str, CarrierState],
    park: Park | None,
) -> list[PlannedPass]:
    ordered = tuple(stitches) if direction == "+" else tuple(reversed(stitches))
    first = ordered[0][0]
    moves = [
        m for car in carriers if (m := _move(car, states[car], direction, first, park)) is not None
    ]
    return [*moves, _parked(PlannedPass(tuple(carriers), direction, ordered), park)]


def plan_item(
    item: WorkItem,
    states: Mapping[str, CarrierState],
    *,
    strategy: str,
    parity: Direction,
    park: Park | None = None,
) -> list[PlannedPass]:
    """Passes (anchoring moves included) that knit ``item`` with every carrier behind the carriage.

    Parameters
    ----------
    item : WorkItem
    states : mapping of str to CarrierState
        Current state of every carrier (missing = never used).
    strategy : {"anchor", "split", "none"}
    parity : {"+", "-"}
        The course's naive direction, used by ``none``.
    park : (int, int), optional
        Parking needles beyond the fabric edges: every pass ends with its carriers parked there
        (see :data:`Park`), and a carrier on the wrong side moves to the other parking needle.

    Returns
    -------
    list of PlannedPass
        In execution order; apply them with :func:`advance`.
    """
    if strategy not in STRATEGIES:
        raise OptionError(
            f"`path_planning` must be one of {', '.join(STRATEGIES)}, got {strategy!r}"
        )
    if not item.stitches:
        return []
    passes = _plan_item(item, states, strategy=strategy, parity=parity, park=park)
    if not item.tucks:
        return passes
    return [
        replace(p, tucks=item.tucks.intersection(n for n, _ in p.stitches), pretuck=item.pretuck)
        if p.kind != "move"
        else p
        for p in passes
    ]


def _plan_item(
    item: WorkItem,
    states: Mapping[str, CarrierState],
    *,
    strategy: str,
    parity: Direction,
    park: Park | None,
) -> list[PlannedPass]:
    st = {c: states.get(c, CarrierState()) for c in item.carriers}
    new = any(s.needle is None for s in st.values())
    if new:
        # The inserting hook needs the first stitches to go leftward from the right.
        ordered = tuple(reversed(item.stitches))
        return [_parked(PlannedPass(item.carriers, "-", ordered), park)]
    if strategy == "none":
        ordered = tuple(item.stitches) if parity == "+" else tuple(reversed(item.stitches))
        return [_parked(PlannedPass(item.carriers, parity, ordered), park)]

    purls = [n for n, b in item.stitches if b == "b"]
    candidates = [
        _with_moves(item.carriers, "+", item.stitches, st, park),
        _with_moves(item.carriers, "-", item.stitches, st, park),
    ]

    def key(ps: list[PlannedPass]) -> tuple[int, int, int, int]:
        # Fewest purls crossed by a pass's own float (those cannot be float-avoided), then
        # fewest passes, then the shortest yarn floats, then fewer moves.
        return (
            *_float_cost(ps, st, purls),
            _float_length(ps, st),
            sum(p.kind == "move" for p in ps),
        )

    if len(item.carriers) == 1:
        car = item.carriers[0]
        candidates += _inside(item, car, st[car], strategy, park)
    best = min(candidates, key=key)
    unpark = (
        _unpark(item.carriers[0], st[item.carriers[0]], park) if len(item.carriers) == 1 else None
    )
    if unpark is not None and key(best)[0] > 0:
        # A parked carrier whose yarn would float across purls of its own pass can first come
        # back to its last loop (one move) and be planned from there.
        car = item.carriers[0]
        back = advance(st, unpark)
        more = [
            [unpark, *ps]
            for ps in (
                _with_moves(item.carriers, "+", item.stitches, back, park),
                _with_moves(item.carriers, "-", item.stitches, back, park),
                *_inside(item, car, back[car], strategy, park),
            )
        ]
        best = min([best, *more], key=key)
    return best


def _inside(
    item: WorkItem, car: str, s: CarrierState, strategy: str, park: Park | None
) -> list[list[PlannedPass]]:
    """Plans for a carrier anchored inside its work (Algorithm 3 *Split* or *Anchor*)."""
    lo, hi = item.stitches[0][0], item.stitches[-1][0]
    x = s.position
    if not lo < x < hi:
        return []
    left = tuple(p for p in item.stitches if p[0] < x)
    right = tuple(p for p in item.stitches if p[0] > x)
    first: Direction = _flip(s.direction or "+")
    if strategy == "split":
        # Knit away from the anchor on the side the carrier can reach first, turn, and knit the
        # other side (the float back over the first part is float-avoided).
        plan = (
            [PlannedPass((car,), "-", tuple(reversed(left))), PlannedPass((car,), "+", right)]
            if first == "-"
            else [PlannedPass((car,), "+", right), PlannedPass((car,), "-", tuple(reversed(left)))]
        )
    elif first == "-":
        # Anchoring stitch: the far-end stitch alone, opposite to the rest.
        plan = [
            PlannedPass((car,), "-", (item.stitches[0],)),
            PlannedPass((car,), "+", tuple(item.stitches[1:])),
        ]
    else:
        plan = [
            PlannedPass((car,), "+", (item.stitches[-1],)),
            PlannedPass((car,), "-", tuple(reversed(item.stitches[:-1]))),
        ]
    return [[_parked(p, park) for p in plan]]


def _unpark(car: str, s: CarrierState, park: Park | None) -> PlannedPass | None:
    """The move bringing a parked carrier back to just beside its last loop, or None."""
    if park is None or s.needle is None or s.last_loop is None:
        return None
    if s.needle >= park[1] and s.direction == "+":
        return PlannedPass((car,), "-", ((s.last_loop + 1, "f"),), "move")
    if s.needle <= park[0] and s.direction == "-":
        return PlannedPass((car,), "+", ((s.last_loop - 1, "f"),), "move")
    return None


def _float_cost(
    passes: Sequence[PlannedPass], states: Mapping[str, CarrierState], purls: Sequence[int]
) -> tuple[int, int]:
    """(purls a pass's own float crosses, passes + transfer passes the floats force).

    A float from a carrier's last loop into its pass that crosses purls the *same* pass knits
    cannot be float-avoided (the loops must be on the front for the float and on the back for
    the stitch at once); one that crosses purls a *later* pass of the item knits costs a
    transfer pass to move them out of the way and back. ``purls`` are the item's purl needles,
    ascending; every pass of a plan knits a contiguous range of the item's needles.
    """
    last = {c: s.last_loop for c, s in states.items()}
    spans = [
        (min(p.stitches[0][0], p.stitches[-1][0]), max(p.stitches[0][0], p.stitches[-1][0]))
        if p.kind != "move"
        else None
        for p in passes
    ]

    def count(lo: int, hi: int) -> int:  # purls strictly between lo and hi
        return max(0, bisect_left(purls, hi) - bisect_right(purls, lo))

    fatal = 0
    extra = 0
    for i, p in enumerate(passes):
        span = spans[i]
        if span is None:
            continue
        first, end = p.stitches[0][0], p.stitches[-1][0]
        for c in p.carriers:
            prev = last.get(c)
            if purls and prev is not None and abs(first - prev) > 1:
                lo, hi = sorted((prev, first))
                fatal += count(max(lo, span[0] - 1), min(hi, span[1] + 1))
                for later in spans[i + 1 :]:
                    if later is not None and count(max(lo, later[0] - 1), min(hi, later[1] + 1)):
                        extra = 1
            last[c] = end
    return fatal, pass_cost(passes, states) + extra


def _float_length(passes: Sequence[PlannedPass], states: Mapping[str, CarrierState]) -> int:
    """Needles crossed by the floats from each carrier's last loop to its next stitch."""
    last = {c: s.last_loop for c, s in states.items()}
    total = 0
    for p in passes:
        if p.kind == "move":
            continue
        first, end = p.stitches[0][0], p.stitches[-1][0]
        for c in p.carriers:
            prev = last.get(c)
            if prev is not None:
                total += abs(first - prev)
            last[c] = end
    return total
