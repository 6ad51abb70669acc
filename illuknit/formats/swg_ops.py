"""What each knitout operation does to the SWG pass builder (one handler per opcode family)."""

from __future__ import annotations

import math
import re
from collections.abc import Callable

from illuknit.core.errors import UnsupportedKnitoutError
from illuknit.formats.swg_build import _Builder, _in_range
from illuknit.formats.swg_ir import CarriageDirection, Gripper, HookAction, PassType, SlotOp
from illuknit.knitout.parse import Needle, Operation

__all__ = ["apply_operation"]

#: ``stitch L T`` -> stitch number, keyed (T, L) as the backend's table is
_STITCH_TABLE: dict[tuple[int, int], int] = {
    (10, -10): 81, (10, 0): 82, (10, 10): 83, (15, 5): 84, (15, 10): 85, (15, 15): 86,
    (20, 10): 87, (20, 15): 88, (20, 20): 89, (25, 15): 90, (25, 20): 91, (25, 25): 92,
    (30, 25): 93, (35, 25): 94, (40, 25): 95, (45, 25): 96, (50, 25): 97, (55, 25): 98,
    (60, 25): 99, (65, 25): 100,
}  # fmt: skip
_UINT = re.compile(r"^[+]?\d+$")


_DIRECTION = {
    "+": CarriageDirection.RIGHT,
    "-": CarriageDirection.LEFT,
    None: CarriageDirection.NONE,
}
_STITCH_OP = {
    ("miss", True): SlotOp.MISS_FRONT,
    ("miss", False): SlotOp.MISS_BACK,
    ("tuck", True): SlotOp.TUCK_FRONT,
    ("tuck", False): SlotOp.TUCK_BACK,
    ("knit", True): SlotOp.KNIT_FRONT,
    ("knit", False): SlotOp.KNIT_BACK,
}


def _bring_in(b: _Builder, op: Operation) -> None:
    for c in op.carriers:
        if c not in ("1", "2", "3", "4", "5", "6", "7", "8", "9", "10"):
            raise b.error(f"carrier {c!r} is not named in the ';;Carriers:' header")
    for c in op.carriers:
        if c in b.carriers:
            raise b.error(f"cannot bring in carrier {c}: it is already active")
    b.carriers.bring_in(op.op, op.carriers)


def _release_hook(b: _Builder, op: Operation) -> None:
    if b.hook is None:
        raise b.error(f"cannot releasehook {' '.join(op.carriers)}: the hook holds nothing")
    direction, held = b.hook
    if held != op.carriers:
        raise b.error(
            f"cannot releasehook {' '.join(op.carriers)}: the hook holds {' '.join(held)}"
        )
    for c in op.carriers:
        b.carriers[c].used_hook = False
    last = b.carriers[op.carriers[0]].last
    assert last is not None  # the hook only holds carriers that have stitched
    slot = b.slot(last[0])
    # the machine releases before the pass and refuses a release pass that moves the carriage
    # empty, so an empty pass the other way comes first when the last pass ran the hook's way
    if b.passes[-1].direction is direction:
        b.passes.append(b.draft(PassType.KNIT_TUCK, direction.opposite, (), slot, SlotOp.SOFT_MISS))
    release = b.draft(PassType.KNIT_TUCK, direction, (), slot, SlotOp.SOFT_MISS)
    release.hook = HookAction.RELEASE
    b.passes.append(release)
    b.hook = None


def _take_out(b: _Builder, op: Operation) -> None:
    for c in op.carriers:
        car = b.carriers.get(c)
        if car is None:
            raise b.error(f"cannot take out carrier {c}: it is not active")
        if car.last is None:
            raise b.error(f"cannot take out carrier {c}: it has not stitched yet")
        if op.op == "out" and car.used_hook:
            raise b.error(f"cannot 'out' carrier {c} while the hook holds it (releasehook first)")
    if op.op == "outhook" and b.hook is not None:
        raise b.error(
            f"cannot outhook {' '.join(op.carriers)}: the hook holds {' '.join(b.hook[1])}"
        )
    # carriers leave to the right, from the rightmost needle any of them is attached to
    best: tuple[int, Needle] | None = None
    for c in op.carriers:
        last = b.carriers[c].last
        assert last is not None
        s = b.slot(last[0])
        if best is None or s > best[0]:
            best = (s, last[0])
    assert best is not None
    d = b.draft(PassType.KNIT_TUCK, CarriageDirection.RIGHT, op.carriers, best[0], SlotOp.SOFT_MISS)
    d.gripper = Gripper.OUT
    if op.op == "outhook":
        d.hook = HookAction.OUT
    b.merge(d)
    for c in op.carriers:
        del b.carriers[c]


#: Operations without yarn that the machine does as the stitch they name.
_YARNLESS = {"drop": "knit", "amiss": "tuck"}


def _stitch(b: _Builder, op: Operation) -> None:
    """knit, tuck, miss, drop (= knit without yarn) and amiss (= tuck without yarn)."""
    name = _YARNLESS.get(op.op, op.op)
    n = op.needle
    cs = op.carriers
    if name == "miss" and not cs:
        raise b.error("miss needs carriers (a miss without yarn does nothing)")
    direction = _DIRECTION[op.direction] if cs else CarriageDirection.NONE
    if name != "miss":
        b.kick_others(n, cs)
    type_ = PassType.A_MISS if name == "tuck" and not cs else PassType.KNIT_TUCK
    d = b.draft(type_, direction, cs, b.slot(n), _STITCH_OP[(name, n.is_front)])
    d.presser = b.presser
    b.take_in(cs, d)
    b.merge(d)
    b.set_last(cs, direction, n)


