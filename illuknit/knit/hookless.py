"""Lowering a schedule for a machine without a yarn-inserting hook (the Kniterate).

The schedulers plan for a Shima-style machine: a yarn comes in on the inserting hook
(``inhook``/``releasehook``), leaves with ``outhook``, and the two yarns of a plated stitch share
one pass. The Kniterate has none of that: yarns come in with ``in`` from the grippers at the left
end of the bed, the take-down rollers only grip fabric that spans the bed, and each pass runs one
carrier. So :func:`lower_hookless` rewrites a schedule's steps, and :func:`write_hookless_knitout`
puts a waste section in front of the piece, as the Kniterate backend's ``waste-section.js`` helper
does. The waste section is made of the schedulers' own steps (:class:`WasteSection`, built by
:func:`waste_section`, passes of role ``waste``) and written by the same step writer
(:func:`~illuknit.knit.knitout.step_operations`):

1. **bring every yarn in** (waste yarn, draw thread, then the pattern's yarns in order of first
   use): each tucks every k-th front needle of the waste width rightward and back leftward
   (k = number of yarns, so no two share a needle); a yarn whose first pattern pass runs leftward tucks once
   more rightward, ending on the right. Each pattern yarn then hangs from its last tuck at the
   edge its first pass starts from (:class:`YarnEntry`); the scheduler tucks its float from
   there to its first stitch like any other long float;
2. **waste section**: ``waste_passes`` passes of the waste yarn knitting alternate needles on
   alternate beds, then 12 passes of a tube (front rightward, back leftward), at roller advance
   400, stitch number 6, speed 300; the waste yarn goes out and the back bed is dropped;
3. **draw thread**: one rightward course on the front needles of the piece, then out; pulling it
   out later separates the piece from the waste;
4. **the piece**: its own cast-on and body, with ``inhook`` / ``releasehook`` removed (the yarn is
   already in), ``outhook`` -> ``out``, and every plated pass split in two passes: the second yarn
   tucks on the pass's needles, then the first knits through them (so the second is caught in
   the fabric as catching requires, with one carrier per pass).

The yarns the pattern may use are the machine's carriers minus the waste and draw-thread ones
(:attr:`~illuknit.core.machine.MachineSpec.pattern_carriers`): the scheduler is given only those,
so a plan that needs more refuses with :class:`~illuknit.core.errors.CarrierShortageError`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

from illuknit.core.errors import SchedulingError
from illuknit.core.machine import MachineSpec
from illuknit.knit.ir import ActionKind, Bed, Direction, Opcode, PassKind, Role
from illuknit.knit.knitout import Prelude, lower_to_knitout, step_operations
from illuknit.knit.schedule import CarrierAction, Op, Pass, Schedule, Step
from illuknit.knitout.program import KnitoutProgram, Operation, format_knitout

__all__ = [
    "WasteSection",
    "YarnEntry",
    "fabric_needles",
    "first_directions",
    "lower_hookless",
    "lower_hookless_knitout",
    "waste_knitout",
    "waste_prelude",
    "waste_section",
    "write_hookless_knitout",
    "yarn_entry",
]

WASTE_ROLLER_ADVANCE = 400
WASTE_STITCH_NUMBER = 6
WASTE_SPEED_NUMBER = 300
TUBE_PASSES = 12
MIN_WASTE_WIDTH = 20


def lower_hookless(schedule: Schedule, *, machine: MachineSpec) -> Schedule:
    """The schedule's steps with hook actions replaced and plated passes split (see above)."""
    steps: list[Step] = []
    for step in schedule.steps:
        if isinstance(step, CarrierAction):
            if step.action in ("out", "outhook"):
                steps.extend(CarrierAction(ActionKind.OUT, (c,)) for c in step.carriers)
            continue  # in/inhook: brought in by the waste section; releasehook: no hook
        if step.kind == "knit" and len(step.carriers) > 1:
            steps.extend(_unplate(step))
        else:
            steps.append(step)
    return replace(schedule, steps=tuple(steps), machine=machine)


def _unplate(p: Pass) -> list[Pass]:
    if any(o.op == "split" for o in p.ops):
        raise SchedulingError("a plated split cannot be knit with one carrier per pass (Kniterate)")
    tucks = tuple(Op(Opcode.TUCK if o.op == Opcode.KNIT else o.op, o.bed, o.needle) for o in p.ops)
    under = [replace(p, ops=tucks, carriers=(c,)) for c in p.carriers[1:]]
    return [*under, replace(p, carriers=p.carriers[:1])]


def first_directions(steps: Sequence[Step]) -> dict[str, str]:
    """Each carrier's direction in its first knit pass, in order of first use."""
    first: dict[str, str] = {}
    for p in steps:
        if isinstance(p, Pass) and p.kind == "knit" and p.direction is not None:
            for c in p.carriers:
                first.setdefault(c, p.direction)
    return first


def fabric_needles(steps: Sequence[Step]) -> tuple[int, int]:
    """The leftmost and rightmost needle the steps make or move loops on (parking misses beyond
    the fabric's edges hold no loops)."""
    needles = [o.needle for p in steps if isinstance(p, Pass) for o in p.ops if o.op != "miss"]
    return min(needles), max(needles)


