"""The Kniterate's carriage passes as data: what :func:`~illuknit.formats.kc_passes.read_kc_passes`
groups knitout operations into and :func:`~illuknit.formats.kc.write_kcode` writes.

A :class:`KcPass` holds one :class:`KcSlotOp` per needle slot and has one :class:`KcPassKind`
(the k-code pass type: stitches, transfer, split or soft miss); :meth:`KcPass.try_append` is the
backend's rule for which operations share a pass. (The SWG machine's passes, a different
vocabulary, are in :mod:`illuknit.formats.swg_ir`.)
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from enum import Enum

__all__ = [
    "CARRIERS",
    "SOFT",
    "KcHeaders",
    "KcPass",
    "KcPassKind",
    "KcProgram",
    "KcSlotOp",
    "combine_kinds",
    "combine_ops",
    "pass_kind",
]

#: The Kniterate's carriers.
CARRIERS = ("1", "2", "3", "4", "5", "6")


class KcSlotOp(Enum):
    """What one needle slot (a front needle and the back needle facing it) does in a pass."""

    SOFT_MISS = "soft miss"
    KNIT_F = "knit front"
    TUCK_F = "tuck front"
    KNIT_B = "knit back"
    TUCK_B = "tuck back"
    KNIT_F_KNIT_B = "knit front, knit back"
    KNIT_F_TUCK_B = "knit front, tuck back"
    TUCK_F_KNIT_B = "tuck front, knit back"
    TUCK_F_TUCK_B = "tuck front, tuck back"
    XFER_TO_BACK = "transfer to back"
    XFER_TO_FRONT = "transfer to front"
    SPLIT = "split"

    @property
    def front(self) -> bool:
        """Whether the slot's front needle acts."""
        return _FRONT_OPS[self]

    @property
    def back(self) -> bool:
        """Whether the slot's back needle acts."""
        return _BACK_OPS[self]


_BOTH = {
    KcSlotOp.KNIT_F_KNIT_B,
    KcSlotOp.KNIT_F_TUCK_B,
    KcSlotOp.TUCK_F_KNIT_B,
    KcSlotOp.TUCK_F_TUCK_B,
    KcSlotOp.SPLIT,
}
_FRONT_OPS = {
    op: op in {KcSlotOp.KNIT_F, KcSlotOp.TUCK_F, KcSlotOp.XFER_TO_BACK} | _BOTH for op in KcSlotOp
}
_BACK_OPS = {
    op: op in {KcSlotOp.KNIT_B, KcSlotOp.TUCK_B, KcSlotOp.XFER_TO_FRONT} | _BOTH for op in KcSlotOp
}

# A front stitch followed (in pass order) by a back stitch in one slot, at half-pitch racking.
_COMBINED = {
    (KcSlotOp.KNIT_F, KcSlotOp.KNIT_B): KcSlotOp.KNIT_F_KNIT_B,
    (KcSlotOp.KNIT_F, KcSlotOp.TUCK_B): KcSlotOp.KNIT_F_TUCK_B,
    (KcSlotOp.TUCK_F, KcSlotOp.KNIT_B): KcSlotOp.TUCK_F_KNIT_B,
    (KcSlotOp.TUCK_F, KcSlotOp.TUCK_B): KcSlotOp.TUCK_F_TUCK_B,
}


def combine_ops(first: KcSlotOp, then: KcSlotOp, *, half_pitch: bool) -> KcSlotOp | None:
    """The slot operation doing ``first`` then ``then``, or None when one slot cannot hold both."""
    if first is KcSlotOp.SOFT_MISS:
        return then
    if then is KcSlotOp.SOFT_MISS:
        return first
    return _COMBINED.get((first, then)) if half_pitch else None


@dataclass(frozen=True, eq=False)
class KcPassKind:
    """The kind of a pass: a soft miss, stitches (``front``/``back`` = ``"K"``, ``"T"`` or None),
    a transfer (``xfer_style``) or a split (``split_to_back``, ``split_rightward``).

    Kinds are interned (made by :func:`pass_kind`), so equal kinds are the same object.
    """

    family: str  # "soft", "stitch", "xfer", "split"
    front: str | None = None
    back: str | None = None
    xfer_style: str = ""
    split_to_back: bool = False
    split_rightward: bool = False

    @property
    def kcode(self) -> str:
        """The k-code pass type (``Kn-Kn``, ``Tu-Kn``, ``Tr-Rl``, ...)."""
        if self.family == "split":
            move = "Rr" if self.split_rightward else "Rl"
            return f"Tr-{move}" if self.split_to_back else f"{move}-Tr"
        if self.family == "soft":
            return "Tu-Tu"
        front = self.front or self.back
        back = self.back or self.front
        return f"{_STITCH_WORD[front or 'T']}-{_STITCH_WORD[back or 'T']}"


