"""Knitout -> Kniterate carriage passes: the first stage of the ``.kc`` writer.

The Kniterate runs one yarn carrier per carriage pass. Knitout operations, as the knitout
parser reads them (:func:`~illuknit.knitout.parse.parse_knitout`, the IR the checker reads too),
are taken in order and merged into the current pass while they fit (same racking, speed,
direction and carrier; a pass kind both can share; the new needle beyond the pass's furthest one
in its direction; stitch numbers that agree); otherwise a new pass starts. Before a new pass with
a carrier, the carrier is "kicked" (a yarn-less soft miss in the other direction) when it may be
parked on the wrong side; before any stitch or transfer, every other live carrier whose yarn is
attached across that needle is kicked out of the way. These rules, and the values written for
each pass (roller advance, stitch number, speed), are those of the CMU Kniterate backend
``knitout-to-kcode.js``, so that the resulting ``.kc`` is the same file (the pass types and the
merge rule are in :mod:`illuknit.formats.kc_ir`). Programs that backend would turn into a wrong
file (plated carriers, slider needles, racking it cannot align) raise
:class:`~illuknit.core.errors.KcodeError`.
"""

from __future__ import annotations

import math
import re

from illuknit.core.errors import KcodeError, KnitoutParseError
from illuknit.core.machine_ranges import machine_value_problem
from illuknit.formats.carriers import KNITERATE_CARRIERS, CarrierBook
from illuknit.formats.kc_ir import (
    CARRIERS,
    SOFT,
    KcHeaders,
    KcPass,
    KcPassKind,
    KcProgram,
    KcSlotOp,
    pass_kind,
)
from illuknit.knitout.parse import KnitoutProgram, Needle, Operation, parse_knitout
from illuknit.knitout.program import Direction

__all__ = ["read_kc_passes"]

_NUMBER = re.compile(r"^[+-]?\d*\.?\d+$")
_STITCH_NUMBER = re.compile(r"^[0-9A-Z]$")
_POSITIONS = ("Left", "Right", "Keep", "Center")


#: a pass's direction ("" for transfers and drops) as the carrier bookkeeping names it
_YARN = {"+": Direction.RIGHT, "-": Direction.LEFT, "": None}


def read_kc_passes(program: KnitoutProgram | str) -> KcProgram:
    """A knitout program's Kniterate carriage passes.

    Text is read by the knitout parser (:func:`~illuknit.knitout.parse.parse_knitout`) first;
    the program's operations are then grouped into passes as the backend groups them.

    Parameters
    ----------
    program : KnitoutProgram or str
        A knitout-2 program (or its text) for the Kniterate (``;;Carriers: 1 2 3 4 5 6``,
        ``in``/``out`` only).

    Returns
    -------
    KcProgram

    Raises
    ------
    KcodeError
        For knitout the Kniterate backend refuses, or would translate into a wrong file (a line
        that does not parse as knitout included).
    """
    # the line after the last, as the backend counts (the formatted text ends with a newline)
    end = len(program.split("\n")) if isinstance(program, str) else program.n_lines + 1
    if isinstance(program, str):
        try:
            program = parse_knitout(program)
        except KnitoutParseError as e:
            raise KcodeError(str(e).removeprefix(f"line {e.line}: "), line=e.line) from None
    reader = _PassReader()
    for operation in program.operations:
        reader.line = operation.line
        if operation.tabs:  # the backend splits tokens at spaces only
            raise reader.fail("tokens must be separated by spaces, not tabs")
        reader.apply(operation)
    if reader.carriers:
        left = " ".join(sorted(reader.carriers, key=int))
        raise KcodeError(f"carriers {left} are never taken out (`out`)", line=end)
    return KcProgram(
        headers=_read_headers(program),
        passes=tuple(reader.passes),
        carrier_spacing=reader.carrier_spacing,
        carrier_stopping_distance=reader.stopping_distance,
    )


def _in_range(name: str, value: object, what: str, line: int) -> None:
    """Refuse a machine value outside the Kniterate range of :mod:`illuknit.core.machine_ranges`
    (the backend takes any number, and the machine would run it)."""
    problem = machine_value_problem(name, value, backend="kniterate")
    if problem is not None:
        raise KcodeError(f"{what[:40]}: {problem}", line=line)