@dataclass(frozen=True)
class YarnEntry:
    """Where each pattern yarn hangs when the piece starts, on a machine without an inserting
    hook: from its last bring-in tuck in the waste section (see the module docstring).

    Every yarn is brought in by tucks on every k-th front needle of the waste width (k = the
    number of yarns, the waste yarn and the draw thread first), rightward and back; a yarn whose
    first pass in the piece runs leftward tucks once more rightward. So its last loop before the
    piece is its last tuck at the edge its first pass starts from, and its carrier is parked just
    beyond that edge. The yarn then floats from that tuck to its first stitch in the piece: the
    schedulers plan that float like any other (:func:`~illuknit.knit.float_tucks.
    tuck_long_floats`), given :meth:`needles`.
    """

    machine: MachineSpec

    def waste_width(self, lo: int, hi: int) -> tuple[int, int]:
        """The waste section's needles for a fabric on needles ``lo`` .. ``hi``."""
        w_lo, w_hi = lo, max(hi, lo + MIN_WASTE_WIDTH - 1)
        if w_hi >= self.machine.needles:
            w_lo, w_hi = max(0, hi - MIN_WASTE_WIDTH + 1), hi
        return w_lo, w_hi

    def yarns(self, first: Mapping[str, str]) -> list[str]:
        """Carriers in the order they are brought in: waste yarn, draw thread, then the pattern's
        yarns in order of first use."""
        waste, draw = self.machine.waste_carrier, self.machine.draw_carrier
        if waste is None or draw is None:
            raise SchedulingError(
                f"the {self.machine.label} preset names no waste/draw-thread carriers"
            )
        return [waste, draw, *(c for c in first if c not in (waste, draw))]

    def needles(self, first: Mapping[str, str], lo: int, hi: int) -> dict[str, int]:
        """Needle of each pattern yarn's last bring-in tuck.

        Parameters
        ----------
        first : mapping of str to str
            Each pattern carrier's direction in its first pass in the piece, in order of first
            use (:func:`first_directions`).
        lo, hi : int
            The fabric's needles (:func:`fabric_needles`).
        """
        w_lo, w_hi = self.waste_width(lo, hi)
        yarns = self.yarns(first)
        k = len(yarns)
        out: dict[str, int] = {}
        for i, c in enumerate(yarns[2:], start=2):
            if first[c] == "-":  # last tucks rightward: the rightmost needle of its residue
                out[c] = w_hi - (w_hi - i) % k
            else:
                out[c] = w_lo + (i - w_lo) % k
        return out


def yarn_entry(machine: MachineSpec) -> YarnEntry:
    """The :class:`YarnEntry` of ``machine`` (which must have no inserting hook)."""
    if machine.inserting_hook:
        raise SchedulingError(f"the {machine.label} brings its yarns in on the inserting hook")
    return YarnEntry(machine)


@dataclass(frozen=True)
class WasteSection:
    """What a machine without an inserting hook knits before the piece, as schedule steps (the
    IR the schedulers emit; see the module docstring for the recipe).

    Attributes
    ----------
    yarn_in : tuple of Step
        Each yarn's ``in`` and its bring-in tuck passes (waste yarn, draw thread, then the
        pattern's yarns in order of first use).
    waste : tuple of Step
        The waste yarn's passes on alternate needles and beds, the tube, its ``out``, then the
        drops: the whole back bed, and the front needles outside the piece.
    draw_thread : tuple of Step
        One front course on the piece's needles, then ``out``.
    """

    yarn_in: tuple[Step, ...]
    waste: tuple[Step, ...]
    draw_thread: tuple[Step, ...]

    @property
    def steps(self) -> tuple[Step, ...]:
        """Every step, in the order they are knit."""
        return self.yarn_in + self.waste + self.draw_thread


def waste_section(
    schedule: Schedule, *, machine: MachineSpec, waste_passes: int = 70
) -> WasteSection:
    """The yarn-in tucks, waste section and draw thread before ``schedule``'s piece."""
    entry = yarn_entry(machine)
    lo, hi = fabric_needles(schedule.steps)
    w_lo, w_hi = entry.waste_width(lo, hi)
    first = first_directions(schedule.steps)
    yarns = entry.yarns(first)
    waste, draw = yarns[:2]
    yarn_in: list[Step] = []
    for i, c in enumerate(yarns):
        yarn_in.append(CarrierAction(ActionKind.IN, (c,)))
        ends_right = first.get(c) == "-"
        for direction in ("+", "-", "+") if ends_right else ("+", "-"):
            yarn_in.append(_tuck_pass(c, i, len(yarns), w_lo, w_hi, direction))
    steps: list[Step] = [
        *_waste_passes(waste, w_lo, w_hi, waste_passes),
        CarrierAction(ActionKind.OUT, (waste,)),
    ]
    steps.append(_drops([(Bed.BACK, n) for n in range(w_lo, w_hi + 1)]))
    outside = [(Bed.FRONT, n) for n in range(w_lo, w_hi + 1) if not lo <= n <= hi]
    if outside:
        steps.append(_drops(outside))
    draw_thread: tuple[Step, ...] = (
        _knit_pass(draw, "+", [(Bed.FRONT, n) for n in range(lo, hi + 1)]),
        CarrierAction(ActionKind.OUT, (draw,)),
    )
    return WasteSection(tuple(yarn_in), tuple(steps), draw_thread)


