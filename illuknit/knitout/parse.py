"""Strict knitout parser: text -> :class:`KnitoutProgram`.

The first stage of the checker. It reads knitout text (knitout-2 as the CMU SWG converter accepts
it, see ``docs/checker.md``) into a frozen IR: the magic line's version, the comment header
(``;;Name: value`` lines right after line 1) and one :class:`Operation` per instruction, each with
its 1-based line number. Comments and blank lines are dropped.

Only *syntax* is judged here: a malformed line (unknown opcode, wrong number of arguments, a
needle or direction that does not parse, binary data) raises :class:`KnitoutParseError` with the
line number. Everything that parses but breaks a machine rule (carrier not in the header, a
racking of 0.5, tab separators the SWG converter refuses) is left to the later stages, which report
it as a finding together with every other problem of the file.
"""

from __future__ import annotations

import functools
import itertools
import math
import re
from dataclasses import dataclass, field

from illuknit.core.errors import KnitoutParseError

__all__ = [
    "BEDS",
    "KnitoutProgram",
    "Needle",
    "Operation",
    "parse_knitout",
    "parse_needle",
]

#: bed prefixes: front, back, front sliders, back sliders
BEDS = ("f", "b", "fs", "bs")

_NEEDLE_RE = re.compile(r"^(fs|bs|f|b)(-?[0-9]+)$")
_HEADER_RE = re.compile(r"^;;([^:\s;][^:]*): (.*)$")
_MAGIC_RE = re.compile(r"^;!knitout-([0-9]+)$")

# opcode -> (needs direction, number of needles, carriers: "none" | "any" | "some")
_SHAPES: dict[str, tuple[bool, int, str]] = {
    "knit": (True, 1, "any"),
    "tuck": (True, 1, "any"),
    "split": (True, 2, "any"),
    "miss": (True, 1, "any"),  # "miss without carriers" is a machine-rule finding, not syntax
    "drop": (False, 1, "none"),
    "amiss": (False, 1, "none"),
    "xfer": (False, 2, "none"),
    "in": (False, 0, "some"),
    "inhook": (False, 0, "some"),
    "releasehook": (False, 0, "some"),
    "out": (False, 0, "some"),
    "outhook": (False, 0, "some"),
}

#: opcodes that move carriers and (except miss) make loops
STITCH_OPS = frozenset({"knit", "tuck", "split", "miss"})
#: opcodes that manage carriers
CARRIER_OPS = frozenset({"in", "inhook", "releasehook", "out", "outhook"})


@dataclass(frozen=True, order=True)
class Needle:
    """One needle: bed prefix (``f``, ``b``, ``fs``, ``bs``) and index (may be negative)."""

    bed: str
    index: int

    def __post_init__(self) -> None:
        if self.bed not in BEDS:
            raise ValueError(f"`bed` must be one of {BEDS}, got {self.bed!r}")

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
def parse_needle(token: str) -> Needle | None:
    """Parse ``f12``/``b-3``/``fs4``; None when the token is not a needle."""
    m = _NEEDLE_RE.match(token)
    if m is None:
        return None
    return Needle(m.group(1), int(m.group(2)))


@dataclass(frozen=True)
class Operation:
    """One knitout instruction.

    Attributes
    ----------
    line : int
        1-based line number in the source text.
    op : str
        Opcode (``knit``, ``xfer``, ``rack``, ``x-stitch-number``, ...).
    direction : str or None
        ``"+"`` (rightward, increasing needle numbers) or ``"-"``; None for undirected ops.
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
    """

    line: int
    op: str
    direction: str | None = None
    needles: tuple[Needle, ...] = ()
    carriers: tuple[str, ...] = ()
    value: float | None = None
    args: tuple[str, ...] = ()
    tabs: bool = False

    def __post_init__(self) -> None:
        if self.line < 1:
            raise ValueError(f"`line` must be >= 1, got {self.line}")
        if self.direction not in (None, "+", "-"):
            raise ValueError(f"`direction` must be '+', '-' or None, got {self.direction!r}")

    @property
    def needle(self) -> Needle:
        """The first (or only) needle."""
        return self.needles[0]

    def __str__(self) -> str:
        parts = [self.op]
        if self.direction is not None:
            parts.append(self.direction)
        parts += [str(n) for n in self.needles]
        parts += list(self.carriers)
        if self.value is not None:
            parts.append(_format_number(self.value))
        parts += list(self.args)
        return " ".join(parts)


@dataclass(frozen=True)
class KnitoutProgram:
    """A parsed knitout file.

    Attributes
    ----------
    version : int
        Version from the magic line ``;!knitout-N``.
    headers : tuple of (str, str, int)
        ``(name, value, line)`` of each ``;;Name: value`` header line, in file order.
    operations : tuple of Operation
        Instructions in file order.
    n_lines : int
        Number of lines of the source text.
    crlf : bool
        True when the text used CRLF line endings (the converter warns).
    """

    version: int
    headers: tuple[tuple[str, str, int], ...] = ()
    operations: tuple[Operation, ...] = ()
    n_lines: int = 1
    crlf: bool = False
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


def _format_number(x: float) -> str:
    return str(int(x)) if float(x).is_integer() else repr(float(x))


def _parse_number(token: str, line: int, what: str) -> float:
    try:
        x = float(token)
    except ValueError:
        raise KnitoutParseError(f"{what} must be a number, got {token!r}", line=line) from None
    if not math.isfinite(x):
        raise KnitoutParseError(f"{what} must be a finite number, got {token!r}", line=line)
    return x


