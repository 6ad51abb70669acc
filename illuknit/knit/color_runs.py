"""Colour runs per course, and which carrier knits each: stranded or intarsia.

First stage of the mixed-colourwork scheduler (paper 7.2-7.3). A *run* is a maximal interval of
wales of one yarn in one course. Every run is knit by a carrier threaded with its yarn; the
question is how many carriers a yarn needs in a course:

* **stranded**: one carrier knits several runs of its yarn in one pass and is carried (floats)
  across the wales between them, behind the other colours' stitches;
* **intarsia**: a run gets its own carrier, which stays anchored where it last knit.

A carriage pass carries one carrier set, so every carrier used in a course costs at least one
pass: fewest passes means fewest carriers per course. The only reason to give a yarn a second
carrier is a float longer than ``MachineSpec.float_limit``, so the runs of a yarn are grouped
greedily from left to right and a new group (a new carrier) starts exactly where the gap to the
previous run exceeds the limit. That greedy grouping is optimal: every group must avoid the long
gaps, and interleaving groups only lengthens floats. When a course would need more carriers than
the machine has, the limit is strict only on request (``strict=True`` raises); by default the
shortest gaps of the yarns short of carriers are bridged by longer floats until the carriers
suffice, and those floats are tucked later (:mod:`illuknit.knit.float_tucks`).

Carriers belong to one yarn for the whole piece (a carrier is threaded once). When a yarn needs
more groups in a course than it has carriers, a free carrier of the machine is threaded with it
-- but one free carrier is kept for every yarn that first appears in a later course, so a yarn's
second carrier never leaves a later yarn without one; groups are matched to the yarn's carriers
nearest first, so an intarsia carrier keeps knitting the region where it is anchored. A pattern
with more yarns than carriers, or (with ``strict=True``) a course short of carriers, is named in
a :class:`~illuknit.core.errors.CarrierShortageError`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from itertools import pairwise
from types import MappingProxyType

import numpy as np
from numpy.typing import ArrayLike

from illuknit.core.errors import (
    CarrierShortageError,
    OptionError,
    PatternValidationError,
    SchedulingError,
)

__all__ = ["ColorPlan", "CoursePlan", "Segment", "color_runs", "plan_color_runs"]

Run = tuple[int, int]


@dataclass(frozen=True)
class Segment:
    """The work of one carrier in one course: runs of one yarn, left to right.

    Parameters
    ----------
    carrier : str
        Carrier name.
    yarn : int
        Yarn index of every stitch of the runs.
    runs : tuple of (int, int)
        Inclusive wale intervals ``(lo, hi)``, ascending and disjoint; the gaps between them are
        floats of at most the float limit.
    """

    carrier: str
    yarn: int
    runs: tuple[Run, ...]

    def __post_init__(self) -> None:
        if not self.runs:
            raise SchedulingError("a segment needs at least one run")
        prev = -2
        for lo, hi in self.runs:
            if lo > hi or lo <= prev + 1:
                raise SchedulingError(f"segment runs must be ascending and disjoint: {self.runs}")
            prev = hi

    @property
    def lo(self) -> int:
        return self.runs[0][0]

    @property
    def hi(self) -> int:
        return self.runs[-1][1]

    @property
    def wales(self) -> list[int]:
        """Every wale knit by the segment, ascending."""
        return [w for lo, hi in self.runs for w in range(lo, hi + 1)]

    @property
    def longest_float(self) -> int:
        """Most wales crossed between two runs (0 for a single run)."""
        return max((b[0] - a[1] - 1 for a, b in pairwise(self.runs)), default=0)


@dataclass(frozen=True)
class CoursePlan:
    """Segments of one course, ordered by their leftmost wale."""

    course: int
    segments: tuple[Segment, ...]


@dataclass(frozen=True, eq=False)
class ColorPlan:
    """Which carrier knits which runs, for every course.

    Parameters
    ----------
    courses : tuple of CoursePlan
        One per course, in knitting order.
    carrier_of_yarn : mapping of int to tuple of str
        Carriers threaded with each yarn, in the order they were first needed.
    float_limit : int
        The limit the runs were grouped with.
    """

    courses: tuple[CoursePlan, ...]
    carrier_of_yarn: Mapping[int, tuple[str, ...]]
    float_limit: int

    def __post_init__(self) -> None:
        object.__setattr__(
            self,
            "carrier_of_yarn",
            MappingProxyType({int(k): tuple(v) for k, v in self.carrier_of_yarn.items()}),
        )

    @property
    def carriers(self) -> tuple[str, ...]:
        """Every carrier the plan uses."""
        return tuple(c for cs in self.carrier_of_yarn.values() for c in cs)

    @property
    def stranded_segments(self) -> int:
        """Segments that float across other colours (more than one run)."""
        return sum(len(s.runs) > 1 for cp in self.courses for s in cp.segments)


def color_runs(row: ArrayLike) -> list[tuple[int, int, int]]:
    """Maximal runs of equal values in a 1-D row: ``(lo, hi, value)`` with ``hi`` inclusive.

    Examples
    --------
    >>> color_runs([0, 0, 1, 0])
    [(0, 1, 0), (2, 2, 1), (3, 3, 0)]
    """
    r = np.asarray(row)
    if r.ndim != 1 or r.size == 0:
        raise PatternValidationError(f"`row` must be a non-empty 1-D array, got shape {r.shape}")
    starts = np.flatnonzero(np.r_[True, r[1:] != r[:-1]])
    ends = np.r_[starts[1:] - 1, r.size - 1]
    return [(int(a), int(b), int(r[a])) for a, b in zip(starts, ends, strict=True)]


def _group_runs(runs: Sequence[Run], float_limit: int) -> list[tuple[Run, ...]]:
    groups: list[list[Run]] = []
    for run in runs:
        if groups and run[0] - groups[-1][-1][1] - 1 <= float_limit:
            groups[-1].append(run)
        else:
            groups.append([run])
    return [tuple(g) for g in groups]


def _deficit(groups: Mapping[int, Sequence[object]], own: Mapping[int, int], free: int) -> int:
    """Carriers missing to give every group its own carrier; yarn ``v`` already has ``own[v]``."""
    return sum(max(0, len(g) - own.get(v, 0)) for v, g in groups.items()) - free


def _fit_carriers(
    groups: dict[int, list[tuple[Run, ...]]], own: Mapping[int, int], free: int
) -> dict[int, list[tuple[Run, ...]]]:
    """Merge groups across their shortest gaps until the machine's carriers suffice.

    Each merge lengthens one float beyond the limit (the checker then warns about it) instead
    of failing: the shortest gap of a yarn that needs a new carrier goes first.
    """
    groups = {v: list(g) for v, g in groups.items()}
    while _deficit(groups, own, free) > 0:
        best: tuple[int, int, int] | None = None  # gap, yarn, index
        for v, g in groups.items():
            if len(g) - own.get(v, 0) <= 0:
                continue
            for i in range(len(g) - 1):
                gap = g[i + 1][0][0] - g[i][-1][1] - 1
                if best is None or gap < best[0]:
                    best = (gap, v, i)
        if best is None:  # only one group per yarn left: more yarns than carriers
            break
        _, v, i = best
        g = groups[v]
        g[i : i + 2] = [g[i] + g[i + 1]]
    return groups


def plan_color_runs(
    yarn: ArrayLike,
    *,
    carriers: Sequence[str],
    float_limit: int,
    strict: bool = False,
    course_names: Sequence[str] | None = None,
) -> ColorPlan:
    """Group every course's colour runs into carrier segments and assign carriers.

    Parameters
    ----------
    yarn : array_like of shape (C, W), int
        Yarn index per stitch, course 0 knitted first.
    carriers : sequence of str
        The machine's carriers, in the order they are handed out.
    float_limit : int
        Longest float (wales crossed between two runs of one carrier); >= 1.
    strict : bool
        When a course would need more carriers than the machine has, raise (True) or lengthen
        the shortest floats beyond the limit until the carriers suffice (False, the default;
        the knitout checker then warns about those floats).
    course_names : sequence of str, optional
        How to name course ``c`` in errors (e.g. ``"course 12 (pattern row 3)"``).

    Returns
    -------
    ColorPlan

    Raises
    ------
    CarrierShortageError
        If a course needs more carriers at once than the machine has (with ``strict``), or
        more yarns than there are carriers.
    OptionError
        For a float limit below 1 or no carriers.
    PatternValidationError
        For a malformed grid.
    """
    y = np.asarray(yarn)
    if y.ndim != 2 or y.size == 0:
        raise PatternValidationError(
            f"`yarn` must be a non-empty (C, W) array, got shape {y.shape}"
        )
    if (
        isinstance(float_limit, bool)
        or not isinstance(float_limit, (int, np.integer))
        or float_limit < 1
    ):
        raise OptionError(
            f"`float_limit` must be an integer >= 1 (wales a yarn may float across), got {float_limit!r}"
        )
    pool = [str(c) for c in carriers]
    if not pool:
        raise OptionError("`carriers` must not be empty")
    free = list(pool)
    of_yarn: dict[int, list[str]] = {}
    anchor: dict[str, float] = {}
    plans: list[CoursePlan] = []
    first_course = {int(v): int(np.argmax((y == v).any(axis=1))) for v in np.unique(y)}
    _check_yarn_count(y, first_course, pool, int(float_limit), course_names)
    for c in range(y.shape[0]):
        by_yarn: dict[int, list[Run]] = {}
        for lo, hi, v in color_runs(y[c]):
            by_yarn.setdefault(v, []).append((lo, hi))
        groups = {v: _group_runs(rs, int(float_limit)) for v, rs in by_yarn.items()}
        owned = {v: len(cs) for v, cs in of_yarn.items()}
        # A carrier stays with its yarn for the whole piece: keep one free for every yarn that
        # first appears in a later course, so that no yarn's extra (intarsia) carrier starves it.
        later = sum(1 for v, fc in first_course.items() if fc > c and v not in of_yarn)
        spare = max(0, len(free) - later)
        if not strict:
            groups = _fit_carriers(groups, owned, spare)
        _check_carriers(c, groups, owned, spare, pool, float_limit, course_names)
        segments = _assign_carriers(groups, of_yarn, anchor, free)
        segments.sort(key=lambda s: s.lo)
        plans.append(CoursePlan(c, tuple(segments)))
    return ColorPlan(
        courses=tuple(plans),
        carrier_of_yarn={v: tuple(cs) for v, cs in of_yarn.items()},
        float_limit=int(float_limit),
    )


def _check_carriers(
    c: int,
    groups: dict[int, list[tuple[Run, ...]]],
    owned: dict[int, int],
    spare: int,
    pool: list[str],
    float_limit: int,
    course_names: Sequence[str] | None,
) -> None:
    """Raise :class:`CarrierShortageError` when course ``c``'s segments need more carriers than
    its yarns own plus the ``spare`` ones, or more than the machine has.

    The messages name what a user can change on the command line.
    """
    name = course_names[c] if course_names is not None else f"course {c}"
    need = sum(len(g) for g in groups.values())
    if need > len(pool):
        detail = ", ".join(f"yarn {v}: {len(g)}" for v, g in sorted(groups.items()))
        raise CarrierShortageError(
            f"{name} needs {need} carriers at once for its colour runs ({detail}) but the "
            f"machine has {len(pool)}; use fewer yarns (--colors / --yarns), fewer separate "
            "colour regions per row (a smoothed picture), or a wider float limit "
            f"(illuknit knit --float-limit N, now {float_limit})",
            course=c,
            needed=need,
            available=len(pool),
        )
    if _deficit(groups, owned, spare) > 0:
        short = sorted(v for v, g in groups.items() if len(g) > owned.get(v, 0))
        raise CarrierShortageError(
            f"{name} needs another carrier for yarn {short[0]} to keep its floats within "
            f"{float_limit} needles, but every one of the machine's {len(pool)} carriers is "
            "threaded with another yarn or kept for a yarn that comes later (a carrier keeps "
            "its yarn for the whole piece); let the long floats be tucked (leave out "
            "--strict-floats), use fewer yarns (--colors / --yarns), or a wider float limit "
            f"(illuknit knit --float-limit N, now {float_limit})",
            course=c,
            needed=len(pool) + 1,
            available=len(pool),
        )


def _check_yarn_count(
    y: np.ndarray,
    first_course: dict[int, int],
    pool: list[str],
    float_limit: int,
    course_names: Sequence[str] | None,
) -> None:
    """Raise :class:`CarrierShortageError` when the pattern has more yarns than carriers (a
    carrier is threaded with one yarn for the whole piece): at the first course that has more
    yarns than carriers at once, else where the first yarn too many comes in."""
    if len(first_course) <= len(pool):
        return
    order = sorted(first_course, key=lambda v: (first_course[v], v))
    arrival = first_course[order[len(pool)]]
    for c in range(arrival + 1):
        if len(np.unique(y[c])) > len(pool):
            runs: dict[int, list[Run]] = {}
            for lo, hi, v in color_runs(y[c]):
                runs.setdefault(v, []).append((lo, hi))
            groups = {v: [tuple(rs)] for v, rs in runs.items()}
            _check_carriers(c, groups, {}, 0, pool, float_limit, course_names)
    name = course_names[arrival] if course_names is not None else f"course {arrival}"
    raise CarrierShortageError(
        f"the pattern uses {len(first_course)} yarns but the machine has {len(pool)} carriers "
        f"for them (a carrier keeps its yarn for the whole piece); {name} brings in yarn "
        f"{order[len(pool)]}, one more than there are carriers: use at most {len(pool)} yarns "
        "(--colors / --yarns)",
        course=arrival,
        needed=len(first_course),
        available=len(pool),
    )


def _assign_carriers(
    groups: dict[int, list[tuple[Run, ...]]],
    of_yarn: dict[int, list[str]],
    anchor: dict[str, float],
    free: list[str],
) -> list[Segment]:
    """A carrier for each segment: the nearest anchored one of its yarn, else a free one.

    Updates ``of_yarn`` (carriers of each yarn), ``anchor`` (each carrier's last centre) and
    ``free`` in place; returns the course's segments, by yarn.
    """
    segments: list[Segment] = []
    for v in sorted(groups):
        own = of_yarn.setdefault(v, [])
        unused = list(own)
        for g in groups[v]:
            centre = (g[0][0] + g[-1][1]) / 2
            if unused:
                # Nearest anchored carrier of this yarn: an intarsia carrier keeps its region.
                car = min(unused, key=lambda k: (abs(anchor[k] - centre), own.index(k)))
                unused.remove(car)
            else:
                car = free.pop(0)
                own.append(car)
            anchor[car] = centre
            segments.append(Segment(car, int(v), g))
    return segments
