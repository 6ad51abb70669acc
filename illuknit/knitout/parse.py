"""Strict knitout parser: text -> :class:`KnitoutProgram`.

The first stage of the checker. It reads knitout text (knitout-2 as the CMU SWG converter accepts
it, see ``docs/checker.md``) into a frozen IR: the magic line's version, the comment header
(``;;Name: value`` lines right after line 1) and one :class:`Operation` per instruction, each with
its 1-based line number, into the IR of :mod:`illuknit.knitout.program` (which this module
re-exports). Whole-line comments are kept with their lines (so a program ``knit_pattern`` wrote
formats back to the same text), trailing comments and blank lines are dropped.

Only *syntax* is judged here: a malformed line (unknown opcode, wrong number of arguments, a
needle or direction that does not parse, binary data) raises :class:`KnitoutParseError` with the
line number. Everything that parses but breaks a machine rule (carrier not in the header, a
racking of 0.5, tab separators the SWG converter refuses) is left to the later stages, which report
it as a finding together with every other problem of the file.
"""

from __future__ import annotations

import functools
import math
import re

from illuknit.core.errors import KnitoutParseError
from illuknit.knitout.program import (
    BEDS,
    Direction,
    KnitoutProgram,
    Needle,
    Opcode,
    Operation,
    make_needle,
)

__all__ = [
    "BEDS",
    "KnitoutProgram",
    "Needle",
    "Operation",
    "parse_knitout",
    "parse_needle",
]

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
STITCH_OPS = frozenset({Opcode.KNIT, Opcode.TUCK, Opcode.SPLIT, Opcode.MISS})
#: opcodes that manage carriers
CARRIER_OPS = frozenset({Opcode.IN, Opcode.INHOOK, Opcode.RELEASEHOOK, Opcode.OUT, Opcode.OUTHOOK})


def parse_needle(token: str) -> Needle | None:
    """Parse ``f12``/``b-3``/``fs4``; None when the token is not a needle."""
    m = _NEEDLE_RE.match(token)
    if m is None:
        return None
    return make_needle(m.group(1), int(m.group(2)))


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
        line,
        op,
        direction=None if direction is None else Direction(direction),
        needles=tuple(needles),
        carriers=carriers,
        tabs=tabs,
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
    comments: list[tuple[int, str]] = []
    for j in range(i, len(lines)):
        body = lines[j].split(";", 1)[0]
        if not body.strip():
            if lines[j].startswith(";"):
                comments.append((j + 1, lines[j]))
            continue
        ops.append(_parse_operation(body, j + 1))
    return KnitoutProgram(
        version=version,
        headers=tuple(headers),
        operations=tuple(ops),
        n_lines=len(lines),
        crlf=crlf,
        comments=tuple(comments),
    )


_CONTROL = re.compile(r"[\x00-\x08\x0b\x0c\x0e-\x1f\x7f]")


def _has_control(line: str) -> bool:
    return _CONTROL.search(line) is not None
