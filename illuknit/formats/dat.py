"""Shima Seiki ``.dat`` files: knitout -> passes -> raster -> bytes, and back to passes.

A ``.dat`` is a KnitPaint raster image: one row per carriage pass, the needle slots in the middle
coloured by what each needle does (colour = operation code), and on both sides twenty *option
lines* whose values set the carriers, stitch and speed numbers, racking, hook and gripper actions
of the row. Three fixed courses come before and after the passes. On disk it is a 0x600-byte
header (four little-endian uint16 ``xmin, ymin, xmax, ymax`` at offset 0, the magic 1000 at
offsets 8 and 16, a 256-colour palette at 0x200) followed by the rows run-length encoded as
``(colour, length)`` byte pairs.

Stages, each pure:

* :func:`~illuknit.formats.swg_passes.plan_swg` -- knitout -> :class:`SwgPlan` (passes);
* :func:`raster_from_plan` -- passes -> raster (ndarray of shape (height, width), uint8);
* :func:`encode_dat` -- raster -> bytes; :func:`decode_dat` the way back;
* :func:`read_dat` -- bytes -> :class:`DatFile` whose ``passes`` say what each row does.

The layout follows the reference SWG backend (``knitout-to-dat.js``) byte for byte; the tests
hold it to that.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache
from importlib import resources

import numpy as np
from numpy.typing import NDArray

from illuknit.core.errors import DatFormatError, MachineRuleError, UnsupportedKnitoutError
from illuknit.formats.dat_rows import DatPass, decode_pass_row
from illuknit.formats.swg_ir import (
    CarriageDirection,
    Gripper,
    HookAction,
    MachinePass,
    PassType,
    SwgPlan,
)
from illuknit.formats.swg_passes import plan_swg
from illuknit.knitout.program import KnitoutProgram

__all__ = [
    "DatFile",
    "DatPass",
    "decode_dat",
    "encode_dat",
    "knitout_to_dat",
    "raster_from_plan",
    "read_dat",
]

#: columns left of the first needle slot: option values/markers, then stop-mark space
LEFT_SPACE = 55
#: columns right of the last needle slot
RIGHT_SPACE = 55
#: rows above the passes' block: end courses (3) + position/width rows and margin (8)
TOP_ROWS = 3 + 8
#: rows below the passes: margin (5) + start courses (3)
BOTTOM_ROWS = 5 + 3
#: raster rows that are not passes
FIXED_ROWS = TOP_ROWS + BOTTOM_ROWS
HEADER_SIZE = 0x600
STOP_MARK = 13

_XFER_TYPES = (PassType.XFER, PassType.XFER_TO_SLIDERS, PassType.XFER_FROM_SLIDERS)


@cache
def _palette() -> bytes:
    """The 256-colour KnitPaint palette (R, G and B planes of 256 bytes each)."""
    data = resources.files("illuknit").joinpath("data/shima_palette.bin").read_bytes()
    assert len(data) == 768
    return data


def carrier_code(carriers: tuple[str, ...], *, type_: PassType) -> int:
    """Option-line code of a carrier set: ``3``, ``34`` (3 leading 4), ``10``, ``110``, ``40``...

    ``10`` is written ``1`` when it leads a pair and ``0`` when it follows any carrier but ``1``;
    no carriers is ``255`` on knit passes ("really none") and ``0`` on transfer passes.
    """
    if not carriers:
        return 255 if type_ is PassType.KNIT_TUCK else 0
    if len(carriers) == 1:
        return int(carriers[0])
    if len(carriers) == 2:
        a, b = carriers
        if a == "10":
            return int("1" + b)
        if b == "10" and a != "1":
            return int(a + "0")
        return int(a + b)
    raise UnsupportedKnitoutError(
        f"a .dat row cannot name {len(carriers)} carriers at once ({' '.join(carriers)}); "
        "plate at most two"
    )


def _byte(value: int, what: str) -> int:
    if not 0 <= value <= 255:
        raise UnsupportedKnitoutError(f"{what} {value} does not fit a .dat option line (0..255)")
    return value


def _pass_options(p: MachinePass, hook_active: bool) -> tuple[dict[int, int], dict[int, int]]:
    """(left, right) option-line values of one pass row, keyed by option number 1..20."""
    left: dict[int, int] = {}
    right: dict[int, int] = {9: 1}  # R9: ignore the links process
    code = carrier_code(p.carriers, type_=p.type)
    right[3] = code
    if p.type is PassType.XFER_TO_SLIDERS:
        left[13] = 1
    elif p.type is PassType.XFER_FROM_SLIDERS:
        left[13] = 3
    elif p.type is PassType.SPLIT:
        left[12] = 10
    elif p.type is PassType.A_MISS:
        left[12] = 20
    if p.gripper is Gripper.IN:
        right[10] = code
    elif p.gripper is Gripper.OUT:
        right[10] = 100 + code
    if p.pause:
        left[7] = 20
    both_beds = p.has_front and p.has_back
    if p.presser == "on" or (
        p.presser == "auto" and not hook_active and p.hook is None and not both_beds
    ):
        right[11] = 101
    right[15] = {HookAction.IN: 10, HookAction.OUT: 20, HookAction.RELEASE: 90, None: 0}[p.hook]
    right[6] = _byte(p.stitch, "stitch number")
    left[5] = left[6] = 0 if p.speed == 0 else _byte(p.speed + 10, "speed number + 10")
    if p.type in _XFER_TYPES:
        right[5] = 1  # knit cancel: transfers use knit+transfer needle selections
        if p.stitch != 0:
            right[13] = 100
    if p.carriage_move:
        right[5] = 2
    floor_r = math.floor(p.racking)
    if p.racking >= 1.0:
        left[4], left[2] = 11, floor_r - 1  # "right 0" is already one needle right
    else:
        left[4], left[2] = 10, -floor_r
    left[3] = 0 if p.racking == floor_r else 1  # quarter pitch
    return left, right


_DIRECTION_MARK = {CarriageDirection.LEFT: 7, CarriageDirection.RIGHT: 6, CarriageDirection.NONE: 1}


def _write_options(
    row: NDArray[np.uint8],
    span: int,
    left: dict[int, int],
    right: dict[int, int],
    direction: CarriageDirection,
) -> None:
    right_base = LEFT_SPACE + span + 4
    for o in range(1, 21):
        row[LEFT_SPACE - 4 - 2 * o] = o
        row[right_base + 2 * o - 1] = o
        if o in left:
            row[LEFT_SPACE - 5 - 2 * o] = left[o]
        if o in right:
            row[right_base + 2 * o] = right[o]
    row[LEFT_SPACE - 6] = row[right_base + 1] = _DIRECTION_MARK[direction]


def _bed_position(plan: SwgPlan, lo: int, hi: int) -> int:
    """Needle where the design's left edge goes, as the ``;;Position`` header asks."""
    span = hi - lo + 1
    if plan.position == "Center":
        if span > plan.width:
            raise MachineRuleError(
                f"the program spans {span} needles, wider than the {plan.width}-needle bed"
            )
        return math.floor((plan.width - span) / 2 + 0.5)
    if plan.position == "Keep":
        if lo <= 0 or hi > plan.width:
            raise MachineRuleError(
                f"';;Position: Keep' needs needles in 1..{plan.width}, the program uses {lo}..{hi}"
            )
        return lo
    return 0 if plan.position == "Right" else 1  # Right: KnitPaint sets the right edge itself