def _parse_operation(body: str, line: int) -> Operation:
    """One instruction: its parse is cached by text (a program repeats few distinct lines, e.g.
    the same knit at the same needle every other course), and the copy gets its own line."""
    try:
        parsed = _parse_text(body)
    except KnitoutParseError:
        return _parse_uncached(body, line)  # raises again, naming this line
    op = object.__new__(Operation)  # a copy without re-running the frozen __init__
    op.__dict__.update(parsed.__dict__)
    op.__dict__["line"] = line
    return op


@functools.lru_cache(maxsize=1 << 16)
def _parse_text(body: str) -> Operation:
    return _parse_uncached(body, 1)  # the line is replaced in each copy


def _parse_uncached(body: str, line: int) -> Operation:
    tabs = "\t" in body
    tokens = body.split()
    op = tokens[0]
    rest = tokens[1:]
    if op == "rack":
        if len(rest) != 1:
            raise KnitoutParseError(f"rack takes one racking value, got {len(rest)}", line=line)
        return Operation(line, op, value=_parse_number(rest[0], line, "racking"), tabs=tabs)
    if op == "stitch":
        if len(rest) != 2:
            raise KnitoutParseError("stitch takes two values (L T)", line=line)
        for t in rest:
            _parse_number(t, line, "stitch value")
        return Operation(line, op, args=tuple(rest), tabs=tabs)
    if op == "pause":
        return Operation(line, op, args=tuple(rest), tabs=tabs)
    if op.startswith("x-") and len(op) > 2:
        return Operation(line, op, args=tuple(rest), tabs=tabs)
    shape = _SHAPES.get(op)
    if shape is None:
        raise KnitoutParseError(f"unknown operation {op!r}", line=line)
    has_dir, n_needles, carrier_rule = shape
    pos = 0
    direction = None
    if has_dir:
        if not rest or rest[0] not in ("+", "-"):
            got = rest[0] if rest else "nothing"
            raise KnitoutParseError(f"{op} needs a direction '+' or '-', got {got!r}", line=line)
        direction = rest[0]
        pos = 1
    needles = []
    for _ in range(n_needles):
        if pos >= len(rest):
            raise KnitoutParseError(f"{op} needs {n_needles} needle(s)", line=line)
        needle = parse_needle(rest[pos])
        if needle is None:
            raise KnitoutParseError(
                f"{op}: {rest[pos]!r} is not a needle (expected f/b/fs/bs + integer)", line=line
            )
        needles.append(needle)
        pos += 1
    carriers = tuple(rest[pos:])
    if carrier_rule == "none" and carriers:
        raise KnitoutParseError(f"{op} takes no carriers (got {' '.join(carriers)!r})", line=line)
    if carrier_rule == "some" and not carriers:
        raise KnitoutParseError(f"{op} needs at least one carrier", line=line)
    for c in carriers:
        if parse_needle(c) is not None or c in ("+", "-"):
            raise KnitoutParseError(
                f"{op}: unexpected {c!r} where a carrier name belongs", line=line
            )
    return Operation(
        line, op, direction=direction, needles=tuple(needles), carriers=carriers, tabs=tabs
    )


def parse_knitout(text: str) -> KnitoutProgram:
    """Parse knitout text.

    Parameters
    ----------
    text : str
        The whole file. CRLF line endings are accepted (and flagged on the result).

    Returns
    -------
    KnitoutProgram
        Headers and operations with 1-based line numbers.

    Raises
    ------
    KnitoutParseError
        For binary input, a missing/bad magic line, or a malformed instruction (with its line).

    Examples
    --------
    >>> prog = parse_knitout(";!knitout-2\\n;;Carriers: 1 2 3\\nknit + f1 3 ; a comment\\n")
    >>> prog.operations[0].line, str(prog.operations[0])
    (3, 'knit + f1 3')
    """
    if not isinstance(text, str):
        raise KnitoutParseError(f"knitout text must be str, got {type(text).__name__}")
    if "\x00" in text:
        raise KnitoutParseError(
            "input looks binary (contains NUL bytes); knitout is a text file "
            "(a .dat file must be converted back first)"
        )
    crlf = "\r\n" in text
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    if not lines:
        raise KnitoutParseError("empty input; knitout must start with ';!knitout-2'", line=1)
    lines = [ln[:-1] if ln.endswith("\r") else ln for ln in lines]
    bad = next((i for i, ln in enumerate(lines) if _has_control(ln)), None)
    if bad is not None:
        raise KnitoutParseError(
            "control characters in the text; is this a binary file?", line=bad + 1
        )
    m = _MAGIC_RE.match(lines[0].rstrip())
    if m is None:
        raise KnitoutParseError(
            f"first line must be the magic line ';!knitout-2', got {lines[0][:40]!r}", line=1
        )
    version = int(m.group(1))
    headers: list[tuple[str, str, int]] = []
    i = 1
    while i < len(lines):
        hm = _HEADER_RE.match(lines[i])
        if hm is None:
            break
        headers.append((hm.group(1), hm.group(2).strip(), i + 1))
        i += 1
    ops: list[Operation] = []
    for j in range(i, len(lines)):
        body = lines[j].split(";", 1)[0]
        if not body.strip():
            continue
        ops.append(_parse_operation(body, j + 1))
    return KnitoutProgram(
        version=version,
        headers=tuple(headers),
        operations=tuple(ops),
        n_lines=len(lines),
        crlf=crlf,
    )


_CONTROL = re.compile(r"[\x00-\x08\x0b\x0c\x0e-\x1f\x7f]")


def _has_control(line: str) -> bool:
    return _CONTROL.search(line) is not None