def _waste_passes(waste: str, lo: int, hi: int, passes: int) -> list[Pass]:
    """``passes`` passes of alternate needles on alternate beds, then the tube (front
    rightward, back leftward)."""
    out = []
    for k in range(passes):
        if k % 2 == 0:
            out.append(_knit_pass(waste, "+", [(_bed(n % 2 == 0), n) for n in range(lo, hi + 1)]))
        else:
            out.append(
                _knit_pass(waste, "-", [(_bed(n % 2 == 1), n) for n in range(hi, lo - 1, -1)])
            )
    for k in range(TUBE_PASSES):
        if k % 2 == 0:
            out.append(_knit_pass(waste, "+", [(Bed.FRONT, n) for n in range(lo, hi + 1)]))
        else:
            out.append(_knit_pass(waste, "-", [(Bed.BACK, n) for n in range(hi, lo - 1, -1)]))
    return out


def _bed(front: bool) -> Bed:
    return Bed.FRONT if front else Bed.BACK


def _knit_pass(
    carrier: str, direction: Direction, needles: Sequence[tuple[Bed, int]], op: Opcode = Opcode.KNIT
) -> Pass:
    """A waste-section pass of ``carrier`` making ``op`` on ``needles`` (in pass order)."""
    ops = tuple(Op(op, bed, n) for bed, n in needles)
    return Pass(
        PassKind.KNIT, ops, direction, (carrier,), 0.0, Role.WASTE, None, WASTE_STITCH_NUMBER
    )


def _drops(needles: Sequence[tuple[Bed, int]]) -> Pass:
    ops = tuple(Op(Opcode.DROP, bed, n) for bed, n in needles)
    return Pass(PassKind.DROP, ops, None, (), 0.0, Role.WASTE)


def _tuck_pass(c: str, i: int, k: int, lo: int, hi: int, direction: Direction) -> Pass:
    """Tucks of yarn ``c`` on every k-th front needle (offset i) across lo..hi.

    (``waste-section.js`` alternates beds; front-only tucks leave no back-bed loop for the next
    yarn to float across.)
    """
    needles = list(range(lo, hi + 1)) if direction == "+" else list(range(hi, lo - 1, -1))
    ops = [Op(Opcode.TUCK, Bed.FRONT, n) for n in needles if n % k == i]
    # end at the far edge, so that the next pass starts behind the carriage
    if not ops or needles[-1] % k != i:
        ops.append(Op(Opcode.MISS, Bed.FRONT, needles[-1]))
    return Pass(
        PassKind.KNIT, tuple(ops), direction, (c,), 0.0, Role.WASTE, None, WASTE_STITCH_NUMBER
    )


def waste_prelude(section: WasteSection) -> list[str | Operation]:
    """What ``section`` puts between the header and the piece: its settings (roller advance,
    stitch number, speed), then each part under a comment naming it."""
    items: list[str | Operation] = [
        Operation(1, "x-roller-advance", args=(f"{WASTE_ROLLER_ADVANCE}",)),
        Operation(1, "x-stitch-number", args=(f"{WASTE_STITCH_NUMBER}",)),
        Operation(1, "x-speed-number", args=(f"{WASTE_SPEED_NUMBER}",)),
    ]
    parts = (
        ("bring the yarns in", section.yarn_in),
        ("waste yarn", section.waste),
        ("draw thread", section.draw_thread),
    )
    for name, steps in parts:
        items.append(f"; {name}")
        items += [op for step in steps for op in step_operations(step)]
    items.append("; the piece")
    return items


def waste_knitout(section: WasteSection) -> list[str]:
    """Knitout lines of ``section`` (:func:`waste_prelude` as text)."""
    return [item if isinstance(item, str) else str(item) for item in waste_prelude(section)]


def lower_hookless_knitout(
    schedule: Schedule,
    *,
    machine: MachineSpec,
    waste_passes: int = 70,
    prelude: Prelude = (),
) -> tuple[KnitoutProgram, Schedule]:
    """The program for a machine without an inserting hook: header, ``prelude``, waste section,
    then the piece; and the schedule it runs (:func:`lower_hookless`), whose step indices the
    piece's operations carry (the waste section's carry none)."""
    lowered = lower_hookless(schedule, machine=machine)
    waste = waste_prelude(waste_section(schedule, machine=machine, waste_passes=waste_passes))
    program = lower_to_knitout(lowered, machine=machine, prelude=[*prelude, *waste])
    return program, lowered


def write_hookless_knitout(
    schedule: Schedule, *, machine: MachineSpec, waste_passes: int = 70
) -> str:
    """Knitout for a machine without an inserting hook: header, waste section, then the piece."""
    program, _ = lower_hookless_knitout(schedule, machine=machine, waste_passes=waste_passes)
    return format_knitout(program)
