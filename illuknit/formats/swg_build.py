"""Builder behind :func:`illuknit.formats.swg_passes.plan_swg`: knitout operations -> passes.

It walks the parsed program once, keeping the machine state the SWG backend keeps (racking,
stitch/speed numbers, presser mode, pending pause, the inserting hook, and for each live carrier
where its yarn is attached and where the carrier itself is parked) and grows a list of draft passes.
Drafts are mutable only inside this module; :func:`freeze_passes` turns them into frozen
:class:`~illuknit.formats.swg_ir.MachinePass` records.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

from illuknit.core.errors import MachineRuleError, UnsupportedKnitoutError
from illuknit.core.machine_ranges import machine_value_problem
from illuknit.formats.carriers import SWG_CARRIERS, CarrierBook
from illuknit.formats.swg_ir import (
    CarriageDirection,
    Gripper,
    HookAction,
    MachinePass,
    PassType,
    SlotOp,
    pass_kind,
)
from illuknit.knitout.parse import KnitoutProgram, Needle
from illuknit.knitout.program import Direction

__all__ = ["freeze_passes", "read_header"]

_CARRIERS = tuple(str(i) for i in range(1, 11))
#: the carriage's direction as the carrier bookkeeping names it, and back
_YARN = {
    CarriageDirection.RIGHT: Direction.RIGHT,
    CarriageDirection.LEFT: Direction.LEFT,
    CarriageDirection.NONE: None,
}
_CARRIAGE = {Direction.RIGHT: CarriageDirection.RIGHT, Direction.LEFT: CarriageDirection.LEFT}
_S = SlotOp
# (front op, back op) -> the slot op doing both at quarter pitch
_COMBINE: dict[tuple[SlotOp, SlotOp], SlotOp] = {
    (_S.MISS_FRONT, _S.MISS_BACK): _S.MISS_FRONT_MISS_BACK,
    (_S.MISS_FRONT, _S.TUCK_BACK): _S.MISS_FRONT_TUCK_BACK,
    (_S.MISS_FRONT, _S.KNIT_BACK): _S.MISS_FRONT_KNIT_BACK,
    (_S.TUCK_FRONT, _S.MISS_BACK): _S.TUCK_FRONT_MISS_BACK,
    (_S.TUCK_FRONT, _S.TUCK_BACK): _S.TUCK_FRONT_TUCK_BACK,
    (_S.TUCK_FRONT, _S.KNIT_BACK): _S.TUCK_FRONT_KNIT_BACK,
    (_S.KNIT_FRONT, _S.MISS_BACK): _S.KNIT_FRONT_MISS_BACK,
    (_S.KNIT_FRONT, _S.TUCK_BACK): _S.KNIT_FRONT_TUCK_BACK,
    (_S.KNIT_FRONT, _S.KNIT_BACK): _S.KNIT_FRONT_KNIT_BACK,
}


def _combine(first: SlotOp, then: SlotOp, quarter: bool) -> SlotOp | None:
    """The op doing ``first`` then ``then`` (moving right) in one slot, or None."""
    if first is _S.SOFT_MISS:
        return then
    if then is _S.SOFT_MISS:
        return first
    return _COMBINE.get((first, then)) if quarter else None


@dataclass(slots=True)
class _Draft:
    type: PassType
    racking: float
    stitch: int
    speed: int
    direction: CarriageDirection
    carriers: tuple[str, ...]
    slots: dict[int, SlotOp]
    hook: HookAction | None = None
    gripper: Gripper | None = None
    pause: bool = False
    presser: str | None = None
    lo: int = field(init=False)  # leftmost and rightmost slot so far
    hi: int = field(init=False)

    def has_front(self) -> bool:
        return any(op.stitches_front for op in self.slots.values())

    def has_back(self) -> bool:
        return any(op.stitches_back for op in self.slots.values())

    def try_append(self, new: _Draft) -> bool:
        """Merge ``new`` (one slot) into this pass when the machine can do both in one pass."""
        if new.pause:
            return False
        if (
            self.direction is not new.direction
            or self.carriers != new.carriers
            or self.type is not new.type
            or self.racking != new.racking
            or self.stitch != new.stitch
            or self.speed != new.speed
        ):
            return False
        if self.presser is not None and new.presser is not None and self.presser != new.presser:
            return False
        if self.presser == "on" and (
            (self.has_front() and new.has_back())
            or (self.has_back() and new.has_front())
            or new.hook is not None
        ):
            return False
        if (self.hook is not None or new.hook is not None) and not (
            (self.hook in (HookAction.IN, HookAction.RELEASE) and new.hook is None)
            or (self.hook is None and new.hook is HookAction.OUT)
        ):
            return False
        if (self.gripper is not None or new.gripper is not None) and not (
            (self.gripper is Gripper.IN and new.gripper is None)
            or (self.gripper is None and new.gripper is Gripper.OUT)
        ):
            return False
        ((s, op),) = new.slots.items()
        merged = self._slot_after(s, op)
        if merged is None:
            return False
        if new.presser is not None:
            self.presser = new.presser
        self.hook = self.hook or new.hook
        self.gripper = self.gripper or new.gripper
        self.slots[s] = merged
        self.lo, self.hi = min(self.lo, s), max(self.hi, s)
        return True

    def _slot_after(self, s: int, op: SlotOp) -> SlotOp | None:
        """What slot ``s`` holds once ``op`` joins the pass there, or None when it cannot."""
        quarter = self.racking != math.floor(self.racking)
        old = self.slots.get(s)
        if self.direction is CarriageDirection.NONE:  # undirected: any order, each slot once
            if old is None:
                return op
            return _combine(old, op, quarter) or _combine(op, old, quarter)
        if (
            self.direction is CarriageDirection.RIGHT
        ):  # only at or right of the rightmost slot so far
            if s < self.hi:
                return None
            return op if s > self.hi else _combine(self.slots[s], op, quarter)
        if s > self.lo:
            return None
        return op if s < self.lo else _combine(op, self.slots[s], quarter)

    def __post_init__(self) -> None:
        self.lo, self.hi = min(self.slots), max(self.slots)


@dataclass(slots=True)
class _Builder:
    passes: list[_Draft] = field(default_factory=list)
    carriers: CarrierBook = field(default_factory=lambda: CarrierBook(SWG_CARRIERS))
    hook: tuple[CarriageDirection, tuple[str, ...]] | None = None
    racking: float = 0.0
    rack_floor: int = 0
    stitch: int = 5
    speed: int = 0
    presser: str = "off"
    pause_pending: bool = False
    line: int = 0

    def error(self, message: str) -> MachineRuleError:
        return MachineRuleError(f"line {self.line}: {message}", line=self.line)

    def slot(self, n: Needle) -> int:
        """Raster slot of a needle: back needles shift with the racking."""
        return n.index if n.bed[0] == "f" else n.index + self.rack_floor

    def draft(
        self,
        type_: PassType,
        direction: CarriageDirection,
        carriers: tuple[str, ...],
        slot: int,
        op: SlotOp,
    ) -> _Draft:
        return _Draft(
            type=type_,
            racking=self.racking,
            stitch=self.stitch,
            speed=self.speed,
            direction=direction,
            carriers=carriers,
            slots={slot: op},
        )

    # -- passes -------------------------------------------------------------------------------
    def merge(self, new: _Draft) -> None:
        """Add a one-slot pass: join the open pass, or start one after any kickbacks it needs."""
        do_pause, self.pause_pending = self.pause_pending, False
        if self.passes and not do_pause and self.passes[-1].try_append(new):
            return
        (pass_slot,) = new.slots
        book = self.carriers
        kicks = book.kicks_before(new.carriers, _YARN[new.direction], pass_slot, self.rack_floor)
        if not kicks:
            new.pause = new.pause or do_pause
            self.passes.append(new)
            return
        back = new.direction.opposite
        for slot in book.kick_order(kicks):
            kick = self.draft(PassType.KNIT_TUCK, back, tuple(kicks[slot]), slot, SlotOp.SOFT_MISS)
            kick.pause, do_pause = do_pause, False
            self.merge(kick)
            book.park(kicks[slot], slot, _YARN[back])
        new.pause = new.pause or do_pause
        self.merge(new)

    def kick_others(self, n: Needle, cs: tuple[str, ...]) -> None:
        """Move every other live carrier attached on the far side of ``n`` out of its way."""
        for name, way, slot in self.carriers.in_the_way(self.slot(n), cs, self.rack_floor):
            carriage = _CARRIAGE[way]
            self.merge(self.draft(PassType.KNIT_TUCK, carriage, (name,), slot, SlotOp.SOFT_MISS))
            self.carriers.park((name,), slot, way)

    def take_in(self, cs: tuple[str, ...], d: _Draft) -> None:
        """First use of carriers announced by ``in``/``inhook``: grippers (and hook) bring them."""
        if not cs:
            return
        announced = None
        for c in cs:
            if c not in self.carriers:
                raise self.error(f"carrier {c} is used but not active (no in/inhook)")
            car = self.carriers[c]
            if car.pending_in is not None:
                announced, car.pending_in = car.pending_in, None
        if announced is None:
            return
        op, in_set = announced
        if in_set != cs:
            raise self.error(
                f"first use of carriers {' '.join(cs)} does not match '{op} {' '.join(in_set)}' "
                "(plated carriers come in together, in the same order)"
            )
        d.gripper = Gripper.IN
        if op == "inhook":
            if self.hook is not None:
                raise self.error(
                    f"cannot bring in {' '.join(cs)} with the hook; it holds {' '.join(self.hook[1])}"
                )
            d.hook = HookAction.IN
            self.hook = (d.direction, cs)

    def set_last(self, cs: tuple[str, ...], d: CarriageDirection, n: Needle) -> None:
        self.carriers.set_last(cs, _YARN[d], n)


def read_header(program: KnitoutProgram) -> tuple[int, str]:
    """(Width, Position) from the header, checking what the backend checks; last value wins."""
    values = {name: (value, line) for name, value, line in program.headers}
    if "Carriers" not in values:
        raise MachineRuleError("the ';;Carriers:' header is required")
    if values["Carriers"][0].split() != list(_CARRIERS):
        raise MachineRuleError(
            "the SWG machine needs ';;Carriers: 1 2 3 4 5 6 7 8 9 10', got "
            f"{values['Carriers'][0]!r}",
            line=values["Carriers"][1],
        )
    width, position = 540, "Center"
    if "Width" in values:
        w, line = values["Width"]
        if not (w.isascii() and w.isdigit()) or int(w) == 0:
            raise MachineRuleError(f"';;Width' must be a positive integer, got {w!r}", line=line)
        width = int(w)
        _in_range("needles", width, f"';;Width: {w}'", line)
    if "Position" in values:
        position, line = values["Position"]
        if position not in ("Left", "Right", "Keep", "Center"):
            raise MachineRuleError(
                f"';;Position' must be Left, Right, Keep or Center, got {position!r}", line=line
            )
    if "Gauge" in values:
        g, line = values["Gauge"]
        if re.fullmatch(r"\d+\.?\d*", g) is None or float(g) <= 0:
            raise MachineRuleError(f"';;Gauge' must be a positive number, got {g!r}", line=line)
        _in_range("gauge", float(g), f"';;Gauge: {g}'", line)
    return width, position


def _in_range(name: str, value: float, what: str, line: int) -> None:
    """Refuse a machine value outside the SWG range of :mod:`illuknit.core.machine_ranges`
    (the backend itself would take it, and the machine would run what it made of it)."""
    problem = machine_value_problem(name, value, backend="swg")
    if problem is not None:
        raise UnsupportedKnitoutError(f"{what[:40]}: {problem}", line=line)


def freeze_passes(drafts: list[_Draft]) -> list[MachinePass]:
    """Frozen passes, with where the carriage really travels (it starts on the right)."""
    out = []
    carriage = CarriageDirection.RIGHT  # the fixed start-up courses leave the carriage on the right
    for d in drafts:
        if abs(d.racking) > 8:
            raise MachineRuleError(f"racking {d.racking:g} is beyond the machine's 8 needles")
        travel = d.direction
        if travel is CarriageDirection.NONE and d.type in (PassType.KNIT_TUCK, PassType.A_MISS):
            travel = (
                CarriageDirection.RIGHT
                if carriage is CarriageDirection.LEFT
                else CarriageDirection.LEFT
            )
        # a pass moving left must start from the right: if the carriage stands left it travels empty
        move = (travel is CarriageDirection.LEFT and carriage is CarriageDirection.LEFT) or (
            travel is CarriageDirection.RIGHT and carriage is CarriageDirection.RIGHT
        )
        if move and d.hook is HookAction.RELEASE:
            raise MachineRuleError(
                "the hook would be released on a pass that starts with an empty carriage move, "
                "which KnitPaint refuses; knit a pass away from the hook's side first"
            )
        if travel is not CarriageDirection.NONE:
            carriage = travel
        slots = tuple(sorted(d.slots.items(), key=lambda item: item[0]))
        ops = [op for _, op in slots]
        out.append(
            MachinePass(
                kind=pass_kind(d.type, d.carriers, ops, d.hook, d.gripper),
                type=d.type,
                direction=d.direction,
                carriage=travel,
                carriage_move=move,
                carriers=d.carriers,
                racking=d.racking,
                stitch=d.stitch,
                speed=d.speed,
                slots=slots,
                hook=d.hook,
                gripper=d.gripper,
                pause=d.pause,
                presser=d.presser,
            )
        )
    return out