_STITCH_WORD = {"K": "Kn", "T": "Tu"}


@functools.cache
def pass_kind(
    family: str,
    front: str | None = None,
    back: str | None = None,
    *,
    xfer_style: str = "",
    split_to_back: bool = False,
    split_rightward: bool = False,
) -> KcPassKind:
    """The one :class:`KcPassKind` with these fields."""
    return KcPassKind(family, front, back, xfer_style, split_to_back, split_rightward)


SOFT = pass_kind("soft")


@functools.cache
def combine_kinds(a: KcPassKind, b: KcPassKind) -> KcPassKind | None:
    """The kind of a pass holding the operations of passes of kinds ``a`` and ``b``, if any."""
    if a is b:
        return a
    if a is SOFT or b is SOFT:
        other = b if a is SOFT else a
        return None if other.family == "xfer" else other
    if a.family == "stitch" and b.family == "stitch":
        if (a.front and b.front and a.front != b.front) or (a.back and b.back and a.back != b.back):
            return None
        return pass_kind("stitch", a.front or b.front, a.back or b.back)
    # a split may join front-only knitting on its source bed (and only that)
    split, stitch = (a, b) if a.family == "split" else (b, a)
    if split.family != "split" or stitch.family != "stitch":
        return None
    source_knit = (("K", None) if split.split_to_back else (None, "K")) == (
        stitch.front,
        stitch.back,
    )
    return split if source_knit else None


@dataclass
class KcPass:
    """One carriage pass being built (mutable while operations merge into it)."""

    kind: KcPassKind
    racking: float
    speed: int | str
    direction: str  # "+", "-" or "" (transfers and drops)
    carriers: tuple[str, ...]
    roller: float
    slots: dict[int, KcSlotOp]
    sizes: dict[int, dict[str, str]] = field(default_factory=dict)
    gripper: str | None = None  # "in" or "out"
    pause: bool = False
    pause_message: str | None = None
    line: int = 0

    @property
    def lo(self) -> int:
        """Leftmost slot used."""
        return self._lo

    @property
    def hi(self) -> int:
        """Rightmost slot used."""
        return self._hi

    def __post_init__(self) -> None:
        self._lo = min(self.slots)
        self._hi = max(self.slots)

    def try_append(self, other: KcPass) -> bool:
        """Merge ``other`` (a one-slot pass) into this pass if the machine can do both at once."""
        if other.pause:
            return False
        if (self.racking, self.direction, self.carriers) != (
            other.racking,
            other.direction,
            other.carriers,
        ) or not _same_speed(self.speed, other.speed):
            return False
        kind = combine_kinds(self.kind, other.kind)
        if kind is None:
            return False
        if not _grippers_fit(self.gripper, other.gripper):
            return False
        half = self.racking != math.floor(self.racking)
        merged = [(s, self._merged_op(s, op, half)) for s, op in other.slots.items()]
        for _, op in merged:
            if op is None:
                return False
        for s, size in other.sizes.items():
            mine = self.sizes.get(s)
            if mine and any(b in mine and mine[b] != v for b, v in size.items()):
                return False
        self.kind = kind
        if self.gripper is None:
            self.gripper = other.gripper
        for s, op in merged:
            assert op is not None
            self.slots[s] = op
            if s < self._lo:
                self._lo = s
            elif s > self._hi:
                self._hi = s
        for s, size in other.sizes.items():
            if s in self.sizes:
                self.sizes[s].update(size)
            else:
                self.sizes[s] = dict(size)
        return True

    def _merged_op(self, s: int, op: KcSlotOp, half: bool) -> KcSlotOp | None:
        if self.direction == "+":
            edge = self._hi
            if s != edge:
                return op if s > edge else None
            return combine_ops(self.slots[s], op, half_pitch=half)
        if self.direction == "-":
            edge = self._lo
            if s != edge:
                return op if s < edge else None
            return combine_ops(op, self.slots[s], half_pitch=half)
        if s not in self.slots:
            return op
        return combine_ops(self.slots[s], op, half_pitch=half) or combine_ops(
            op, self.slots[s], half_pitch=half
        )


def _grippers_fit(first: str | None, then: str | None) -> bool:
    # yarn comes in at the start of a pass and leaves at its end
    return (then is None and first in (None, "in")) or (first is None and then == "out")


def _same_speed(a: int | str, b: int | str) -> bool:
    # the backend compares speeds as written: the default number 100 differs from "100"
    return type(a) is type(b) and a == b


@dataclass(frozen=True)
class KcHeaders:
    """The header values the k-code writer uses."""

    position: str = "Center"
    width: int = 252


@dataclass(frozen=True)
class KcProgram:
    """The carriage passes of a knitout program and the file-wide settings that shape them."""

    headers: KcHeaders
    passes: tuple[KcPass, ...]
    carrier_spacing: float = 2.0
    carrier_stopping_distance: float = 2.5