def _transfer(b: _Builder, op: Operation) -> None:
    """xfer (= split without yarn) and split, hook to hook or to/from sliders."""
    n, t = op.needles
    cs = op.carriers
    if n.is_front != t.is_front:
        back, front = (n, t) if t.is_front else (t, n)
        if back.index + b.racking != front.index:
            raise b.error(f"needles {n} and {t} are not aligned at racking {b.racking:g}")
    if n.is_slider and t.is_slider:
        raise b.error(f"cannot move loops from slider {n} to slider {t}")
    if n.is_slider and cs:
        raise b.error(f"cannot split from slider {n}")
    if t.is_slider and cs:
        raise UnsupportedKnitoutError(
            f"split via sliders ({op}) is not implemented by the .dat writer", line=op.line
        )
    if not cs:
        type_ = (
            PassType.XFER_FROM_SLIDERS
            if n.is_slider
            else PassType.XFER_TO_SLIDERS
            if t.is_slider
            else PassType.XFER
        )
        slot_op = SlotOp.XFER_TO_BACK if n.is_front else SlotOp.XFER_TO_FRONT
        direction = CarriageDirection.NONE
    else:
        type_ = PassType.SPLIT
        slot_op = SlotOp.SPLIT_TO_BACK if n.is_front else SlotOp.SPLIT_TO_FRONT
        direction = _DIRECTION[op.direction]
    b.kick_others(n, cs)
    d = b.draft(type_, direction, cs, b.slot(n), slot_op)
    if not cs:
        d.stitch = 0  # transfers use the machine's own transfer stitch
    if any(b.carriers[c].pending_in is not None for c in cs if c in b.carriers):
        # the backend would put the yarn-in gripper action on a split pass, which it doubts
        # the machine does; knit or tuck with the carrier first
        raise UnsupportedKnitoutError(
            f"bringing carriers in on a split ({op}) is not supported: knit or tuck with "
            f"{' '.join(cs)} first",
            line=op.line,
        )
    b.take_in(cs, d)
    b.merge(d)
    b.carriers.follow_loop(n, t)  # a yarn attached to the moved loop went with it
    b.set_last(cs, direction, n)


def _rack(b: _Builder, op: Operation) -> None:
    assert op.value is not None
    r = op.value
    if r - math.floor(r) not in (0.0, 0.25):
        raise b.error(f"racking must be an integer or an integer + 0.25, got {r:g}")
    b.racking = r
    b.rack_floor = math.floor(r)


def _stitch_size(b: _Builder, op: Operation) -> None:
    if len(op.args) != 2 or not all(a.lstrip("+-").isdigit() for a in op.args):
        raise b.error(f"stitch takes two integers L T, got {' '.join(op.args)!r}")
    leading, size = int(op.args[0]), int(op.args[1])
    if (size, leading) not in _STITCH_TABLE:
        known = ", ".join(f"{t2} {t1}" for t1, t2 in _STITCH_TABLE)
        raise b.error(f"'stitch {leading} {size}' is not in the stitch table ({known})")
    b.stitch = _STITCH_TABLE[(size, leading)]


def _extension(b: _Builder, op: Operation) -> None:
    if op.op == "x-stitch-number":
        b.stitch = _check_uint(op, b)
        _in_range("stitch_number", b.stitch, f"{op.op} {op.args[0]}", op.line)
    elif op.op == "x-speed-number":
        b.speed = _check_uint(op, b)
        _in_range("speed_number", b.speed, f"{op.op} {op.args[0]}", op.line)
    elif op.op == "x-presser-mode":
        if len(op.args) != 1 or op.args[0] not in ("on", "off", "auto"):
            raise b.error(f"x-presser-mode takes on, off or auto, got {' '.join(op.args)!r}")
        b.presser = op.args[0]
    else:
        raise UnsupportedKnitoutError(
            f"extension {op.op!r} is not supported by the SWG .dat writer", line=op.line
        )


def _pause(b: _Builder, op: Operation) -> None:
    b.pause_pending = True


_HANDLERS: dict[str, Callable[[_Builder, Operation], None]] = {
    "in": _bring_in,
    "inhook": _bring_in,
    "releasehook": _release_hook,
    "out": _take_out,
    "outhook": _take_out,
    "knit": _stitch,
    "tuck": _stitch,
    "miss": _stitch,
    "drop": _stitch,
    "amiss": _stitch,
    "xfer": _transfer,
    "split": _transfer,
    "rack": _rack,
    "stitch": _stitch_size,
    "pause": _pause,
}


def apply_operation(b: _Builder, op: Operation) -> None:
    """Apply one knitout operation to the builder's passes and machine state."""
    handler = _HANDLERS.get(op.op)
    if handler is None and op.op.startswith("x-"):
        handler = _extension
    if handler is None:
        raise UnsupportedKnitoutError(f"operation {op.op!r} is not supported", line=op.line)
    handler(b, op)


def _check_uint(op: Operation, b: _Builder) -> int:
    if len(op.args) != 1 or _UINT.match(op.args[0]) is None:
        raise b.error(f"{op.op} takes one non-negative integer, got {' '.join(op.args)!r}")
    return int(op.args[0])