def _read_headers(program: KnitoutProgram) -> KcHeaders:
    carriers: list[str] | None = None
    position = "Center"
    width = 252
    for name, value, line in program.headers:
        if name == "Carriers":
            carriers = re.split(" +", value)
        elif name == "Gauge":
            if not (re.match(r"^\d+\.?\d*$", value) and float(value) > 0):
                raise KcodeError(f"`Gauge` must be a positive number, got {value!r}", line=line)
            _in_range("gauge", float(value), f";;Gauge: {value}", line)
        elif name == "Width":
            if not (re.match(r"^\d+$", value) and int(value) > 0):
                raise KcodeError(f"`Width` must be a positive integer, got {value!r}", line=line)
            width = int(value)
            _in_range("needles", width, f";;Width: {value}", line)
        elif name == "Position":
            if value not in _POSITIONS:
                raise KcodeError(
                    f"`Position` must be one of {', '.join(_POSITIONS)}, got {value!r}", line=line
                )
            position = value
    if carriers is None or tuple(carriers) != CARRIERS:
        line = len(program.headers) + 2  # the first line after the header
        raise KcodeError("the Kniterate needs the header ';;Carriers: 1 2 3 4 5 6'", line=line)
    return KcHeaders(position=position, width=width)


class _PassReader:
    """The backend's running state while knitout operations are read (racking, stitch number,
    carriers and where each is attached and parked); :meth:`apply` takes one operation."""

    def __init__(self) -> None:
        self.passes: list[KcPass] = []
        self.carriers = CarrierBook(KNITERATE_CARRIERS)
        self.racking = 0.0
        self.stitch = "5"
        self.xfer_stitch = "3"
        self.xfer_style = "four-pass"
        self.speed: int | str = 100
        self.roller = 100.0
        self.add_roller = 0.0
        self.pause_pending = False
        self.pause_message: str | None = None
        self.end_pending = False
        self.carrier_spacing = 2.0
        self.stopping_distance = 2.5
        self.line = 0

    # -- helpers -------------------------------------------------------------------------------
    def fail(
        self,
        message: str,
        *,
        needle: str | None = None,
        carrier: str | None = None,
        racking: float | None = None,
    ) -> KcodeError:
        return KcodeError(message, line=self.line, needle=needle, carrier=carrier, racking=racking)

    def slot(self, n: Needle) -> int:
        return n.index if n.is_front else n.index + math.floor(self.racking)

    def new_pass(
        self,
        kind: KcPassKind,
        carriers: tuple[str, ...],
        direction: str,
        slot: int,
        op: KcSlotOp,
        *,
        roller: float,
    ) -> KcPass:
        return KcPass(
            kind=kind,
            racking=self.racking,
            speed=self.speed,
            direction=direction,
            carriers=carriers,
            roller=roller,
            slots={slot: op},
            line=self.line,
        )

    def take_roller(self, value: float) -> float:
        """``value``, then undo a one-pass ``x-add-roller-advance``."""
        if self.add_roller != 0:
            self.roller -= self.add_roller
            self.add_roller = 0.0
        return value

    def needle(self, n: Needle) -> Needle:
        if n.is_slider:
            raise self.fail(f"slider needle {n} is not supported on the Kniterate", needle=str(n))
        return n

    def number(self, op: str, args: list[str]) -> float:
        if len(args) != 1 or not _NUMBER.match(args[0]):
            raise self.fail(f"`{op}` takes one number, got {' '.join(args)!r}")
        return float(args[0])

    # -- merging passes ------------------------------------------------------------------------
    def merge(self, p: KcPass) -> None:
        """Add ``p`` to the current pass or start a new one, kicking its carrier first if needed."""
        do_pause, self.pause_pending = self.pause_pending, False
        do_end, self.end_pending = self.end_pending, False
        if self.passes and not do_pause and not do_end and self.passes[-1].try_append(p):
            return
        (slot,) = p.slots
        book = self.carriers
        kicks = book.kicks_before(p.carriers, _YARN[p.direction], slot, math.floor(self.racking))
        if kicks:
            back = Direction.RIGHT if p.direction == "-" else Direction.LEFT
            for s in book.kick_order(kicks):
                kick_pass = self.new_pass(
                    SOFT,
                    tuple(kicks[s]),
                    back.value,
                    s,
                    KcSlotOp.SOFT_MISS,
                    roller=self.kick_roller,
                )
                kick_pass.pause, do_pause = do_pause, False  # the backend drops its message
                self.merge(kick_pass)
                book.park(kicks[s], s, back)
        if do_pause:
            p.pause, p.pause_message = True, self.pause_message
        if kicks:
            self.merge(p)
        else:
            self.passes.append(p)

    @property
    def kick_roller(self) -> float:
        roller = self.carriers.policy.kick_roller
        assert roller is not None  # the Kniterate's policy names it
        return roller

    def kick_others(self, n: Needle, carriers: tuple[str, ...]) -> None:
        """Move every other live carrier whose yarn is attached across ``n`` out of its way."""
        if len(self.carriers) <= len(carriers):
            return  # no other carrier is in
        book, rack_floor = self.carriers, math.floor(self.racking)
        for name, way, slot in book.in_the_way(self.slot(n), carriers, rack_floor):
            self.merge(
                self.new_pass(
                    SOFT, (name,), way.value, slot, KcSlotOp.SOFT_MISS, roller=self.kick_roller
                )
            )
            book.park((name,), slot, way)

    def mark_in(self, carriers: tuple[str, ...], p: KcPass) -> None:
        """Mark ``p`` as bringing ``carriers`` in from the grippers if this is their first use."""
        pending: tuple[str, tuple[str, ...]] | None = None
        for c in carriers:
            if c not in self.carriers:
                raise self.fail(f"carrier {c} is used but not brought in (`in {c}`)", carrier=c)
            if self.carriers[c].pending_in is not None:
                pending, self.carriers[c].pending_in = self.carriers[c].pending_in, None
        if pending is not None:
            if pending[1] != carriers:
                raise self.fail(
                    f"first use of carriers {' '.join(carriers)} does not match "
                    f"`in {' '.join(pending[1])}`"
                )
            p.gripper = "in"

    def set_last(self, carriers: tuple[str, ...], direction: str, n: Needle) -> None:
        self.carriers.set_last(carriers, _YARN[direction], n)

    # -- operations ----------------------------------------------------------------------------
    def apply(self, operation: Operation) -> None:
        """Apply one knitout operation (the backend reads a ``drop`` as a knit, an ``amiss``
        as a tuck and an ``xfer`` as a split, each without yarn)."""
        op, direction = operation.op, operation.direction or "+"
        if op in ("inhook", "releasehook", "outhook"):
            raise self.fail(f"`{op}`: the Kniterate has no yarn inserting hook (use `in`/`out`)")
        if op == "in":
            self.bring_in(operation.carriers)
        elif op == "out":
            self.take_out(operation.carriers)
        elif op in ("knit", "tuck", "miss", "drop", "amiss"):
            op = {"drop": "knit", "amiss": "tuck"}.get(op, op)
            self.stitch_op(op, direction, operation.needle, operation.carriers)
        elif op in ("split", "xfer"):
            source, target = operation.needles
            self.split_op(direction, source, target, operation.carriers)
        elif op == "rack":
            assert operation.value is not None
            self.set_racking(operation.value)
        else:
            self.setting(op, list(operation.args))

    def setting(self, op: str, args: list[str]) -> None:
        """``stitch``, ``pause`` or an extension (``x-...``)."""
        if op == "stitch":
            if len(args) != 2 or not all(re.match(r"^[+-]?\d+$", a) for a in args):
                raise self.fail("`stitch` takes two integers")
            # the backend ignores `stitch`; sizes come from x-stitch-number
        elif op in ("x-stitch-number", "x-xfer-stitch-number"):
            if len(args) != 1 or not _STITCH_NUMBER.match(args[0]):
                raise self.fail(f"`{op}` must be one of 0-9 or A-Z, got {' '.join(args)!r}")
            if op == "x-stitch-number":
                self.stitch = args[0]
            else:
                self.xfer_stitch = args[0]
        elif op == "x-speed-number":
            _in_range("speed_number", self.number(op, args), f"{op} {args[0]}", self.line)
            self.speed = args[0]
        elif op == "x-roller-advance":
            self.roller = self.number(op, args)
            _in_range("roller_advance", self.roller, f"{op} {args[0]}", self.line)
        elif op == "x-add-roller-advance":
            self.add_roller = self.number(op, args)
            _in_range("roller_advance", abs(self.add_roller), f"{op} {args[0]}", self.line)
            self.roller += self.add_roller
        elif op == "x-carrier-spacing":
            self.carrier_spacing = self.number(op, args)
            if (
                self.carrier_spacing * 2 != round(self.carrier_spacing * 2)
                or self.carrier_spacing < 1
            ):
                raise self.fail("`x-carrier-spacing` must be a multiple of 0.5 and at least 1")
        elif op == "x-carrier-stopping-distance":
            self.stopping_distance = math.floor(self.number(op, args)) + 0.5
        elif op == "x-xfer-style":
            if args not in (["four-pass"], ["two-pass"]):
                raise self.fail("`x-xfer-style` must be 'four-pass' or 'two-pass'")
            self.xfer_style = args[0]
        elif op == "x-end-pass":
            if args:
                raise self.fail("`x-end-pass` takes no arguments")
            self.end_pending = True
        elif op == "pause":
            self.pause_pending = True
            self.pause_message = " ".join(args) if args else None
        # (other extensions, x-presser-mode, ..., do nothing here)

    def set_racking(self, value: float) -> None:
        racking = value
        if racking - math.floor(racking) == 0.25:  # quarter pitch is the Kniterate's half pitch
            racking += 0.25
        if racking - math.floor(racking) not in (0.0, 0.5):
            raise self.fail(f"racking must be whole or whole + 0.5, got {value:g}", racking=racking)
        self.racking = racking

    def bring_in(self, carriers: tuple[str, ...]) -> None:
        for c in carriers:
            if c not in CARRIERS:
                raise self.fail(f"carrier {c!r} is not one of 1-6", carrier=c)
            if c in self.carriers:
                raise self.fail(f"carrier {c} is already in", carrier=c)
        self.carriers.bring_in("in", carriers)

    def take_out(self, carriers: tuple[str, ...]) -> None:
        for c in carriers:
            if c not in self.carriers or self.carriers[c].last is None:
                raise self.fail(f"carrier {c} cannot go out: it has not stitched", carrier=c)
        if len(carriers) != 1:
            raise self.fail("take carriers out one at a time (`out 1`, `out 2`)")
        state = self.carriers[carriers[0]]
        assert state.last is not None
        p = self.new_pass(
            SOFT,
            carriers,
            "-",
            self.slot(state.last[0]),
            KcSlotOp.SOFT_MISS,
            roller=self.take_roller(0),
        )
        p.gripper = "out"
        self.merge(p)
        del self.carriers[carriers[0]]

    def stitch_op(self, op: str, direction: str, n: Needle, carriers: tuple[str, ...]) -> None:
        """A knit, tuck or miss (without carriers: a drop or an amiss)."""
        n = self.needle(n)
        if not carriers:
            if op == "miss":
                raise self.fail("`miss` needs a carrier")
            direction = ""
        else:
            self.check_carriers(direction, carriers)
        if op != "miss":
            self.kick_others(n, carriers)
        slot = self.slot(n)
        if op == "miss":
            kind, slot_op = SOFT, KcSlotOp.SOFT_MISS
        else:
            stitch = "K" if op == "knit" else "T"
            kind = pass_kind(
                "stitch", stitch if n.is_front else None, None if n.is_front else stitch
            )
            slot_op = {
                ("K", True): KcSlotOp.KNIT_F,
                ("K", False): KcSlotOp.KNIT_B,
                ("T", True): KcSlotOp.TUCK_F,
                ("T", False): KcSlotOp.TUCK_B,
            }[stitch, n.is_front]
        p = self.new_pass(
            kind, carriers, direction, slot, slot_op, roller=self.take_roller(self.roller)
        )
        if op != "miss":
            p.sizes[slot] = {n.bed: self.stitch}
        self.mark_in(carriers, p)
        self.merge(p)
        self.set_last(carriers, direction, n)

    def check_carriers(self, direction: str, carriers: tuple[str, ...]) -> None:
        if direction not in ("+", "-"):
            raise self.fail(f"direction must be + or -, got {direction!r}")
        if len(carriers) > 1:
            raise self.fail(
                f"plating ({' '.join(carriers)} in one stitch) is not supported on the Kniterate",
                carrier=" ".join(carriers),
            )

    def split_op(self, direction: str, n: Needle, t: Needle, carriers: tuple[str, ...]) -> None:
        """A split from ``n`` to ``t`` (without carriers: a transfer)."""
        n, t = self.needle(n), self.needle(t)
        if n.is_front == t.is_front:
            raise self.fail(f"transfers go between beds, not {n.bed}{n.index} -> {t.bed}{t.index}")
        front, back = (n, t) if n.is_front else (t, n)
        if front.index != back.index + self.racking:
            raise self.fail(
                f"{n.bed}{n.index} and {t.bed}{t.index} are not aligned at racking "
                f"{self.racking:g}",
                racking=self.racking,
            )
        if carriers:
            self.check_carriers(direction, carriers)
            kind = pass_kind("split", split_to_back=n.is_front, split_rightward=direction == "+")
            op, size = KcSlotOp.SPLIT, self.stitch
        else:
            direction = ""
            kind = pass_kind("xfer", xfer_style=self.xfer_style)
            op = KcSlotOp.XFER_TO_BACK if n.is_front else KcSlotOp.XFER_TO_FRONT
            size = self.xfer_stitch
        self.kick_others(n, carriers)
        p = self.new_pass(
            kind, carriers, direction, self.slot(n), op, roller=self.take_roller(self.add_roller)
        )
        p.sizes = {self.slot(n): {n.bed: size}}
        p.sizes.setdefault(self.slot(t), {})[t.bed] = size
        self.mark_in(carriers, p)
        self.merge(p)
        self.carriers.follow_loop(n, t)  # the loop the yarn holds moved to t
        self.set_last(carriers, direction, n)
