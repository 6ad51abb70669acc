"""What a pattern costs a hand knitter: its rows as worked, bottom up, and which are knittable.

A hand knitter works the chart row by row from the cast-on edge: every unit row is two knitted
rows (the second in ``LogicalPattern.upper_yarn`` where a split bump changes yarn), every unit
two stitches wide (docs/hand-knitting.md). Per row :func:`hand_rows` counts the yarns, the
colour changes, the colour blocks (runs of one yarn), the longest stranded float (the most
stitches a yarn crosses behind the work between two of its own stitches) and the catches those
floats need (one every :data:`CATCH_EVERY` stitches of a float longer than that).

A row is **knittable by hand** (:attr:`HandRow.knittable`) when it is worked in one yarn, or
stranded with at most :data:`MAX_HAND_YARNS` yarns and floats of at most :data:`MAX_FLOAT`
stitches, or in intarsia with at most :data:`MAX_HAND_BLOCKS` colour blocks (a bobbin each).
:func:`hand_cost` sums a pattern's rows into a :class:`HandCost`; the share of knittable rows
is what a design made for hands is ranked by first (:mod:`illuknit.design.tiles.perception`,
``made_for="hands"``).

>>> import numpy as np
>>> from illuknit.core.pattern import LogicalPattern, Yarn
>>> yarns = (Yarn("dark", (0, 0, 0)), Yarn("cream", (240, 240, 230)))
>>> p = LogicalPattern(np.array([[0, 0, 1, 1, 0, 0]]), np.zeros((1, 6), bool), yarns)
>>> cost = hand_cost(p)
>>> cost.knittable_rows, cost.rows, cost.longest_float, cost.max_changes
(2, 2, 4, 2)
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import groupby
from typing import Any

import numpy as np

from illuknit.core.pattern import LogicalPattern, check_pattern

__all__ = [
    "CATCH_EVERY",
    "COLOUR_STITCHES_PER_MINUTE",
    "MAX_FLOAT",
    "MAX_HAND_BLOCKS",
    "MAX_HAND_YARNS",
    "MINUTES_PER_CHANGE",
    "PLAIN_STITCHES_PER_MINUTE",
    "HandCost",
    "HandRow",
    "hand_cost",
    "hand_hours",
    "hand_rows",
]

#: A stranded knitter catches (traps) a float behind the work every this many stitches.
CATCH_EVERY = 5
#: The longest float (stitches) a row may carry and still count as knittable stranded.
MAX_FLOAT = 7
#: The most yarns a stranded row may carry (one in each hand).
MAX_HAND_YARNS = 2
#: The most colour blocks (bobbins hanging at once) an intarsia row may have.
MAX_HAND_BLOCKS = 6
#: Assumed hand-knitting speed, stitches a minute, in rows of one yarn: a rule of thumb for an
#: average knitter (20-30 are commonly quoted), not measured by illuknit.
PLAIN_STITCHES_PER_MINUTE = 25.0
#: ... and in rows of two or more yarns (stranded or intarsia): about half as fast.
COLOUR_STITCHES_PER_MINUTE = 12.0
#: Minutes each colour change in a row costs on top (drop, pick up, twist, untangle).
MINUTES_PER_CHANGE = 0.1


@dataclass(frozen=True)
class HandRow:
    """One row as a hand knitter works it.

    Attributes
    ----------
    number : int
        Row number from the cast-on edge (1 first).
    yarns, changes, blocks : int
        Distinct yarns, colour changes along the row and runs of one yarn (``changes + 1``).
    longest_float : int
        The most stitches a yarn crosses behind the work between two of its stitches (0 for
        one yarn).
    catches : int
        The catches the row's floats need, one every :data:`CATCH_EVERY` stitches.
    """

    number: int
    yarns: int
    changes: int
    blocks: int
    longest_float: int
    catches: int

    @property
    def stranded_ok(self) -> bool:
        """Knittable stranded: at most 2 yarns, floats of at most :data:`MAX_FLOAT` stitches."""
        return self.yarns <= MAX_HAND_YARNS and self.longest_float <= MAX_FLOAT

    @property
    def intarsia_ok(self) -> bool:
        """Knittable in intarsia: at most :data:`MAX_HAND_BLOCKS` colour blocks."""
        return self.blocks <= MAX_HAND_BLOCKS

    @property
    def knittable(self) -> bool:
        """One yarn, or knittable stranded, or knittable in intarsia."""
        return self.yarns == 1 or self.stranded_ok or self.intarsia_ok

    @property
    def in_intarsia(self) -> bool:
        """Worked in intarsia: knittable so and not stranded with short floats. Its yarns
        hang in blocks, a bobbin each, so it carries no float however far apart a yarn's
        blocks lie."""
        return self.intarsia_ok and not self.stranded_ok


def _row(number: int, units: np.ndarray) -> HandRow:
    stitches = np.repeat(np.asarray(units), 2).tolist()
    runs = [(int(y), len(list(g))) for y, g in groupby(stitches)]
    longest = catches = pos = 0
    last_end: dict[int, int] = {}
    for y, length in runs:
        if y in last_end:
            gap = pos - last_end[y]
            longest = max(longest, gap)
            catches += (gap - 1) // CATCH_EVERY
        pos += length
        last_end[y] = pos
    return HandRow(number, len(last_end), len(runs) - 1, len(runs), longest, catches)


def hand_rows(pattern: LogicalPattern) -> list[HandRow]:
    """Every row of ``pattern`` as worked by hand, from the cast-on edge (2 per unit row)."""
    pattern = check_pattern(pattern)
    n = pattern.shape[0]
    return [
        _row(k + 1, (pattern.yarn if k % 2 == 0 else pattern.upper_yarn)[n - 1 - k // 2])
        for k in range(2 * n)
    ]


@dataclass(frozen=True)
class HandCost:
    """A pattern's cost to a hand knitter, summed over its rows (:func:`hand_cost`).

    Attributes
    ----------
    rows, knittable_rows : int
        Rows in all, and rows :attr:`HandRow.knittable`.
    colour_rows : int
        Rows with more than one yarn.
    max_changes : int
    mean_changes : float
        Colour changes a row, most and mean over all rows.
    longest_float : int
        The longest float of any row not worked in intarsia (stitches;
        :attr:`HandRow.in_intarsia`).
    catches : int
        Catches all those floats need.
    max_yarns, max_blocks : int
        The most yarns and colour blocks in a row.
    stitches : int
        Stitches a row (two a unit).
    changes : int
        Colour changes in all rows.
    """

    rows: int
    knittable_rows: int
    colour_rows: int
    max_changes: int
    mean_changes: float
    longest_float: int
    catches: int
    max_yarns: int
    max_blocks: int
    stitches: int
    changes: int

    @property
    def knittable_share(self) -> float:
        """The share of rows knittable by hand, in [0, 1]."""
        return self.knittable_rows / self.rows if self.rows else 1.0

    @property
    def hours(self) -> float:
        """Hours of hand knitting estimated from the stitch counts and colour work: rows of one
        yarn at :data:`PLAIN_STITCHES_PER_MINUTE`, rows of more at
        :data:`COLOUR_STITCHES_PER_MINUTE`, and :data:`MINUTES_PER_CHANGE` a colour change
        (rules of thumb, not measured)."""
        plain = self.rows - self.colour_rows
        minutes = (
            plain * self.stitches / PLAIN_STITCHES_PER_MINUTE
            + self.colour_rows * self.stitches / COLOUR_STITCHES_PER_MINUTE
            + self.changes * MINUTES_PER_CHANGE
        )
        return minutes / 60

    def describe(self) -> str:
        """One line: ``rows knittable by hand 228 of 228, longest float 6 sts, ...``."""
        return (
            f"rows knittable by hand {self.knittable_rows} of {self.rows}, longest float "
            f"{self.longest_float} sts ({self.catches} catches), colour changes a row max "
            f"{self.max_changes} / mean {self.mean_changes:.1f}, up to {self.max_yarns} yarns "
            f"and {self.max_blocks} blocks a row"
        )

    def to_json(self) -> dict[str, Any]:
        return {
            "rows": self.rows,
            "knittable_rows": self.knittable_rows,
            "knittable_share": round(self.knittable_share, 4),
            "colour_rows": self.colour_rows,
            "max_changes": self.max_changes,
            "mean_changes": round(self.mean_changes, 3),
            "longest_float": self.longest_float,
            "catches": self.catches,
            "max_yarns": self.max_yarns,
            "max_blocks": self.max_blocks,
            "stitches": self.stitches,
            "changes": self.changes,
            "hours": round(self.hours, 2),
        }


def hand_cost(pattern: LogicalPattern) -> HandCost:
    """The hand knitter's cost of ``pattern`` (:func:`hand_rows` summed)."""
    rows = hand_rows(pattern)
    carried = [r for r in rows if not r.in_intarsia]  # the rows whose yarns float
    return HandCost(
        rows=len(rows),
        knittable_rows=sum(r.knittable for r in rows),
        colour_rows=sum(r.yarns > 1 for r in rows),
        max_changes=max(r.changes for r in rows),
        mean_changes=float(np.mean([r.changes for r in rows])),
        longest_float=max((r.longest_float for r in carried), default=0),
        catches=sum(r.catches for r in carried),
        max_yarns=max(r.yarns for r in rows),
        max_blocks=max(r.blocks for r in rows),
        stitches=2 * pattern.shape[1],
        changes=sum(r.changes for r in rows),
    )


def hand_hours(pattern: LogicalPattern) -> float:
    """Hours of hand knitting estimated from the stitch counts and colour work
    (:attr:`HandCost.hours`: rules of thumb, not measured)."""
    return hand_cost(pattern).hours