def raster_from_plan(plan: SwgPlan) -> NDArray[np.uint8]:
    """The KnitPaint raster of a plan: ndarray of shape (passes + 19, needles + 110), uint8.

    Row 0 is the first row of the file (a margin); passes follow the three start-up courses.
    """
    slots = [s for p in plan.passes for s, _ in p.slots]
    lo, hi = min(slots), max(slots)
    span = hi - lo + 1
    n = len(plan.passes)
    raster = np.zeros((n + FIXED_ROWS, LEFT_SPACE + span + RIGHT_SPACE), dtype=np.uint8)
    top = n + BOTTOM_ROWS + 4  # position code and width line
    position = _bed_position(plan, lo, hi)
    raster[top, LEFT_SPACE - 7] = position % 100
    raster[top + 1, LEFT_SPACE - 7] = position // 100
    raster[top, LEFT_SPACE - 5 : LEFT_SPACE + span + 5] = 1

    def full_course(y: int, color: int, direction: CarriageDirection, **extra: int) -> None:
        raster[y, LEFT_SPACE : LEFT_SPACE + span] = color
        raster[y, LEFT_SPACE - 1] = raster[y, LEFT_SPACE + span] = STOP_MARK
        right = {3: 255, 9: 1} | {int(k[1:]): v for k, v in extra.items() if k[0] == "R"}
        left = {4: 10} | {int(k[1:]): v for k, v in extra.items() if k[0] == "L"}
        _write_options(raster[y], span, left, right, direction)

    # start-up: a miss course right, then knit front left, knit back right
    full_course(5, 216, CarriageDirection.RIGHT)
    full_course(6, 51, CarriageDirection.LEFT)
    full_course(7, 52, CarriageDirection.RIGHT)
    carriage = CarriageDirection.RIGHT
    hook_active = False
    for i, p in enumerate(plan.passes):
        row = raster[BOTTOM_ROWS + i]
        for s, op in p.slots:
            row[LEFT_SPACE + s - lo] = op.color
        first, last = p.needle_range
        row[LEFT_SPACE + first - lo - 1] = row[LEFT_SPACE + last - lo + 1] = STOP_MARK
        left, right = _pass_options(p, hook_active)
        if p.hook is HookAction.IN:
            hook_active = True
        elif p.hook is HookAction.RELEASE:
            hook_active = False
        _write_options(row, span, left, right, p.carriage)
        if p.carriage is not CarriageDirection.NONE:
            carriage = p.carriage
    y = BOTTOM_ROWS + n
    full_course(y, 51, CarriageDirection.LEFT, R5=2 if carriage is CarriageDirection.LEFT else 0)
    full_course(y + 1, 52, CarriageDirection.RIGHT)
    full_course(y + 2, 3, CarriageDirection.LEFT, L3=1, R7=11)  # R7 11: drop-failure detection on
    return raster


