"""One pass row of a ``.dat`` read back: needle colours and option lines -> :class:`DatPass`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from illuknit.core.errors import DatFormatError
from illuknit.formats.swg_ir import (
    CarriageDirection,
    Gripper,
    HookAction,
    MachinePassKind,
    PassType,
    SlotOp,
    pass_kind,
)

__all__ = ["DatPass", "decode_carriers", "decode_pass_row"]

# colour -> the operation it stands for (shared colours read as the simpler operation)
_OP_OF_COLOR: dict[int, SlotOp] = {}
for _op in SlotOp:
    _OP_OF_COLOR.setdefault(_op.color, _op)
_STOP_MARK = 13
_DIRECTIONS = {7: CarriageDirection.LEFT, 6: CarriageDirection.RIGHT, 1: CarriageDirection.NONE}
_HOOKS = {0: None, 10: HookAction.IN, 20: HookAction.OUT, 90: HookAction.RELEASE}


@dataclass(frozen=True)
class DatPass:
    """What one pass row of a ``.dat`` does.

    Attributes
    ----------
    row : int
        0-based index among the pass rows (the fixed courses are not counted).
    kind : MachinePassKind
    type : PassType
    carriage : CarriageDirection
        Direction mark of the row (NONE for transfers).
    carriage_move : bool
        Option R5 = 2: the carriage first travels empty to the side the row starts from.
    carriers : tuple of str
        Decoded from option R3. A code 11..19 reads as carrier 1 leading 1..9, which the file
        cannot tell apart from carrier 10 leading the same carrier.
    racking : float
    stitch : int
    speed : int
    slots : tuple of (int, int)
        (needle offset from the design's left edge, colour code) of each needle acted on.
    hook : HookAction or None
    gripper : Gripper or None
    pause : bool
    presser : bool
        Option R11 = 101: fabric presser on.
    """

    row: int
    kind: MachinePassKind
    type: PassType
    carriage: CarriageDirection
    carriage_move: bool
    carriers: tuple[str, ...]
    racking: float
    stitch: int
    speed: int
    slots: tuple[tuple[int, int], ...]
    hook: HookAction | None
    gripper: Gripper | None
    pause: bool
    presser: bool

    @property
    def needle_range(self) -> tuple[int, int]:
        """(leftmost, rightmost) needle offset the row acts on."""
        return self.slots[0][0], self.slots[-1][0]


def decode_carriers(code: int) -> tuple[str, ...]:
    """Option-line carrier code -> carrier names (inverse of ``dat.carrier_code``)."""
    if code in (0, 255):
        return ()
    if 1 <= code <= 10:
        return (str(code),)
    if code == 110:
        return ("1", "10")
    if 20 <= code <= 90 and code % 10 == 0:
        return (str(code // 10), "10")
    if 11 <= code <= 98 and code % 10 != 0:
        return (str(code // 10), str(code % 10))
    raise DatFormatError(f"carrier code {code} names no carrier set")


def _row_type(left: dict[int, int], right: dict[int, int], colors: set[int]) -> PassType:
    if left[13] == 1:
        return PassType.XFER_TO_SLIDERS
    if left[13] == 3:
        return PassType.XFER_FROM_SLIDERS
    if left[12] == 10:
        return PassType.SPLIT
    if left[12] == 20:
        return PassType.A_MISS
    if right[5] == 1 and colors <= {SlotOp.XFER_TO_BACK.color, SlotOp.XFER_TO_FRONT.color}:
        return PassType.XFER
    return PassType.KNIT_TUCK


def decode_pass_row(
    pixels: NDArray[np.uint8], *, span: int, left_space: int, index: int
) -> DatPass:
    """Read one raster row laid out as :func:`illuknit.formats.dat.raster_from_plan` writes it."""
    right_base = left_space + span + 4
    left = {o: int(pixels[left_space - 5 - 2 * o]) for o in range(1, 21)}
    right = {o: int(pixels[right_base + 2 * o]) for o in range(1, 21)}
    mark = int(pixels[left_space - 6])
    if mark not in _DIRECTIONS or right[15] not in _HOOKS:
        raise DatFormatError(f"pass row {index}: direction mark {mark} / hook {right[15]} unknown")
    needles = pixels[left_space : left_space + span]
    where = np.flatnonzero((needles != 0) & (needles != _STOP_MARK))
    if len(where) == 0:
        raise DatFormatError(f"pass row {index} acts on no needle")
    slots = tuple((int(s), int(needles[s])) for s in where)
    unknown = {c for _, c in slots} - set(_OP_OF_COLOR)
    if unknown:
        raise DatFormatError(f"pass row {index}: colour(s) {sorted(unknown)} are no operation")
    type_ = _row_type(left, right, {c for _, c in slots})
    carriers = decode_carriers(right[3])
    hook = _HOOKS[right[15]]
    grip = right[10]
    gripper = None if grip == 0 else Gripper.OUT if grip > 100 else Gripper.IN
    ops = [_OP_OF_COLOR[c] for _, c in slots]
    quarter = 0.25 if left[3] else 0.0
    racking = (left[2] + 1 if left[4] == 11 else -left[2]) + quarter
    return DatPass(
        row=index,
        kind=pass_kind(type_, carriers, ops, hook, gripper),
        type=type_,
        carriage=_DIRECTIONS[mark],
        carriage_move=right[5] == 2,
        carriers=carriers,
        racking=float(racking),
        stitch=right[6],
        speed=0 if left[5] == 0 else left[5] - 10,
        slots=slots,
        hook=hook,
        gripper=gripper,
        pause=left[7] == 20,
        presser=right[11] == 101,
    )
