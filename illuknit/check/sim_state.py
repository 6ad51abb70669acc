"""The simulator's machine state and the records it writes.

:class:`MachineState` is what :func:`~illuknit.check.simulate.simulate_program` keeps while it
runs a program (the module docstring there says what each part means): the loops on every
needle, the racking, each carrier (:class:`SimCarrier`), the inserting hook, and a union-find
over the loop graph. It records machine-rule :class:`Event` s and raw fabric observations
(:class:`~illuknit.knitout.floats.Float` via its
:class:`~illuknit.knitout.floats.FloatTracker`, :class:`FaceFloat`, :class:`WrongSide`); :class:`CarrierEnd` reports a carrier
left in at the end.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from illuknit.knitout.floats import FloatTracker, needle_slot
from illuknit.knitout.parse import Needle

__all__ = [
    "MAX_EVENTS_PER_CODE",
    "CarrierEnd",
    "Drop",
    "Event",
    "FaceFloat",
    "KnitRun",
    "MachineState",
    "SimCarrier",
    "WrongSide",
]

#: Findings of one code beyond this many are counted, not stored (a systematic error in a large
#: program would otherwise produce tens of thousands of identical lines).
MAX_EVENTS_PER_CODE = 200


@dataclass(frozen=True)
class Event:
    """A machine-rule event: ``code`` (see ``rules.RULES``) at a 1-based line."""

    line: int
    code: str
    message: str


@dataclass(frozen=True)
class FaceFloat:
    """A float of ``carrier`` passing in front of loops held on back needles ``needles``."""

    line: int
    carrier: str
    needles: tuple[str, ...]


@dataclass(frozen=True)
class WrongSide:
    """A stitch made while ``carrier`` sat ahead of the needle in the pass direction."""

    line: int
    carrier: str
    needle: str
    direction: str
    carrier_location: float
    carrier_direction: str


@dataclass(frozen=True)
class Drop:
    """A ``drop`` (or a knit without yarn) that released live ``loops`` from ``needle``.

    ``made`` is how many loops the program had made by then (the loops made later have ids
    ``>= made``)."""

    line: int
    needle: str
    loops: tuple[int, ...]
    made: int


@dataclass
class KnitRun:
    """A carrier's latest run of consecutive knit operations in one direction, each pulled
    through loops of yarns already taken out: a draw thread, if the carrier goes out right
    after it and it then holds every loop on the needles."""

    first: int  # loop ids first .. last
    last: int
    direction: str
    op_index: int  # index of its last operation


@dataclass(frozen=True)
class BumpYarnChange:
    """A purl (knit on the back bed) pulled through a loop knit on the front bed -- a bump --
    by carriers none of which made that loop: the yarn changes inside the bump."""

    line: int
    needle: str
    carriers: tuple[str, ...]
    below: tuple[str, ...]


@dataclass(frozen=True)
class UnclearedTuck:
    """A tuck on a back needle that held a loop (a tall bump's tuck), whose loops were moved or
    dropped at ``line`` before a knit on that needle pulled through it."""

    line: int
    needle: str
    tuck_line: int


@dataclass(frozen=True)
class CarrierEnd:
    """A carrier still in action when the program ends."""

    carrier: str
    in_line: int
    last_line: int


@dataclass
class SimCarrier:
    """One carrier as the simulator sees it (see :class:`MachineState`)."""

    name: str
    active: bool = False
    pending: tuple[str, ...] | None = None  # set named on in/inhook, until first use
    used: bool = False
    x: float | None = None  # location of last op
    dir: str | None = None
    last_loop: int | None = None
    in_line: int = 0
    last_line: int = 0


@dataclass
class MachineState:
    """The machine while a program runs: beds, racking, carriers, the hook, the loop graph, and
    the events and fabric observations recorded so far (described in
    :mod:`illuknit.check.simulate`)."""

    header_carriers: frozenset[str] | None
    max_racking: float
    max_loops: int
    bed_width: int | None
    keep_position: bool
    rack: float = 0.0
    beds: dict[str, dict[int, list[int]]] = field(
        default_factory=lambda: {b: {} for b in ("f", "b", "fs", "bs")}
    )
    carriers: dict[str, SimCarrier] = field(default_factory=dict)
    hook_set: tuple[str, ...] | None = None
    hook_slot: int | None = None  # None while waiting for the first hooked stitch
    parent: list[int] = field(default_factory=list)  # union-find over loop ids
    loop_lines: list[int] = field(default_factory=list)
    loop_carriers: list[str] = field(default_factory=list)
    events: list[Event] = field(default_factory=list)
    counts: dict[str, int] = field(default_factory=dict)
    floats: FloatTracker = field(default_factory=FloatTracker)
    face_floats: list[FaceFloat] = field(default_factory=list)
    wrong_sides: list[WrongSide] = field(default_factory=list)
    reported_unknown: set[str] = field(default_factory=set)
    min_index: int | None = None
    max_index: int | None = None
    width_reported: bool = False
    op_index: int = 0  # index of the operation being run
    held_ever: set[tuple[str, int]] = field(default_factory=set)  # needles that held a loop
    loop_tails: list[int] = field(default_factory=list)  # knits in a row on one needle, per loop
    drops: list[Drop] = field(default_factory=list)
    runs: dict[str, KnitRun] = field(default_factory=dict)
    draw_threads: list[int] = field(default_factory=list)  # first loop id of each
    front_loops: set[int] = field(default_factory=set)  # loops made on a front needle
    bump_tucks: dict[int, int] = field(default_factory=dict)  # uncleared tuck loop -> its line
    yarn_changes: list[BumpYarnChange] = field(default_factory=list)
    uncleared_tucks: list[UnclearedTuck] = field(default_factory=list)

    # -- bookkeeping ------------------------------------------------------------------------
    def event(self, line: int, code: str, message: str) -> None:
        n = self.counts.get(code, 0)
        self.counts[code] = n + 1
        if n < MAX_EVENTS_PER_CODE:
            self.events.append(Event(line, code, message))

    def find(self, a: int) -> int:
        parent = self.parent
        root = a
        while parent[root] != root:
            root = parent[root]
        while parent[a] != root:  # path compression
            parent[a], a = root, parent[a]
        return root

    def union(self, a: int, b: int) -> None:
        ra, rb = self.find(a), self.find(b)
        if ra != rb:
            # keep the older loop as root so labels follow creation order
            if ra < rb:
                self.parent[rb] = ra
            else:
                self.parent[ra] = rb

    def new_loop(self, line: int, carrier: str) -> int:
        lid = len(self.parent)
        self.parent.append(lid)
        self.loop_lines.append(line)
        self.loop_carriers.append(carrier)
        return lid

    # -- geometry -----------------------------------------------------------------------------
    def location(self, n: Needle) -> float:
        return float(n.index) if n.is_front else n.index + self.rack

    def slot(self, n: Needle) -> int:
        return needle_slot(n, self.rack)

    def held(self, n: Needle) -> list[int]:
        return self.beds[n.bed].get(n.index, [])

    def take(self, n: Needle) -> list[int]:
        return self.beds[n.bed].pop(n.index, [])

    def move_off(self, n: Needle, line: int) -> list[int]:
        """Take the loops of ``n`` to move or drop them: a bump tuck among them that no knit
        has cleared yet is recorded (:class:`UnclearedTuck`)."""
        loops = self.take(n)
        if self.bump_tucks:
            for lid in loops:
                tuck_line = self.bump_tucks.pop(lid, None)
                if tuck_line is not None:
                    self.uncleared_tucks.append(UnclearedTuck(line, str(n), tuck_line))
        return loops

    def drop(self, n: Needle, line: int) -> None:
        """Release the loops of ``n`` (a ``drop``, or a knit without yarn)."""
        loops = self.move_off(n, line)
        if loops:
            self.drops.append(Drop(line, str(n), tuple(loops), len(self.parent)))

    def put(self, n: Needle, loops: list[int], line: int) -> None:
        if not loops:
            return
        self.held_ever.add((n.bed, n.index))
        bed = self.beds[n.bed]
        cur = bed.get(n.index)
        if cur is None:
            bed[n.index] = cur = []
        cur.extend(loops)
        if len(cur) > self.max_loops:
            self.event(
                line,
                "too-many-loops",
                f"{n} holds {len(cur)} loops; the machine holds at most {self.max_loops}",
            )

    def note_needle(self, n: Needle, line: int) -> None:
        i = n.index
        if self.min_index is None or i < self.min_index:
            self.min_index = i
        if self.max_index is None or i > self.max_index:
            self.max_index = i
        w = self.bed_width
        if w is None or self.width_reported:
            return
        if self.keep_position:
            if not 1 <= i <= w:
                self.width_reported = True
                self.event(
                    line,
                    "too-wide",
                    f"{n} is outside the bed (Position: Keep needs needles 1..{w})",
                )
        elif self.max_index - self.min_index + 1 > w:
            self.width_reported = True
            self.event(
                line,
                "too-wide",
                f"the program spans needles {self.min_index}..{self.max_index}, "
                f"wider than the {w}-needle bed",
            )

    def carrier(self, name: str, line: int) -> SimCarrier:
        c = self.carriers.get(name)
        if c is None:
            c = self.carriers[name] = SimCarrier(name)
        hc = self.header_carriers
        if hc is not None and name not in hc and name not in self.reported_unknown:
            self.reported_unknown.add(name)
            self.event(
                line,
                "carrier-unknown",
                f"carrier {name} is not listed in the ;;Carriers: header",
            )
        return c
