"""One carrier bookkeeping for the machine pass builders (the SWG ``.dat``, the Kniterate ``.kc``).

Both builders keep, for each live carrier, where its yarn is attached (the last needle it stitched
and the direction it went) and where the carrier itself is parked (it may have travelled on past
that needle, so before a pass in the same direction it is "kicked": a yarn-less soft miss the other
way). Both kick a carrier before its own pass when it may be parked on the wrong side
(:meth:`CarrierBook.kicks_before`) and kick every other carrier whose yarn hangs across a needle
about to be used out of its way (:meth:`CarrierBook.in_the_way`). Where the two reference backends
agree, the rule is written once here; where they differ, the difference is a field of the
machine's :class:`CarrierPolicy` (:data:`SWG_CARRIERS`, :data:`KNITERATE_CARRIERS`):

- **kick order**: the kicks before one pass are made slot by slot; the SWG backend takes the
  non-negative slots ascending, then the negative ones in the order they were added (the order
  JavaScript gives an object's integer keys), the Kniterate backend sorts them;
- **hook**: only the SWG machine has a yarn-inserting hook, so only it tracks which carriers the
  hook still holds (``used_hook``);
- **roller on kicks**: the Kniterate writes a roller advance per pass and its kick passes use 0;
  the SWG machine has no such value.

Directions are the knitout program's :class:`~illuknit.knitout.program.Direction` (``+``, ``-``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass

from illuknit.knitout.program import Bed, Direction, Needle

__all__ = [
    "KNITERATE_CARRIERS",
    "SWG_CARRIERS",
    "CarrierBook",
    "CarrierPolicy",
    "CarrierState",
    "js_key_order",
    "slot_of",
]

#: the kicks before one pass, by the slot each kick pass runs at, carriers in order added
Kicks = dict[int, list[str]]


def js_key_order(kicks: Kicks) -> list[int]:
    """Non-negative slots ascending, then negative ones as added (JavaScript's integer keys)."""
    return sorted(s for s in kicks if s >= 0) + [s for s in kicks if s < 0]


def _sorted_slots(kicks: Kicks) -> list[int]:
    return sorted(kicks)


@dataclass(frozen=True, slots=True)
class CarrierPolicy:
    """Where one machine's carrier bookkeeping differs from the other's (see the module)."""

    machine: str
    kick_order: Callable[[Kicks], list[int]]
    tracks_hook: bool
    kick_roller: float | None  # roller advance of a kick pass (None: the machine has none)


SWG_CARRIERS = CarrierPolicy("swg", kick_order=js_key_order, tracks_hook=True, kick_roller=None)
KNITERATE_CARRIERS = CarrierPolicy(
    "kniterate", kick_order=_sorted_slots, tracks_hook=False, kick_roller=0
)


def slot_of(n: Needle, rack_floor: int) -> int:
    """Raster slot of a needle: back needles shift with the (floored) racking."""
    return n.index if n.bed[0] == "f" else n.index + rack_floor


@dataclass(slots=True)
class CarrierState:
    """One live carrier: announced (``pending_in`` until first use), attached, parked."""

    name: str
    pending_in: tuple[str, tuple[str, ...]] | None = None  # (in op, carrier set) until first use
    used_hook: bool = False  # the inserting hook still holds it (machines with a hook only)
    last: tuple[Needle, Direction | None] | None = None  # where the yarn is attached
    kick: tuple[Needle, Direction | None] | None = None  # where the carrier is parked


class CarrierBook(dict[str, CarrierState]):
    """The live carriers by name, with the kick rules both machines share."""

    def __init__(self, policy: CarrierPolicy) -> None:
        super().__init__()
        self.policy = policy
        self._sorted_from: tuple[str, ...] = ()
        self._sorted: list[str] = []

    def bring_in(self, op: str, carriers: tuple[str, ...]) -> None:
        """Announce ``carriers`` (``in`` or ``inhook``); they come in on their first use."""
        hook = self.policy.tracks_hook and op == "inhook"
        for c in carriers:
            self[c] = CarrierState(c, (op, carriers), used_hook=hook)

    def in_order(self) -> list[str]:
        """The live carriers in carrier-number order (kept while the live set is unchanged)."""
        live = tuple(self)
        if live != self._sorted_from:
            self._sorted_from = live
            self._sorted = sorted(live, key=int)
        return self._sorted

    def kicks_before(
        self,
        carriers: tuple[str, ...],
        direction: Direction | None,
        pass_slot: int,
        rack_floor: int,
    ) -> Kicks:
        """The kicks the carriers of a new pass need first, by slot: a carrier parked after a
        pass in the same direction may have stopped anywhere beyond, so it is always kicked; one
        parked the other way is kicked back to the pass's slot when it stands beyond it."""
        kicks: Kicks = {}
        for c in carriers:
            car = self[c]
            if car.last is None or car.kick is None:
                continue  # being brought in: nothing to kick yet
            kick_slot = slot_of(car.kick[0], rack_floor)
            if car.kick[1] is direction:
                kicks.setdefault(kick_slot, []).append(c)
            elif (direction is Direction.RIGHT and kick_slot > pass_slot) or (
                direction is Direction.LEFT and kick_slot < pass_slot
            ):
                kicks.setdefault(pass_slot, []).append(c)
        return kicks

    def kick_order(self, kicks: Kicks) -> list[int]:
        """The slots of ``kicks`` in the order this machine makes them."""
        return self.policy.kick_order(kicks)

    def in_the_way(
        self, needle_slot: int, carriers: tuple[str, ...], rack_floor: int
    ) -> Iterator[tuple[str, Direction, int]]:
        """(carrier, way, slot) for each other live carrier to kick out of the way of a needle:
        its yarn hangs just left (``-``) or right (``+``) of its last needle, and it is kicked
        that way from there unless it is already parked on that side. The caller makes the kick
        and :meth:`park` s the carrier before the next is looked at."""
        for name in self.in_order():
            car = self[name]
            if name in carriers or car.last is None or car.kick is None:
                continue
            last = car.last[0]
            last_slot = last.index if last.bed[0] == "f" else last.index + rack_floor
            left_of = last_slot < needle_slot or (
                last_slot == needle_slot and car.last[1] is Direction.LEFT
            )
            kick_slot = slot_of(car.kick[0], rack_floor)
            if left_of:
                if car.kick[1] is Direction.LEFT and kick_slot <= needle_slot:
                    continue
                yield name, Direction.LEFT, last_slot
            else:
                if car.kick[1] is Direction.RIGHT and kick_slot >= needle_slot:
                    continue
                yield name, Direction.RIGHT, last_slot

    def park(self, carriers: tuple[str, ...] | list[str], slot: int, way: Direction | None) -> None:
        """The carriers were kicked at front slot ``slot`` going ``way``."""
        for c in carriers:
            self[c].kick = (Needle(Bed.FRONT, slot), way)

    def set_last(self, carriers: tuple[str, ...], direction: Direction | None, n: Needle) -> None:
        """The carriers stitched at ``n`` going ``direction``: attached and parked there."""
        for c in carriers:
            self[c].last = (n, direction)
            self[c].kick = (n, direction)

    def follow_loop(self, source: Needle, target: Needle) -> None:
        """A yarn attached to the loop moved from ``source`` is now attached at ``target``."""
        for car in self.values():
            if car.last is not None and car.last[0] == source:
                car.last = (target, car.last[1])