def encode_dat(raster: NDArray[np.uint8]) -> bytes:
    """Raster -> ``.dat`` bytes (header, palette, run-length encoded rows)."""
    h, w = raster.shape
    if not (0 < w < 0xFFFF and 0 < h < 0xFFFF):
        raise UnsupportedKnitoutError(f"a {w} x {h} raster does not fit a .dat header")
    header = bytearray(HEADER_SIZE)
    header[0:8] = np.array([0, 0, w - 1, h - 1], dtype="<u2").tobytes()
    header[8:10] = header[16:18] = (1000).to_bytes(2, "little")
    header[0x200:0x500] = _palette()
    body = bytearray()
    for row in raster:
        body += _encode_row(row)
    return bytes(header + body)


def _encode_row(row: NDArray[np.uint8]) -> bytearray:
    """Runs of one colour as (colour, length) pairs of at most 255.

    A run that is an exact multiple of 255 long and not at the row's end is followed by a
    (colour, 0) pair; KnitPaint reads it as nothing, and the reference writes it, so we do too.
    """
    out = bytearray()
    change = np.flatnonzero(row[1:] != row[:-1]) + 1
    starts = np.concatenate(([0], change))
    ends = np.concatenate((change, [len(row)]))
    for a, e in zip(starts.tolist(), ends.tolist(), strict=True):
        color, length = int(row[a]), e - a
        while length > 255:
            out += bytes((color, 255))
            length -= 255
        out += bytes((color, length))
        if length == 255 and e != len(row):
            out += bytes((color, 0))
    return out


