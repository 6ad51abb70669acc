"""The SWG machine's carriage passes as data: what :func:`~illuknit.formats.swg_passes.plan_swg`
returns and the ``.dat`` writer encodes.

A :class:`MachinePass` is one row of the ``.dat``: its :class:`PassType` (what the needles do;
passes of different types never merge), its :class:`MachinePassKind` (what the pass is for:
knitting, a kickback, a hook release, ...), the :class:`CarriageDirection` it runs and travels,
and one :class:`SlotOp` per needle slot. These are the machine's vocabulary, not the scheduler's:
:class:`illuknit.knit.ir.PassKind` says what a *scheduled* pass does (knit, xfer, drop) and
:data:`illuknit.knit.ir.Direction` is a knitout direction (``"+"``/``"-"``, never none).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

__all__ = [
    "CarriageDirection",
    "Gripper",
    "HookAction",
    "MachinePass",
    "MachinePassKind",
    "PassType",
    "SlotOp",
    "SwgPlan",
    "pass_kind",
]


class CarriageDirection(Enum):
    """Carriage direction: rightward (``+``), leftward (``-``) or none (transfers)."""

    RIGHT = "+"
    LEFT = "-"
    NONE = ""

    @property
    def opposite(self) -> CarriageDirection:
        """RIGHT <-> LEFT; NONE stays NONE."""
        return {
            CarriageDirection.RIGHT: CarriageDirection.LEFT,
            CarriageDirection.LEFT: CarriageDirection.RIGHT,
        }.get(self, self)


class PassType(Enum):
    """What the needles do in a pass; passes of different types never merge."""

    KNIT_TUCK = "knit-tuck"  # knit, tuck, miss, drop and carrier moves
    A_MISS = "a-miss"
    SPLIT = "split"
    XFER = "xfer"
    XFER_TO_SLIDERS = "xfer-to-sliders"
    XFER_FROM_SLIDERS = "xfer-from-sliders"


class HookAction(Enum):
    """Yarn-inserting hook action of a pass."""

    IN = "hook-in"
    RELEASE = "hook-release"
    OUT = "hook-out"


class Gripper(Enum):
    """Yarn gripper action of a pass (yarn in before it, yarn out after it)."""

    IN = "gripper-in"
    OUT = "gripper-out"


class SlotOp(Enum):
    """What happens at one needle slot in a pass, with its KnitPaint colour code.

    Several members share a colour (e.g. ``KNIT_FRONT`` and ``KNIT_FRONT_MISS_BACK``) but are
    different operations for merging: a combined slot takes no third operation.
    """

    SOFT_MISS = "soft-miss"  # carrier move only; any other op at the slot replaces it
    MISS_FRONT = "miss-f"
    MISS_BACK = "miss-b"
    TUCK_FRONT = "tuck-f"
    TUCK_BACK = "tuck-b"
    KNIT_FRONT = "knit-f"
    KNIT_BACK = "knit-b"
    KNIT_FRONT_KNIT_BACK = "knit-f+knit-b"
    KNIT_FRONT_TUCK_BACK = "knit-f+tuck-b"
    KNIT_FRONT_MISS_BACK = "knit-f+miss-b"
    TUCK_FRONT_KNIT_BACK = "tuck-f+knit-b"
    TUCK_FRONT_TUCK_BACK = "tuck-f+tuck-b"
    TUCK_FRONT_MISS_BACK = "tuck-f+miss-b"
    MISS_FRONT_KNIT_BACK = "miss-f+knit-b"
    MISS_FRONT_TUCK_BACK = "miss-f+tuck-b"
    MISS_FRONT_MISS_BACK = "miss-f+miss-b"
    XFER_TO_BACK = "xfer-f>b"
    XFER_TO_FRONT = "xfer-b>f"
    SPLIT_TO_BACK = "split-f>b"
    SPLIT_TO_FRONT = "split-b>f"

    @property
    def color(self) -> int:
        """KnitPaint colour index written in the raster."""
        return _COLOR[self]

    @property
    def stitches_front(self) -> bool:
        """True when the front needle of the slot forms a loop (knit or tuck)."""
        return self in _FRONT_STITCH

    @property
    def stitches_back(self) -> bool:
        """True when the back needle of the slot forms a loop (knit or tuck)."""
        return self in _BACK_STITCH


_S = SlotOp
_COLOR: dict[SlotOp, int] = {
    _S.SOFT_MISS: 16,
    _S.MISS_FRONT: 216,
    _S.MISS_BACK: 217,
    _S.TUCK_FRONT: 11,
    _S.TUCK_BACK: 12,
    _S.KNIT_FRONT: 51,
    _S.KNIT_BACK: 52,
    _S.KNIT_FRONT_KNIT_BACK: 3,
    _S.KNIT_FRONT_TUCK_BACK: 41,
    _S.KNIT_FRONT_MISS_BACK: 51,
    _S.TUCK_FRONT_KNIT_BACK: 42,
    _S.TUCK_FRONT_TUCK_BACK: 88,
    _S.TUCK_FRONT_MISS_BACK: 11,
    _S.MISS_FRONT_KNIT_BACK: 52,
    _S.MISS_FRONT_TUCK_BACK: 12,
    _S.MISS_FRONT_MISS_BACK: 16,
    _S.XFER_TO_BACK: 20,
    _S.XFER_TO_FRONT: 30,
    _S.SPLIT_TO_BACK: 101,
    _S.SPLIT_TO_FRONT: 102,
}
_FRONT_STITCH = frozenset(
    {
        _S.TUCK_FRONT,
        _S.KNIT_FRONT,
        _S.KNIT_FRONT_KNIT_BACK,
        _S.KNIT_FRONT_TUCK_BACK,
        _S.KNIT_FRONT_MISS_BACK,
        _S.TUCK_FRONT_KNIT_BACK,
        _S.TUCK_FRONT_TUCK_BACK,
        _S.TUCK_FRONT_MISS_BACK,
    }
)
_BACK_STITCH = frozenset(
    {
        _S.TUCK_BACK,
        _S.KNIT_BACK,
        _S.KNIT_FRONT_KNIT_BACK,
        _S.KNIT_FRONT_TUCK_BACK,
        _S.TUCK_FRONT_KNIT_BACK,
        _S.TUCK_FRONT_TUCK_BACK,
        _S.MISS_FRONT_KNIT_BACK,
        _S.MISS_FRONT_TUCK_BACK,
    }
)
_EXPLICIT_MISS = frozenset({_S.MISS_FRONT, _S.MISS_BACK, _S.MISS_FRONT_MISS_BACK})


class MachinePassKind(Enum):
    """What a carriage pass is for (derived from its type, slots, carriers and hook)."""

    KNIT = "knit"  # knits and/or tucks with yarn
    MISS = "miss"  # explicit knitout misses only: carrier placed on purpose
    KICKBACK = "kickback"  # carrier moved out of the way / back to the right side
    CARRIER_OUT = "carrier-out"  # carriers taken out (out / outhook)
    HOOK_RELEASE = "hook-release"
    CARRIAGE_MOVE = "carriage-move"  # empty pass so the hook release does not move the carriage
    DROP = "drop"
    AMISS = "amiss"
    TRANSFER = "transfer"
    TRANSFER_TO_SLIDERS = "transfer-to-sliders"
    TRANSFER_FROM_SLIDERS = "transfer-from-sliders"
    SPLIT = "split"


@dataclass(frozen=True)
class MachinePass:
    """One carriage pass of the SWG machine (one row of the ``.dat``).

    Attributes
    ----------
    kind : MachinePassKind
        What the pass is for.
    type : PassType
        Needle-action type (decides which operations could share the pass).
    direction : CarriageDirection
        Knitout direction of the pass; NONE for transfers, drops and a-misses.
    carriage : CarriageDirection
        Where the carriage actually travels: drops and a-misses go away from where it stands;
        transfers stay NONE (the machine picks).
    carriage_move : bool
        True when the carriage must first travel empty to the side the pass starts from.
    carriers : tuple of str
        Carrier set, in knitout order (first = leading carrier of a plated pair).
    racking : float
        Racking R (back needle k faces front needle k + R).
    stitch : int
        Stitch number (KnitPaint stitch table index; 0 = machine default for transfers).
    speed : int
        Speed number (0 = default).
    slots : tuple of (int, SlotOp)
        Needle slots the pass acts on, ascending. Slot of a back needle = index + floor(racking).
    hook : HookAction or None
    gripper : Gripper or None
    pause : bool
        Optional operator stop before the pass.
    presser : str or None
        Fabric presser mode in force (``on``/``off``/``auto``); None for passes without one.
    """

    kind: MachinePassKind
    type: PassType
    direction: CarriageDirection
    carriage: CarriageDirection
    carriage_move: bool
    carriers: tuple[str, ...]
    racking: float
    stitch: int
    speed: int
    slots: tuple[tuple[int, SlotOp], ...]
    hook: HookAction | None = None
    gripper: Gripper | None = None
    pause: bool = False
    presser: str | None = None

    def __post_init__(self) -> None:
        if not self.slots:
            raise ValueError("`slots` must name at least one needle slot")
        if any(b[0] <= a[0] for a, b in zip(self.slots, self.slots[1:], strict=False)):
            raise ValueError("`slots` must be strictly ascending")

    @property
    def needle_range(self) -> tuple[int, int]:
        """(leftmost, rightmost) slot the pass acts on."""
        return self.slots[0][0], self.slots[-1][0]

    @property
    def has_front(self) -> bool:
        """True when a front needle knits or tucks in this pass."""
        return any(op.stitches_front for _, op in self.slots)

    @property
    def has_back(self) -> bool:
        """True when a back needle knits or tucks in this pass."""
        return any(op.stitches_back for _, op in self.slots)


def pass_kind(
    type_: PassType,
    carriers: tuple[str, ...],
    ops: list[SlotOp],
    hook: HookAction | None,
    gripper: Gripper | None,
) -> MachinePassKind:
    """Classify a pass by what it contains (also used by the ``.dat`` reader)."""
    simple = {
        PassType.A_MISS: MachinePassKind.AMISS,
        PassType.SPLIT: MachinePassKind.SPLIT,
        PassType.XFER: MachinePassKind.TRANSFER,
        PassType.XFER_TO_SLIDERS: MachinePassKind.TRANSFER_TO_SLIDERS,
        PassType.XFER_FROM_SLIDERS: MachinePassKind.TRANSFER_FROM_SLIDERS,
    }
    if type_ in simple:
        return simple[type_]
    stitches = any(op.stitches_front or op.stitches_back for op in ops)
    if not carriers:
        if stitches:
            return MachinePassKind.DROP
        return (
            MachinePassKind.HOOK_RELEASE
            if hook is HookAction.RELEASE
            else MachinePassKind.CARRIAGE_MOVE
        )
    if stitches:
        return MachinePassKind.KNIT
    if any(op in _EXPLICIT_MISS for op in ops):
        return MachinePassKind.MISS
    return MachinePassKind.CARRIER_OUT if gripper is Gripper.OUT else MachinePassKind.KICKBACK


@dataclass(frozen=True)
class SwgPlan:
    """The passes of a program plus the header values the raster needs.

    Attributes
    ----------
    passes : tuple of MachinePass
    width : int
        ``;;Width`` (needles per bed; 540 when absent).
    position : str
        ``;;Position``: ``Center`` (default), ``Keep``, ``Left`` or ``Right``.
    """

    passes: tuple[MachinePass, ...]
    width: int = 540
    position: str = "Center"

    def __post_init__(self) -> None:
        if self.position not in ("Center", "Keep", "Left", "Right"):
            raise ValueError(
                f"`position` must be Center, Keep, Left or Right, got {self.position!r}"
            )
        if self.width < 1:
            raise ValueError(f"`width` must be positive, got {self.width}")
