"""What a hand knitter needs beyond the chart: written rows, technique advice and materials.

* :func:`written_row` writes one row as a knitter reads it, runs of one stitch in one yarn
  compressed (``k2, p4``) and the longest repeat folded (``*k2, p4; rep from * to last 2 sts,
  k2``), with the row's stitch count.
* :func:`row_colourwork` counts, per row, the colour changes, the colour blocks and the longest
  float a stranded knitter would carry (a yarn crossing the back of the stitches it skips);
  :func:`hand_advice` turns those numbers into advice a knitter would follow: stocking stitch
  stripes when each row has one yarn; stranded knitting, catching floats every
  :data:`CATCH_EVERY` stitches, when rows use two yarns; intarsia only when the blocks are large
  (:data:`MIN_INTARSIA_BLOCK` stitches and at most :data:`MAX_INTARSIA_BLOCKS` blocks a row);
  and when none fits, it says so with the numbers and what would make it knittable (fewer yarns,
  a simplified design, a machine).
* :func:`yarn_estimate` estimates each yarn's length and weight from its stitch count and gauge.
* :func:`with_border` frames a pattern in garter stitch against curling: selvedge stitches at
  both sides and garter ridges at the cast-on and bind-off edges, as the hand documents knit it.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from itertools import groupby

import numpy as np

from illuknit.core.arguments import check_int
from illuknit.core.gauge import Gauge
from illuknit.core.pattern import LogicalPattern
from illuknit.design.hand_cost import (
    COLOUR_STITCHES_PER_MINUTE,
    MAX_FLOAT,
    MAX_HAND_BLOCKS,
    MINUTES_PER_CHANGE,
    PLAIN_STITCHES_PER_MINUTE,
    hand_hours,
)

__all__ = [
    "CATCH_EVERY",
    "MAX_INTARSIA_BLOCKS",
    "MIN_INTARSIA_BLOCK",
    "HandAdvice",
    "HandVerdict",
    "RowColourwork",
    "YarnEstimate",
    "compress_repeats",
    "hand_advice",
    "hand_verdict",
    "intarsia_bobbins",
    "row_colourwork",
    "with_border",
    "written_row",
    "yarn_estimate",
]

#: Stranded knitting: catch (trap) a float behind the work every this many stitches.
CATCH_EVERY = 5
#: Intarsia is sensible when every block of a row is at least this many stitches wide ...
MIN_INTARSIA_BLOCK = 6
#: ... and a row has at most this many blocks (bobbins hanging at once).
MAX_INTARSIA_BLOCKS = 8
#: Stranded knitting carries at most this many yarns in a row comfortably.
MAX_STRANDED_YARNS = 2


def compress_repeats(tokens: list[tuple[str, int]]) -> str:
    """Tokens ``(text, stitches)`` in working order, as a knitter writes them, with the longest
    repeat folded: ``*k2, p4; rep from * to last 2 sts, k2``.

    >>> compress_repeats([("k2", 2), ("p4", 4)] * 3 + [("k2", 2)])
    '*k2, p4; rep from * to last 2 sts, k2'
    >>> compress_repeats([("k1", 1), ("p1", 1)] * 4)
    '*k1, p1; rep from * to end'
    >>> compress_repeats([("k3", 3), ("p2", 2)])
    'k3, p2'
    """
    n = len(tokens)
    best: tuple[int, int, int, int] | None = None  # (tokens saved, start, period, repeats)
    for period in range(1, min(8, n // 2) + 1):
        for start in range(0, n - 2 * period + 1):
            unit = tokens[start : start + period]
            reps = 1
            while tokens[start + reps * period : start + (reps + 1) * period] == unit:
                reps += 1
            saved = (reps - 1) * period
            if reps >= 2 and saved >= 2 and (best is None or saved > best[0]):
                best = (saved, start, period, reps)
    if best is None:
        return ", ".join(t for t, _ in tokens)
    _, start, period, reps = best
    prefix = tokens[:start]
    unit = tokens[start : start + period]
    suffix = tokens[start + reps * period :]
    parts = [t for t, _ in prefix]
    body = "*" + ", ".join(t for t, _ in unit) + "; rep from *"
    if suffix:
        last = sum(s for _, s in suffix)
        body += f" to last {last} st{'s' if last > 1 else ''}, " + ", ".join(t for t, _ in suffix)
    else:
        body += " to end"
    return ", ".join([*parts, body])


def written_row(worked: list[tuple[str, int]], names: list[str]) -> str:
    """One row as written instructions: ``with black, *k2, p4; rep from * ... (120 sts)``.

    ``worked`` is ``(stitch, yarn)`` in working order (:meth:`illuknit.outputs.chart.HandRow.worked`).
    """
    yarns = {y for _, y in worked}
    single = len(yarns) == 1
    tokens = []
    for (op, y), grp in groupby(worked):
        count = len(list(grp))
        text = f"{op}{count}" if single else f"{op}{count} {names[y]}"
        tokens.append((text, count))
    total = len(worked)
    if single:
        ops = {op for op, _ in worked}
        name = names[next(iter(yarns))]
        if ops == {"k"}:
            return f"with {name}, knit across ({total} sts)."
        if ops == {"p"}:
            return f"with {name}, purl across ({total} sts)."
        return f"with {name}, {compress_repeats(tokens)} ({total} sts)."
    return f"{compress_repeats(tokens)} ({total} sts)."


@dataclass(frozen=True)
class RowColourwork:
    """Colourwork of one hand-knitting row (stitches in chart order).

    Attributes
    ----------
    number : int
        Row number from the cast-on edge.
    yarns : int
        Distinct yarns in the row.
    changes : int
        Colour changes along the row.
    blocks : int
        Runs of one yarn (``changes + 1``).
    shortest_block : int
        Narrowest run of one yarn, in stitches.
    longest_float : int
        Most stitches a yarn skips between two of its stitches in the row (0 for one yarn).
    """

    number: int
    yarns: int
    changes: int
    blocks: int
    shortest_block: int
    longest_float: int

    @property
    def technique(self) -> str:
        """``"plain"`` (one yarn), ``"intarsia"`` (large blocks: a bobbin each, no floats),
        ``"stranded"`` (two yarns, floats caught every :data:`CATCH_EVERY` stitches) or
        ``"not-sensible"`` (more yarns than can be stranded, in blocks too small for intarsia).

        In that order: intarsia for large blocks; stranded for 2 yarns whose floats are short
        (:data:`~illuknit.design.hand_cost.MAX_FLOAT`); then intarsia for a row of few blocks
        (:data:`~illuknit.design.hand_cost.MAX_HAND_BLOCKS`) even where one is narrow, rather
        than a long float carried for a few stitches -- so every row
        :attr:`~illuknit.design.hand_cost.HandRow.knittable` gets a technique that works it
        without long floats; then stranded with long floats caught."""
        if self.yarns == 1:
            return "plain"
        if self.shortest_block >= MIN_INTARSIA_BLOCK and self.blocks <= MAX_INTARSIA_BLOCKS:
            return "intarsia"
        short = self.longest_float <= MAX_FLOAT
        if self.yarns <= MAX_STRANDED_YARNS and short:
            return "stranded"
        if self.blocks <= MAX_HAND_BLOCKS:
            return "intarsia"
        if self.yarns <= MAX_STRANDED_YARNS:
            return "stranded"
        return "not-sensible"

    def note(self) -> str:
        """What the written row says about its colourwork ("" for one yarn)."""
        t = self.technique
        changes = f"{self.changes} colour change{'s' if self.changes > 1 else ''}"
        if t == "plain":
            return ""
        if t == "intarsia":
            return f"intarsia, {self.blocks} blocks, {changes}"
        catch = f", catch every {CATCH_EVERY}" if self.longest_float > CATCH_EVERY else ""
        if t == "stranded":
            return f"stranded, {changes}, longest float {self.longest_float} sts{catch}"
        return (
            f"{self.yarns} yarns, {changes}, blocks from {self.shortest_block} sts, "
            f"longest float {self.longest_float} sts"
        )


def row_colourwork(pattern: LogicalPattern) -> list[RowColourwork]:
    """Per hand-knitting row (2 per unit row, from the cast-on edge): yarns, changes, floats.

    Both rows of a unit row have the same colours, so the numbers repeat in pairs, except where
    split bumps knit a unit's second row in another yarn (``LogicalPattern.upper``).
    """
    n, _ = pattern.shape
    out = []
    for k in range(2 * n):
        yarn = np.repeat((pattern.yarn if k % 2 == 0 else pattern.upper_yarn)[n - 1 - k // 2], 2)
        runs = [(int(y), len(list(g))) for y, g in groupby(yarn.tolist())]
        longest = 0
        last_end: dict[int, int] = {}
        pos = 0
        for y, length in runs:
            if y in last_end:
                longest = max(longest, pos - last_end[y])
            pos += length
            last_end[y] = pos
        out.append(
            RowColourwork(
                number=k + 1,
                yarns=len({y for y, _ in runs}),
                changes=len(runs) - 1,
                blocks=len(runs),
                shortest_block=min(length for _, length in runs),
                longest_float=longest,
            )
        )
    return out


#: The widest border :func:`with_border` makes, in ridge units (40 stitches at each side, 40
#: rows at each end): wider is a second piece, not a border.
MAX_BORDER_UNITS = 20


def with_border(pattern: LogicalPattern, units: int) -> LogicalPattern:
    """``pattern`` framed by a garter border ``units`` ridge units wide (each 2 stitches x 2
    rows): ``2 * units`` garter stitches at each side (knit on both sides: raised units) in the
    yarns of the edge stitches beside them, so the border adds no colour change, and ``units``
    garter ridges (``2 * units`` rows) below the first row and above the last, in the yarn most
    of that edge row is in. It adds ``4 * units`` stitches and ``4 * units`` rows. The border
    is for the hand documents (written rows, chart, sizes); the design itself is unchanged.

    >>> from illuknit.core.pattern import parse_yarns
    >>> p = LogicalPattern(np.array([[0, 1], [1, 1]]), np.zeros((2, 2), bool),
    ...                    parse_yarns("black,white"))
    >>> b = with_border(p, 1)
    >>> b.shape, b.yarn.tolist(), int(b.raised.sum())
    ((4, 4), [[0, 0, 0, 0], [0, 0, 1, 1], [1, 1, 1, 1], [1, 1, 1, 1]], 12)
    """
    check_int(units, "border", min=0, max=MAX_BORDER_UNITS)
    if units == 0:
        return pattern
    sides = ((0, 0), (units, units))
    yarn = np.pad(pattern.yarn, sides, mode="edge")
    upper = np.pad(pattern.upper_yarn, sides, mode="edge")
    raised = np.pad(pattern.raised, sides, constant_values=True)
    top = np.bincount(upper[0]).argmax()  # the bind-off edge follows the top row's WS row
    bottom = np.bincount(yarn[-1]).argmax()  # the cast-on edge: row 1
    rows = np.full((units, yarn.shape[1]), top, dtype=yarn.dtype)
    below = np.full((units, yarn.shape[1]), bottom, dtype=yarn.dtype)
    flat = np.ones((units, yarn.shape[1]), bool)
    return LogicalPattern(
        np.vstack([rows, yarn, below]).astype(pattern.yarn.dtype),
        np.vstack([flat, raised, flat]),
        pattern.yarns,
        upper=np.vstack([rows, upper, below]).astype(pattern.yarn.dtype),
    )


def intarsia_bobbins(
    pattern: LogicalPattern, rows: tuple[RowColourwork, ...] | None = None
) -> dict[int, int]:
    """Bobbins to wind per yarn index for the intarsia rows: the most blocks that yarn has in
    one intarsia row (a block a bobbin).

    >>> from illuknit.core.pattern import parse_yarns
    >>> p = LogicalPattern(np.array([[0] * 4 + [1] * 4 + [0] * 4]), np.zeros((1, 12), bool),
    ...                    parse_yarns("black,white"))
    >>> intarsia_bobbins(p)
    {0: 2, 1: 1}
    """
    rows = tuple(row_colourwork(pattern)) if rows is None else rows
    n, _ = pattern.shape
    out: dict[int, int] = {}
    for r in rows:
        if r.technique != "intarsia":
            continue
        k = r.number - 1
        yarn = (pattern.yarn if k % 2 == 0 else pattern.upper_yarn)[n - 1 - k // 2]
        blocks = Counter(int(y) for y, _ in groupby(yarn.tolist()))
        for y, count in blocks.items():
            out[y] = max(out.get(y, 0), count)
    return out


@dataclass(frozen=True)
class HandAdvice:
    """How to knit a pattern by hand, and whether it is sensible to.

    Attributes
    ----------
    technique : {"stripes", "stranded", "intarsia", "not-sensible"}
    knittable : bool
        False when no hand technique fits the rows sensibly.
    lines : tuple of str
        The advice as sentences, numbers included.
    rows : tuple of RowColourwork
    """

    technique: str
    knittable: bool
    lines: tuple[str, ...]
    rows: tuple[RowColourwork, ...]


def hand_advice(pattern: LogicalPattern) -> HandAdvice:
    """Advice on knitting ``pattern`` by hand, from the colourwork of its rows
    (:attr:`RowColourwork.technique` per row)."""
    rows = tuple(row_colourwork(pattern))
    multi = [r for r in rows if r.yarns > 1]
    if not multi:
        return HandAdvice(
            "stripes",
            True,
            (
                "Every row is worked in one yarn: change yarn at the start of a row, carrying "
                "the unused yarn up the side (twist it with the working yarn every other row).",
            ),
            rows,
        )
    by = Counter(r.technique for r in rows)
    most_yarns = max(r.yarns for r in rows)
    most_changes = max(r.changes for r in rows)
    stranded = [r for r in multi if r.technique == "stranded"]
    longest = max((r.longest_float for r in stranded), default=0)
    smallest = min(r.shortest_block for r in multi)
    lines = [
        f"{len(multi)} of {len(rows)} rows change colour: up to {most_yarns} yarns and "
        f"{most_changes} colour changes in a row, blocks as narrow as {smallest} stitches."
    ]
    if by["intarsia"]:
        bobbins = intarsia_bobbins(pattern, rows)
        wind = ", ".join(f"{pattern.yarns[y].name} {k}" for y, k in sorted(bobbins.items()))
        lines.append(
            f"{by['intarsia']} rows have few colour blocks (at most {MAX_INTARSIA_BLOCKS} a "
            f"row, each at least {MIN_INTARSIA_BLOCK} stitches wide, or at most "
            f"{MAX_HAND_BLOCKS} a row): work them in intarsia, each block "
            "from its own ball or bobbin, twisting the yarns at every colour change so the "
            f"blocks stay joined. No yarn is carried across the back. Bobbins to wind: {wind}."
        )
    if by["stranded"]:
        lines.append(
            f"{by['stranded']} rows have small blocks of 2 yarns: work them in stranded "
            "knitting, one yarn in each hand, carrying the yarn not in use loosely across the "
            + (
                f"wrong side; its floats reach {longest} stitches, so catch (trap) it with the "
                f"working yarn every {CATCH_EVERY} stitches."
                if longest > CATCH_EVERY
                else f"wrong side; its floats are at most {longest} stitches, short enough "
                "to leave uncaught."
            )
        )
    if not by["not-sensible"]:
        technique = "intarsia" if by["intarsia"] >= by["stranded"] else "stranded"
        lines.append("Each colour row's note below says which, with its numbers.")
        return HandAdvice(technique, True, tuple(lines), rows)
    bad = [r for r in rows if r.technique == "not-sensible"]
    lines += [
        f"This design is not sensibly knitted by hand: {len(bad)} rows (the first is row "
        f"{bad[0].number}) carry {max(r.yarns for r in bad)} yarns in blocks as narrow as "
        f"{min(r.shortest_block for r in bad)} stitches and up to {max(r.blocks for r in bad)} "
        f"blocks a row: more than {MAX_STRANDED_YARNS} yarns cannot be stranded, and intarsia "
        f"needs blocks of at least {MIN_INTARSIA_BLOCK} stitches and at most "
        f"{MAX_INTARSIA_BLOCKS} bobbins a row.",
        "To knit it by hand: design it with 2 yarns (stranded knitting then works), simplify "
        "it so the colour blocks are larger (illuknit double --simplify), or knit it on a "
        "machine (illuknit knit).",
    ]
    return HandAdvice("not-sensible", False, tuple(lines), rows)


@dataclass(frozen=True)
class YarnEstimate:
    """Yarn needed for one colour."""

    name: str
    hex: str
    stitches: int
    metres: float
    grams: float

    def describe(self) -> str:
        if not self.stitches:
            return f"{self.name} ({self.hex}): not used in this design"
        return (
            f"{self.name} ({self.hex}): {self.stitches} sts, about {self.metres:.0f} m "
            f"({self.metres * 1.0936:.0f} yd), {self.grams:.0f} g"
        )


#: Yarn used per stitch, in stitch widths: Munden's wale constant of dry-relaxed plain knitting
#: (loop length / stitch width, about 3.8-4.2); the low end, the margin covers the rest.
LOOP_LENGTH_IN_STITCH_WIDTHS = 3.8
#: Metres per 100 g of DK yarn (Craft Yarn Council weight 3: roughly 200-250 m per 100 g).
DK_METRES_PER_100G = 225.0


def yarn_estimate(
    pattern: LogicalPattern,
    gauge: Gauge,
    *,
    margin: float = 0.2,
    metres_per_100g: float = DK_METRES_PER_100G,
    floats: bool = True,
) -> list[YarnEstimate]:
    """Length and weight of each yarn: its stitches x loop length, floats, plus ``margin``.

    Every stitch takes :data:`LOOP_LENGTH_IN_STITCH_WIDTHS` stitch widths of yarn; with
    ``floats`` a stranded yarn also crosses the blocks of other yarns between its own stitches.
    Cast-on, bind-off and tails are covered by ``margin`` (default 20 %).
    """
    counts: Counter[int] = Counter()
    carried: Counter[int] = Counter()
    n, _ = pattern.shape
    for r in range(n):
        for course in (pattern.yarn, pattern.upper_yarn):  # a unit row's two rows
            row = np.repeat(course[r], 2)
            for y, c in zip(*np.unique(row, return_counts=True), strict=True):
                counts[int(y)] += int(c)
                if floats:
                    idx = np.flatnonzero(row == y)
                    carried[int(y)] += int(idx[-1] - idx[0] + 1 - c)
    loop_cm = LOOP_LENGTH_IN_STITCH_WIDTHS * gauge.stitch_cm
    out = []
    for i, y in enumerate(pattern.yarns):
        metres = (counts[i] * loop_cm + carried[i] * gauge.stitch_cm) / 100 * (1 + margin)
        out.append(YarnEstimate(y.name, y.hex, counts[i], metres, metres / metres_per_100g * 100))
    return out


#: A design is for machines only when a row's float exceeds this many stitches (a yarn carried
#: behind that many stitches needs catching all along: slow, and the carried yarn's bulk at the
#: back flattens the ridges the illusion needs, paper section 4.1) ...
MACHINE_ONLY_FLOAT = 24
#: ... or a row changes colour more than this many times.
MACHINE_ONLY_CHANGES = 20


@dataclass(frozen=True)
class HandVerdict:
    """The cover's verdict: estimated hours by hand, the technique and whether hands are
    sensible at all (``machine_only``), with the sentence that says so."""

    hours: float
    technique: str
    machine_only: bool
    text: str


def hand_verdict(pattern: LogicalPattern) -> HandVerdict:
    """Hours of hand knitting estimated from the stitch counts and colour work
    (:func:`~illuknit.design.hand_cost.hand_hours`: rules of thumb), the technique, and whether the design is for
    machines only (:data:`MACHINE_ONLY_FLOAT`, :data:`MACHINE_ONLY_CHANGES`)."""
    advice = hand_advice(pattern)
    hours = hand_hours(pattern)
    floats = max((r.longest_float for r in advice.rows if r.technique == "stranded"), default=0)
    changes = max(r.changes for r in advice.rows)
    coloured = sum(r.yarns > 1 for r in advice.rows)
    machine_only = not advice.knittable or floats > MACHINE_ONLY_FLOAT
    # many changes are slow only where long floats must be caught: a stranded row whose floats
    # are all short is ordinary two-handed colour work however often it changes yarn
    machine_only |= any(
        r.changes > MACHINE_ONLY_CHANGES and r.longest_float > MAX_FLOAT
        for r in advice.rows
        if r.technique != "intarsia"
    )
    rates = (
        f"(an estimate at {PLAIN_STITCHES_PER_MINUTE:g} stitches a minute in one-yarn rows, "
        f"{COLOUR_STITCHES_PER_MINUTE:g} in colour rows and {MINUTES_PER_CHANGE * 60:g} s a "
        "colour change: rules of thumb, not measured)"
    )
    technique = {
        "stripes": "stripes of one yarn a row (illusion knitting)",
        "stranded": "stranded colour work (floats caught behind the work)",
        "intarsia": "intarsia (a ball or bobbin a colour block)",
        "not-sensible": "none fits: rows of 3 or more yarns in blocks too small for intarsia",
    }[advice.technique]
    whole = round(hours)
    said = "under an hour" if whole == 0 else f"about {whole} hour{'s' if whole > 1 else ''}"
    text = f"By hand: {said} {rates}; technique: {technique}."
    if machine_only:
        text += (
            f" This design is for machines only: {coloured} of {len(advice.rows)} rows change "
            f"colour, up to {changes} times a row, with floats up to {floats} stitches. By hand "
            "that is weeks of catching floats, and the carried yarn's bulk at the back flattens "
            "the ridges the illusion needs. Knit it on a machine (illuknit knit), or design it "
            "with fewer colours a row."
        )
    return HandVerdict(hours, advice.technique, machine_only, text)
