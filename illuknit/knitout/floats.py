"""Floats of a knitout program: the one measure the checker and ``illuknit knit`` both report.

A *float* is the yarn of one carrier between two consecutive loops it makes (knit, tuck or
split with that carrier). Its length is the number of needle slots strictly between the two
loops, as the machine sees them: a front needle ``f n`` sits at slot ``n``, a back needle ``b k``
at slot ``k + floor(R)`` at racking ``R``. A carrier brought in (``in``/``inhook``) or taken out
(``out``/``outhook``) starts afresh: its next loop has no float before it. ``miss`` moves a
carrier without a loop, so a carrier parked far away and brought back does not make a float.

:class:`FloatTracker` is that rule. The checker's simulator
(:func:`~illuknit.check.simulate.simulate_program`) feeds it as it runs a program;
:func:`program_floats` feeds it from the operations alone (no loops, no beds), which is what
:func:`~illuknit.knitting.knit_pattern` uses for the ``long_floats`` / ``longest_float`` it reports
(and refuses). It lives with the program, below the scheduler, so that every floor that makes
or reads a program measures floats one way; :func:`is_long_float` is the one rule over it.
Both therefore give the same floats, by construction (and a test holds every generated program
to it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from illuknit.knitout.program import KnitoutProgram, Needle, Opcode

__all__ = [
    "Float",
    "FloatTracker",
    "is_long_float",
    "long_floats",
    "needle_slot",
    "program_floats",
]

#: Operations that leave a loop of their carriers' yarn on a needle.
LOOP_OPS = frozenset({Opcode.KNIT, Opcode.TUCK, Opcode.SPLIT})
#: Operations after which a carrier's next loop starts afresh.
_CUTS = frozenset({Opcode.IN, Opcode.INHOOK, Opcode.OUT, Opcode.OUTHOOK})


@dataclass(frozen=True)
class Float:
    """Yarn of ``carrier`` crossing needle slots between two consecutive loops.

    ``line`` is the line of the operation that made the far loop.
    """

    line: int
    carrier: str
    from_slot: int
    to_slot: int

    @property
    def length(self) -> int:
        """Number of needle slots strictly between the two loops."""
        return abs(self.to_slot - self.from_slot) - 1


def is_long_float(length: int, limit: int) -> bool:
    """The one rule for what a long float is: longer than the float limit, both in needles
    skipped (a float of ``limit`` needles skipped is allowed, one longer is not). The
    checker's ``long-float`` warning, the refusal of :func:`~illuknit.knitting.knit_pattern`
    and the schedulers' tucks all read it.

    >>> is_long_float(20, 20), is_long_float(21, 20)
    (False, True)
    """
    return length > limit


def needle_slot(needle: Needle, racking: float) -> int:
    """The slot of ``needle`` at ``racking``: front needles at their index, back needles at
    ``index + floor(racking)``."""
    return needle.index if needle.is_front else needle.index + math.floor(racking)


@dataclass
class FloatTracker:
    """Each carrier's last loop slot, and every float of length >= 1 seen so far."""

    last: dict[str, int] = field(default_factory=dict)
    floats: list[Float] = field(default_factory=list)

    def loop(self, line: int, carrier: str, slot: int) -> Float | None:
        """``carrier`` made a loop at ``slot``: the float before it (None when shorter than one
        slot, or when the carrier had no loop since it came in)."""
        prev = self.last.get(carrier)
        self.last[carrier] = slot
        if prev is None or abs(slot - prev) <= 1:
            return None
        f = Float(line, carrier, prev, slot)
        self.floats.append(f)
        return f

    def cut(self, carrier: str) -> None:
        """``carrier`` came in or went out: its next loop starts afresh."""
        self.last.pop(carrier, None)


def program_floats(program: KnitoutProgram) -> tuple[Float, ...]:
    """Every float of length >= 1 in ``program``, in line order (see the module docstring)."""
    tracker = FloatTracker()
    shift = 0  # back needles' slot shift at the racking in force (see needle_slot)
    loop, cut = tracker.loop, tracker.cut
    for op in program.operations:
        name = op.op
        if name in LOOP_OPS and op.carriers:
            n = op.needles[0]
            slot = n.index if n.bed[0] == "f" else n.index + shift
            for c in op.carriers:
                loop(op.line, c, slot)
        elif name == "rack" and op.value is not None:
            shift = math.floor(op.value)
        elif name in _CUTS:
            for c in op.carriers:
                cut(c)
    return tuple(tracker.floats)


def long_floats(program: KnitoutProgram, limit: int) -> tuple[Float, ...]:
    """The floats of ``program`` longer than ``limit`` needle slots."""
    return tuple(f for f in program_floats(program) if is_long_float(f.length, limit))
