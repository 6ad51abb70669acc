"""Ordering one course's work for fewest passes (the mixed-colourwork scheduler's search).

A course's work items are every carrier's segment (minus its plated stitches) and one item per
plated carrier pair (:func:`course_items`). :func:`order_and_plan` orders them for fewest passes
-- branch and bound over every order up to :data:`EXHAUSTIVE_ITEMS` items, a beam search beyond,
each order also charged what the next course's own work would cost from where it leaves the
carriers -- and plans each with :func:`~illuknit.knit.path_planning.plan_item`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

from illuknit.core.errors import SchedulingError
from illuknit.knit.catching import JoinTuck, PlatedStitch
from illuknit.knit.path_planning import (
    CarrierState,
    Park,
    PlannedPass,
    WorkItem,
    advance,
    pass_cost,
    plan_item,
)

__all__ = ["BEAM_WIDTH", "EXHAUSTIVE_ITEMS", "course_items", "order_and_plan"]


def course_items(
    plan_segments: Sequence[tuple[str, list[int]]],
    catches: Sequence[PlatedStitch],
    beds: Sequence[str],
    left: int,
    tucks: Sequence[JoinTuck] = (),
    tuck_first: Sequence[bool] | None = None,
) -> list[WorkItem]:
    """Work items of a course: each carrier's own stitches, then one item per plated pair.

    A carrier's tuck joins (front-bed tucks on a neighbour's needle) join its own item. Where
    ``tuck_first`` marks a wale (tall bumps), the carrier's own stitch there is preceded by a
    tuck on its needle: one ``pretuck`` item per carrier, listed before its own item.
    """
    plated_wales = {p.wale for p in catches}
    tucked: dict[str, set[int]] = {}
    for t in tucks:
        tucked.setdefault(t.carrier, set()).add(left + t.wale)
    items: list[WorkItem] = []
    for car, wales in plan_segments:
        own = [(left + w, beds[w]) for w in wales if w not in plated_wales]
        if tuck_first is not None:
            pre = tuple(
                (left + w, beds[w]) for w in wales if tuck_first[w] and w not in plated_wales
            )
            if pre:
                items.append(
                    WorkItem((car,), pre, tucks=frozenset(n for n, _ in pre), pretuck=True)
                )
        extra = tucked.get(car, set())
        if own or extra:
            st = tuple(sorted([*own, *((n, "f") for n in extra)]))
            items.append(WorkItem((car,), st, tucks=frozenset(extra)))
    groups: dict[tuple[str, str], list[int]] = {}
    for p in catches:
        groups.setdefault(p.carriers, []).append(p.wale)
    for cars, wales in groups.items():
        items.append(WorkItem(cars, tuple((left + w, beds[w]) for w in sorted(wales)), plated=True))
    # A tuck that must come first: the item knitting its needle follows the tucking carrier.
    firsts = [(left + t.wale, t.carrier) for t in tucks if t.first]
    return [
        replace(
            it,
            follows=frozenset(
                c for n, c in firsts if any(m == n for m, _ in it.stitches) and n not in it.tucks
            ),
        )
        if firsts
        else it
        for it in items
    ]


#: Courses with at most this many work items are ordered by exhaustive search (branch and
#: bound over permutations); larger ones greedily.
EXHAUSTIVE_ITEMS = 6
#: Partial orders kept per step when a course has more items than that (scaled down as the
#: item count grows, to keep the time per course bounded).
BEAM_WIDTH = 8


def order_and_plan(
    items: list[WorkItem],
    states: dict[str, CarrierState],
    strategy: str,
    parity: str,
    lookahead: Sequence[WorkItem] = (),
    park: Park | None = None,
) -> tuple[list[PlannedPass], dict[str, CarrierState]]:
    """Order a course's items for fewest passes; a carrier's own item comes before plating.

    Up to :data:`EXHAUSTIVE_ITEMS` items every order is tried (branch and bound on the pass
    count, plans cached per item and carrier states); beyond, a beam search keeps the
    :data:`BEAM_WIDTH` cheapest partial orders. ``none`` keeps the given order.
    """
    if strategy == "none":
        planned: list[PlannedPass] = []
        st = dict(states)
        order = [it for it in items if len(it.carriers) == 1] + [
            it for it in items if len(it.carriers) > 1
        ]
        for it in order:
            for p in plan_item(it, st, strategy=strategy, parity=parity, park=park):  # type: ignore[arg-type]
                st = advance(st, p)
                planned.append(p)
        return planned, st
    orders = _Orders(items, strategy, parity, lookahead, park)
    if len(items) <= EXHAUSTIVE_ITEMS:
        return _branch_and_bound(orders, states)
    return _beam_search(orders, states)


#: A planned item: its passes, their cost and the item carriers' new states.
_Entry = tuple[list[PlannedPass], int, dict[str, CarrierState]]


class _Orders:
    """What both searches ask about a course's items, with the answers cached.

    :meth:`plan` plans an item from given carrier states, :meth:`ready` says whether an item
    may come next, :meth:`ahead` charges what the next course's own work would cost.
    """

    def __init__(
        self,
        items: list[WorkItem],
        strategy: str,
        parity: str,
        lookahead: Sequence[WorkItem],
        park: Park | None,
    ) -> None:
        self.items = items
        self.strategy = strategy
        self.parity = parity
        self.lookahead = lookahead
        self.park = park
        self.unused = CarrierState()
        self.cache: dict[tuple[int, tuple[CarrierState, ...]], _Entry] = {}
        self.ahead_cache: dict[tuple[int, CarrierState], int] = {}
        self.own = {
            it.carriers[0]: i
            for i, it in enumerate(items)
            if len(it.carriers) == 1 and not it.pretuck
        }
        #: carrier -> index of its tall-bump tuck item (its own item comes right after it)
        self.pre = {it.carriers[0]: i for i, it in enumerate(items) if it.pretuck}

    def _plan_item(self, it: WorkItem, st: dict[str, CarrierState]) -> list[PlannedPass]:
        return plan_item(it, st, strategy=self.strategy, parity=self.parity, park=self.park)  # type: ignore[arg-type]

    def plan(self, i: int, st: dict[str, CarrierState]) -> _Entry:
        """Passes of item ``i`` from ``st``, their cost and the item carriers' new states."""
        it = self.items[i]
        unused = self.unused
        key = (i, tuple(st.get(c, unused) for c in it.carriers))
        got = self.cache.get(key)
        if got is None:
            ps = self._plan_item(it, st)
            sub = {c: st.get(c, unused) for c in it.carriers}
            cost = pass_cost(ps, sub)
            for p in ps:
                sub = advance(sub, p)
            got = (ps, cost, sub)
            self.cache[key] = got
        return got

    def ready(self, i: int, st: dict[str, CarrierState], left: list[int]) -> bool:
        """True when item ``i`` may come next (its carriers knit, what it follows is done)."""
        it = self.items[i]
        if any(self.own.get(c) in left for c in it.follows):
            return False
        if self.pre:
            # A carrier's own item follows its tall-bump tucks at once: no other pass (nor a
            # transfer for its floats) comes between a tuck and the knit that clears it.
            car = it.carriers[0]
            if not it.pretuck and self.pre.get(car) in left:
                return False
            waiting = [
                self.own[c]
                for c, j in self.pre.items()
                if j not in left and self.own.get(c) in left
            ]
            if waiting and i not in waiting:
                return False
        return len(it.carriers) == 1 or all(
            st.get(c, self.unused).needle is not None for c in it.carriers
        )

    def ahead(self, st: dict[str, CarrierState]) -> int:
        """Extra passes the next course's own segments would need from these states."""
        extra = 0
        for k, it in enumerate(self.lookahead):
            car = it.carriers[0]
            cs = st.get(car, self.unused)
            if cs.needle is None:
                continue
            key = (k, cs)
            got = self.ahead_cache.get(key)
            if got is None:
                ps = self._plan_item(it, {car: cs})
                got = pass_cost(ps, {car: cs}) - 1
                self.ahead_cache[key] = got
            extra += got
        return extra


