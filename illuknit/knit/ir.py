"""The lowest IR: needle operations, carriage passes and carrier actions, typed.

Every scheduler emits these and every later stage (the knitout writer, the machine pass model,
the time model) reads them. The vocabularies are enums (:class:`PassKind`, :class:`Opcode`,
:class:`Bed`, :class:`Role`, :class:`ActionKind`; :class:`Opcode` and :class:`Bed` are the knitout
program's own, :class:`illuknit.knitout.program.Opcode` and :class:`illuknit.knitout.program.Bed`,
an operation holding one of :data:`NEEDLE_OPS`); they are :class:`~enum.StrEnum` members whose
values are the knitout tokens, so ``str(Opcode.KNIT) == "knit"`` and a pass still compares equal
to the plain string it was written with. Constructors accept either form and store the enum.
(``OpKind``, the schedule's own copy of the needle opcodes, is a deprecated name of
:class:`Opcode`.)

The course -> pattern row mapping lives here too (:func:`course_row`), because the knitout writer,
the schedulers' error messages and the checker's trace-back all need the same formula.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from enum import StrEnum
from itertools import pairwise
from typing import Any, Literal

import numpy as np

from illuknit.core.errors import MachineRuleError, SchedulingError
from illuknit.knitout.program import Bed, Opcode

__all__ = [
    "NEEDLE_OPS",
    "ActionKind",
    "Bed",
    "CarrierAction",
    "Direction",
    "Op",
    "Opcode",
    "Pass",
    "PassKind",
    "Role",
    "Step",
    "course_row",
    "flip",
]

Direction = Literal["+", "-"]


class PassKind(StrEnum):
    """What a carriage pass does: lay yarn (``knit``), move loops (``xfer``), release them."""

    KNIT = "knit"
    XFER = "xfer"
    DROP = "drop"


#: The needle operations an :class:`Op` holds; the first four use the pass's carriers and direction.
NEEDLE_OPS = (Opcode.KNIT, Opcode.TUCK, Opcode.MISS, Opcode.SPLIT, Opcode.XFER, Opcode.DROP)

#: Operations a knit pass may hold.
YARN_OPS = frozenset(NEEDLE_OPS[:4])


def __getattr__(name: str) -> object:
    if name == "OpKind":  # deprecated: the schedule's copy of the knitout program's opcodes
        warnings.warn(
            "illuknit.knit.ir.OpKind is deprecated; use illuknit.knitout.program.Opcode "
            "(also importable from illuknit.knit.ir)",
            DeprecationWarning,
            stacklevel=2,
        )
        return Opcode
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


class Role(StrEnum):
    """What a pass is for (reporting and knitout comments)."""

    CAST_ON = "cast-on"
    PARK = "park"
    BODY = "body"
    TRANSFER = "transfer"
    BIND_OFF = "bind-off"
    TAIL = "tail"
    FLOAT_AVOIDANCE = "float-avoidance"
    ANCHOR = "anchor"
    WASTE = "waste"


class ActionKind(StrEnum):
    """Carrier actions: bring carriers in (``in``/``inhook``), release the hook, take them out."""

    IN = "in"
    INHOOK = "inhook"
    RELEASEHOOK = "releasehook"
    OUT = "out"
    OUTHOOK = "outhook"


def flip(d: Direction) -> Direction:
    """The opposite carriage direction."""
    return "-" if d == "+" else "+"


def course_row(course: int, rows: int) -> int:
    """Pattern row of knitting course ``course`` for a pattern of ``rows`` unit rows.

    The machine knits from the bottom edge up and every unit is two courses, so course ``c`` is
    row ``rows - 1 - c // 2`` (row 0 is the top of the picture).

    >>> course_row(0, 10), course_row(3, 10)
    (9, 8)
    """
    return rows - 1 - course // 2


def _enum(cls: type[StrEnum], value: Any, what: str) -> StrEnum:
    # Millions of operations are built per piece: look members up directly (enum's __call__ is
    # slow); members and their plain-string values both hit the map.
    member = cls._value2member_map_.get(value)
    if member is not None:
        return member  # type: ignore[return-value]
    try:
        return cls(value)
    except ValueError:
        allowed = tuple(m.value for m in cls)
        raise SchedulingError(f"{what} must be one of {allowed}, got {value!r}") from None


def _needle_op(value: Any) -> Opcode:
    """The needle opcode ``value`` names (a pass checks the ones it is given as members)."""
    op = Opcode._value2member_map_.get(value)
    if op not in NEEDLE_OPS:
        allowed = tuple(o.value for o in NEEDLE_OPS)
        raise SchedulingError(f"operation must be one of {allowed}, got {value!r}")
    return op


@dataclass(frozen=True, slots=True)
class Op:
    """One needle operation.

    ``op`` is one of :data:`NEEDLE_OPS` (an :class:`Opcode`); ``knit``/``tuck``/``miss``/``split`` use the pass's carriers
    and direction. ``bed`` is a :class:`Bed`; ``to_bed``/``to_needle`` name the receiving needle
    of ``xfer`` and ``split``.
    """

    op: Opcode
    bed: Bed
    needle: int
    to_bed: Bed | None = None
    to_needle: int | None = None

    def __post_init__(self) -> None:
        # (the schedulers pass members already: only strings are looked up)
        if type(self.op) is not Opcode:
            object.__setattr__(self, "op", _needle_op(self.op))
        if type(self.bed) is not Bed:
            object.__setattr__(self, "bed", _enum(Bed, self.bed, "bed"))
        if self.to_bed is not None and type(self.to_bed) is not Bed:
            object.__setattr__(self, "to_bed", _enum(Bed, self.to_bed, "target bed"))


@dataclass(frozen=True)
class Pass:
    """One carriage pass.

    Parameters
    ----------
    kind : PassKind
        ``knit`` passes carry yarn (knit/tuck/miss/split ops); ``xfer`` passes move loops;
        ``drop`` passes release loops.
    ops : tuple of Op
        In execution order (for knit passes: in ``direction`` order).
    direction : {"+", "-"} or None
        Carriage direction of a knit pass; None for xfer/drop passes.
    carriers : tuple of str
        Carriers of a knit pass, primary first (more than one = plating).
    racking : float
        An integer or an integer + 0.25.
    role : Role
        What the pass is for.
    course : int or None
        Stitch course the pass belongs to (None for cast-on/bind-off).
    stitch_number : int or None
        ``x-stitch-number`` for the pass (None: machine default).
    """

    kind: PassKind
    ops: tuple[Op, ...]
    direction: Direction | None = None
    carriers: tuple[str, ...] = ()
    racking: float = 0.0
    role: Role = Role.BODY
    course: int | None = None
    stitch_number: int | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "kind", _enum(PassKind, self.kind, "pass `kind`"))
        object.__setattr__(self, "role", _enum(Role, self.role, "pass `role`"))
        if not self.ops:
            raise SchedulingError("a pass needs at least one operation")
        if self.kind is PassKind.KNIT:
            if self.direction not in ("+", "-"):
                raise SchedulingError(
                    f"knit pass needs direction '+' or '-', got {self.direction!r}"
                )
            if not self.carriers:
                raise SchedulingError("knit pass needs at least one carrier")
            if any(o.op not in YARN_OPS for o in self.ops):
                raise SchedulingError(f"knit pass ops must be {sorted(str(k) for k in YARN_OPS)}")
            # Ops must advance strictly in the pass direction (front and back of one needle are
            # the same slot at racking 0, so they cannot share a pass then).
            rack = int(np.floor(self.racking))
            slots = [o.needle + (rack if o.bed is Bed.BACK else 0) for o in self.ops]
            sign = 1 if self.direction == "+" else -1
            if any(sign * (b - a) <= 0 for a, b in pairwise(slots)):
                raise SchedulingError(
                    f"knit pass ops must advance strictly in direction {self.direction}"
                )
        else:
            if self.direction is not None or self.carriers:
                raise SchedulingError(f"{self.kind} pass takes no direction and no carriers")
            if any(o.op != self.kind for o in self.ops):
                raise SchedulingError(f"{self.kind} pass may only hold {self.kind} ops")
        r = float(self.racking)
        if not (r == int(r) or r - np.floor(r) == 0.25):
            raise MachineRuleError(
                f"racking must be an integer or integer + 0.25, got {r}", racking=r
            )

    @property
    def needle_span(self) -> tuple[int, int]:
        """(leftmost, rightmost) needle touched, targets included."""
        ns = [o.needle for o in self.ops] + [
            o.to_needle for o in self.ops if o.to_needle is not None
        ]
        return (min(ns), max(ns))

    @property
    def is_move(self) -> bool:
        """True for a knit pass of misses only: it moves its carriers and makes no loop."""
        return self.kind is PassKind.KNIT and all(o.op is Opcode.MISS for o in self.ops)


@dataclass(frozen=True)
class CarrierAction:
    """Bring carriers in or out: ``in``, ``inhook``, ``releasehook``, ``out`` or ``outhook``."""

    action: ActionKind
    carriers: tuple[str, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "action", _enum(ActionKind, self.action, "carrier action"))
        if not self.carriers:
            raise SchedulingError("carrier action needs at least one carrier")


Step = Pass | CarrierAction
