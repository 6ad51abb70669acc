"""The knitout program as data: one typed operation vocabulary, the program, and its text.

Every stage that makes or reads knitout shares this IR, in the spirit of knitout_interpreter's
typed instructions: the scheduler's lowering (:func:`~illuknit.knit.knitout.lower_to_knitout`)
returns a :class:`KnitoutProgram`, the parser (:func:`~illuknit.knitout.parse.parse_knitout`)
reads a file into one, and the checker, the float measure and the machine writers read it.
Text is written only at the edge, by :func:`format_knitout`.

The vocabulary is :class:`~enum.StrEnum` members whose values are the knitout tokens
(:class:`Opcode`, :class:`Bed`, :class:`Direction`), so ``Opcode.KNIT == "knit"`` and code that
compares with the plain tokens keeps working; needles are integers on a :class:`Bed`
(:class:`Needle`), carriers a tuple of names in the written order. Extension opcodes
(``x-stitch-number``, ``x-speed-number``, ...) are open-ended: they stay their name (a ``str``)
with their raw arguments.

Each :class:`Operation` carries its line (the program's lines are those of its text, comments
included, so a finding's line is the file's) and, when a scheduler made it, its provenance:
``step``, the index of the schedule step it came from (None for lines no step wrote, such as
settings or a machine's waste section).
"""

from __future__ import annotations

import functools
import itertools
from dataclasses import dataclass, field
from enum import StrEnum

__all__ = [
    "BEDS",
    "Bed",
    "Direction",
    "KnitoutProgram",
    "Needle",
    "Opcode",
    "Operation",
    "format_knitout",
    "make_needle",
]


class Opcode(StrEnum):
    """The knitout-2 opcodes (extensions ``x-*`` are not members: they stay their name)."""

    KNIT = "knit"
    TUCK = "tuck"
    SPLIT = "split"
    MISS = "miss"
    DROP = "drop"
    AMISS = "amiss"
    XFER = "xfer"
    IN = "in"
    INHOOK = "inhook"
    RELEASEHOOK = "releasehook"
    OUT = "out"
    OUTHOOK = "outhook"
    RACK = "rack"
    STITCH = "stitch"
    PAUSE = "pause"


class Bed(StrEnum):
    """Needle bed: ``f`` front, ``b`` back, ``fs`` / ``bs`` their sliders."""

    FRONT = "f"
    BACK = "b"
    FRONT_SLIDERS = "fs"
    BACK_SLIDERS = "bs"


class Direction(StrEnum):
    """Carriage direction of a stitch: ``+`` rightward (increasing needles), ``-`` leftward."""

    RIGHT = "+"
    LEFT = "-"


#: bed prefixes: front, back, front sliders, back sliders
BEDS = tuple(b.value for b in Bed)


@dataclass(frozen=True, order=True)
class Needle:
    """One needle: bed (``f``, ``b``, ``fs``, ``bs``) and index (may be negative)."""

    bed: Bed
    index: int

    def __post_init__(self) -> None:
        bed = Bed._value2member_map_.get(self.bed)
        if bed is None:
            raise ValueError(f"`bed` must be one of {BEDS}, got {self.bed!r}")
        object.__setattr__(self, "bed", bed)

    @property
    def is_front(self) -> bool:
        """True for ``f`` and ``fs``."""
        return self.bed[0] == "f"

    @property
    def is_slider(self) -> bool:
        """True for slider needles (``fs``, ``bs``), which hold loops but cannot form them."""
        return len(self.bed) == 2

    def __str__(self) -> str:
        return f"{self.bed}{self.index}"


@functools.lru_cache(maxsize=8192)  # programs name the same needles over and over
def make_needle(bed: str, index: int) -> Needle:
    """The :class:`Needle` ``bed`` ``index`` (shared: a program names few distinct needles)."""
    return Needle(Bed(bed), index)