def decode_dat(data: bytes) -> NDArray[np.uint8]:
    """``.dat`` bytes -> raster, ndarray of shape (height, width), uint8."""
    if not isinstance(data, (bytes, bytearray, memoryview)):
        raise DatFormatError(f"a .dat must be bytes, got {type(data).__name__}")
    data = bytes(data)
    if len(data) < HEADER_SIZE:
        raise DatFormatError(f"too short for a .dat ({len(data)} bytes, the header alone is 1536)")
    x0, y0, x1, y1 = np.frombuffer(data[:8], dtype="<u2").tolist()
    if (x0, y0) != (0, 0) or data[8:10] != (1000).to_bytes(2, "little"):
        raise DatFormatError("not a KnitPaint .dat (header origin or magic number differs)")
    w, h = x1 + 1, y1 + 1
    pairs = np.frombuffer(data[HEADER_SIZE:], dtype=np.uint8)
    if len(pairs) % 2:
        raise DatFormatError("the run-length data has an odd number of bytes")
    colors, lengths = pairs[0::2], pairs[1::2].astype(np.int64)
    if int(lengths.sum()) != w * h:
        raise DatFormatError(
            f"the runs cover {int(lengths.sum())} pixels, the header says {w} x {h} = {w * h}"
        )
    flat = np.repeat(colors, lengths)
    return flat.reshape(h, w)


@dataclass(frozen=True)
class DatFile:
    """A decoded ``.dat``.

    Attributes
    ----------
    raster : ndarray of shape (height, width), uint8
        Colour codes, row 0 first in the file.
    passes : tuple of DatPass
        The pass rows (without the six fixed courses), in knitting order.
    position : int
        Bed position code of the design's left edge (0 = KnitPaint places it at the right).
    """

    raster: NDArray[np.uint8]
    passes: tuple[DatPass, ...]
    position: int

    def __post_init__(self) -> None:
        if self.raster.ndim != 2 or self.raster.dtype != np.uint8:
            raise ValueError("`raster` must be a 2-D uint8 array")
        if self.raster.shape[0] != len(self.passes) + FIXED_ROWS:
            raise ValueError("`passes` must have one entry per pass row (height - 19)")

    @property
    def needles(self) -> int:
        """Width of the design in needle slots."""
        return int(self.raster.shape[1]) - LEFT_SPACE - RIGHT_SPACE


def read_dat(data: bytes) -> DatFile:
    """Read a ``.dat``: what each pass row does, with which carriers, at which racking.

    Raises
    ------
    DatFormatError
        When the bytes are not a ``.dat`` laid out as KnitPaint / the SWG backend write them.
    """
    raster = decode_dat(data)
    h, w = raster.shape
    span = w - LEFT_SPACE - RIGHT_SPACE
    if span < 1 or h < FIXED_ROWS:
        raise DatFormatError(f"a {w} x {h} raster has no room for needles and fixed courses")
    raster.setflags(write=False)
    n = h - FIXED_ROWS
    passes = tuple(
        decode_pass_row(raster[BOTTOM_ROWS + i], span=span, left_space=LEFT_SPACE, index=i)
        for i in range(n)
    )
    top = n + BOTTOM_ROWS + 4
    position = int(raster[top, LEFT_SPACE - 7]) + 100 * int(raster[top + 1, LEFT_SPACE - 7])
    return DatFile(raster=raster, passes=passes, position=position)


def knitout_to_dat(program: KnitoutProgram | str) -> bytes:
    """A knitout program (or its text) -> Shima ``.dat`` bytes (identical to the reference SWG
    backend's).

    Raises
    ------
    KnitoutParseError, MachineRuleError
        The text is not knitout, or breaks a rule of the SWG machine (the message names the line).
    UnsupportedKnitoutError
        Valid knitout the writer does not implement; no file is better than a wrong one.
    """
    return encode_dat(raster_from_plan(plan_swg(program)))