def _branch_and_bound(
    orders: _Orders, states: dict[str, CarrierState]
) -> tuple[list[PlannedPass], dict[str, CarrierState]]:
    """The cheapest order of every order of the items (next course's cost included)."""
    best: list[object] = [None, None, None]  # cost, passes, states

    def search(
        left: list[int], st: dict[str, CarrierState], acc: list[PlannedPass], cost: int
    ) -> None:
        if best[0] is not None and cost >= best[0]:  # type: ignore[operator]
            return
        if not left:
            total = cost + orders.ahead(st)
            if best[0] is None or total < best[0]:  # type: ignore[operator]
                best[0], best[1], best[2] = total, list(acc), st
            return
        for i in left:
            if not orders.ready(i, st, left):
                continue
            ps, c, sub = orders.plan(i, st)
            search([j for j in left if j != i], {**st, **sub}, acc + ps, cost + c)

    search(list(range(len(orders.items))), dict(states), [], 0)
    if best[1] is None:  # pragma: no cover - catching never pairs an unused carrier
        raise SchedulingError("plated stitch with a carrier that never knit")
    return best[1], best[2]  # type: ignore[return-value]


def _beam_search(
    orders: _Orders, states: dict[str, CarrierState]
) -> tuple[list[PlannedPass], dict[str, CarrierState]]:
    """Keep the cheapest partial orders at each depth (fewer the more items there are)."""
    n_items = len(orders.items)
    beam: list[tuple[int, list[int], dict[str, CarrierState], list[PlannedPass]]] = [
        (0, list(range(n_items)), dict(states), [])
    ]
    width = max(2, BEAM_WIDTH * EXHAUSTIVE_ITEMS // n_items)
    for _ in range(n_items):
        grown = []
        for cost, left, st, acc in beam:
            for i in left:
                if not orders.ready(i, st, left):
                    continue
                ps, c, sub = orders.plan(i, st)
                grown.append((cost + c, [j for j in left if j != i], {**st, **sub}, acc + ps))
        if not grown:  # pragma: no cover - catching never pairs an unused carrier
            raise SchedulingError("plated stitch with a carrier that never knit")
        grown.sort(key=lambda t: t[0])
        beam = grown[:width]
    _, _, st, planned = min(beam, key=lambda t: t[0] + orders.ahead(t[2]))
    return planned, st