@dataclass(frozen=True)
class Operation:
    """One knitout instruction.

    Attributes
    ----------
    line : int
        1-based line number in the program's text.
    op : Opcode or str
        An :class:`Opcode`, or the name of an extension (``x-stitch-number``, ...).
    direction : Direction or None
        :attr:`Direction.RIGHT` (``+``) or :attr:`Direction.LEFT` (``-``); None for undirected
        operations.
    needles : tuple of Needle
        0, 1 (knit, tuck, miss, drop, amiss) or 2 (split, xfer) needles, source first.
    carriers : tuple of str
        Carrier set in the written order (order matters for plating and for ``in`` sets).
    value : float or None
        Racking for ``rack``.
    args : tuple of str
        Raw arguments of ``stitch``, ``x-*`` and ``pause``.
    tabs : bool
        True when the line separates tokens with tabs (the SWG converter refuses them).
    step : int or None
        Provenance: the index of the schedule step this operation was lowered from (None when
        no step made it: parsed text, settings, a machine's waste section). Not compared.
    """

    line: int
    op: Opcode | str
    direction: Direction | None = None
    needles: tuple[Needle, ...] = ()
    carriers: tuple[str, ...] = ()
    value: float | None = None
    args: tuple[str, ...] = ()
    tabs: bool = False
    step: int | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        if self.line < 1:
            raise ValueError(f"`line` must be >= 1, got {self.line}")
        if self.direction is not None:
            direction = Direction._value2member_map_.get(self.direction)
            if direction is None:
                raise ValueError(f"`direction` must be '+', '-' or None, got {self.direction!r}")
            object.__setattr__(self, "direction", direction)
        op = Opcode._value2member_map_.get(self.op)
        if op is not None:
            object.__setattr__(self, "op", op)

    @property
    def needle(self) -> Needle:
        """The first (or only) needle."""
        return self.needles[0]

    def at(self, line: int, step: int | None = None) -> Operation:
        """This operation on ``line`` with provenance ``step`` (a copy that skips re-checking:
        a program repeats few distinct operations)."""
        op = object.__new__(Operation)
        fields = self.__dict__.copy()
        fields["line"] = line
        fields["step"] = step
        object.__setattr__(op, "__dict__", fields)
        return op

    def __str__(self) -> str:
        return _operation_text(
            self.op, self.direction, self.needles, self.carriers, self.value, self.args
        )


@functools.lru_cache(maxsize=1 << 16)
def _operation_text(
    op: str,
    direction: str | None,
    needles: tuple[Needle, ...],
    carriers: tuple[str, ...],
    value: float | None,
    args: tuple[str, ...],
) -> str:
    parts = [op]
    if direction is not None:
        parts.append(direction)
    parts += [str(n) for n in needles]
    parts += list(carriers)
    if value is not None:
        parts.append(format_number(value))
    parts += list(args)
    return " ".join(parts)


def format_number(x: float) -> str:
    """``0``, ``-1``, ``0.25``: integers without a decimal point."""
    return str(int(x)) if float(x).is_integer() else repr(float(x))


@dataclass(frozen=True)
class KnitoutProgram:
    """A knitout program: its header, its operations and its comment lines, each on its line.

    Attributes
    ----------
    version : int
        Version from the magic line ``;!knitout-N``.
    headers : tuple of (str, str, int)
        ``(name, value, line)`` of each ``;;Name: value`` header line, in file order.
    operations : tuple of Operation
        Instructions in file order.
    n_lines : int
        Number of lines of the text.
    crlf : bool
        True when the text used CRLF line endings (the converter warns).
    comments : tuple of (int, str)
        ``(line, text)`` of each whole-line comment (``text`` starts with ``;``), in file order.
        Not compared.
    """

    version: int
    headers: tuple[tuple[str, str, int], ...] = ()
    operations: tuple[Operation, ...] = ()
    n_lines: int = 1
    crlf: bool = False
    comments: tuple[tuple[int, str], ...] = field(default=(), compare=False)
    _header_map: dict[str, tuple[str, int]] = field(
        default_factory=dict, init=False, repr=False, compare=False
    )

    def __post_init__(self) -> None:
        if self.n_lines < 1:
            raise ValueError(f"`n_lines` must be >= 1, got {self.n_lines}")
        lines = [op.line for op in self.operations]
        if any(b <= a for a, b in itertools.pairwise(lines)):
            raise ValueError("`operations` must be in strictly increasing line order")
        # first occurrence wins, as in the converter
        hm: dict[str, tuple[str, int]] = {}
        for name, value, line in self.headers:
            hm.setdefault(name, (value, line))
        object.__setattr__(self, "_header_map", hm)

    def header(self, name: str) -> tuple[str, int] | None:
        """``(value, line)`` of header ``name`` (first occurrence), or None."""
        return self._header_map.get(name)

    @property
    def width(self) -> int | None:
        """The ``;;Width`` header as a positive integer; None when absent or not one."""
        w = self.header("Width")
        if w is None or not (w[0].isascii() and w[0].isdigit()) or int(w[0]) == 0:
            return None
        return int(w[0])


def format_knitout(program: KnitoutProgram) -> str:
    """The text of ``program``: the magic line, the header, then each operation and comment on
    its line (lines nothing names are blank), single spaces between tokens, LF line endings,
    ending with a newline.

    >>> p = KnitoutProgram(2, (("Carriers", "1 2 3", 2),), (Operation(4, "knit", "+", (make_needle("f", 1),), ("3",)),), 4, comments=((3, "; hello"),))
    >>> format_knitout(p)
    ';!knitout-2\\n;;Carriers: 1 2 3\\n; hello\\nknit + f1 3\\n'
    """
    lines = [""] * program.n_lines
    lines[0] = f";!knitout-{program.version}"
    for name, value, line in program.headers:
        lines[line - 1] = f";;{name}: {value}"
    for line, text in program.comments:
        lines[line - 1] = text
    for op in program.operations:
        lines[op.line - 1] = str(op)
    return "\n".join(lines) + "\n"
