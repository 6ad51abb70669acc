"""Lowering: a logical illusion pattern -> a grid of stitches in knitting order.

Each logical unit becomes 2 x 2 stitches (paper 4.1):

* a **flat** unit is two courses of knits in its two wales;
* a **bump** (raised unit) is a knit course followed by a purl course in its two wales -- "a knit
  with a purl child" -- so bumps lie in the garter direction, the one the paper found tallest;
* a **split bump** (a raised unit whose ``LogicalPattern.upper`` differs from its ``yarn``) knits
  its first (knit) course in ``yarn`` and its second (purl) course in ``upper``: the yarn changes
  inside the bump, between the knit loop and the purl loop pulled through it;
* a **tall bump** (``tall_bumps=True``) adds yarn to every raised unit: each purl of a bump is
  preceded by a tuck on its own needle (the back needle, holding the bump's knit loop), which the
  purl then knits through (:attr:`StitchPattern.tuck_first`). A tuck and a knit on one needle
  cannot share a carriage pass, so each course with tall bumps costs one more pass per carrier.

Course/row mapping (fixed project-wide): the machine knits from the bottom edge of the piece up,
so knitting course ``c`` belongs to pattern row ``N - 1 - c // 2``; within a unit, course
``2 * (N - 1 - i)`` is the unit's first (knit) course and ``2 * (N - 1 - i) + 1`` its second
(knit for flats, purl for bumps). Wale ``w`` belongs to pattern column ``w // 2``; wale 0 is the
left edge seen from the technical face (the front bed), so it sits on the leftmost needle.

Every stitch carries its unit's yarn (in the second course of a split bump, its ``upper`` yarn).
The stitch pattern also records how it starts and ends on the machine (``cast_on_courses`` plain courses after a tuck cast-on, then a chain bind-off), which the
scheduler turns into passes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from illuknit.core.errors import PatternValidationError, SchedulingError
from illuknit.core.machine import DEFAULT_MACHINE, MachineSpec
from illuknit.core.pattern import LogicalPattern, Yarn
from illuknit.knit.ir import course_row

__all__ = ["KNIT", "PURL", "StitchPattern", "lower_to_stitches"]

#: Stitch kinds in :attr:`StitchPattern.kind`: a knit is made on the front bed, a purl on the back.
KNIT = 0
PURL = 1

BindOff = Literal["chain"]


def _readonly(a: NDArray[Any]) -> NDArray[Any]:
    a = np.array(a, copy=True)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class StitchPattern:
    """Stitches in knitting order: course 0 is knitted first (the bottom edge of the piece).

    Parameters
    ----------
    kind : ndarray of shape (C, W), uint8
        :data:`KNIT` or :data:`PURL` per stitch.
    yarn : ndarray of shape (C, W), int16
        Yarn index (into ``yarns``) of each stitch.
    yarns : tuple of Yarn
        The palette.
    gauge : float
        Needles per inch the stitches are meant for (sets the physical size).
    course_aspect : float
        Course height / stitch width, for the physical height estimate.
    cast_on_courses : int
        Plain knit courses, in the yarn of course 0, after the tuck cast-on and before course 0.
    bind_off : str
        How the last course is secured: ``"chain"`` (a transfer bind-off across the piece).
    tuck_first : ndarray of shape (C, W), bool, or None
        Stitches preceded by a tuck on their own needle in the stitch's yarn, in a pass of its
        own (tall bumps); None: no such tucks.
    units : (int, int) or None
        Shape (N rows, M columns) of the logical pattern the stitches were lowered from; None
        for stitches made directly. Course ``c`` belongs to pattern row
        :func:`~illuknit.knit.ir.course_row` ``(c, N)``.
    meta : mapping
        Provenance (the logical pattern's own ``meta``, under ``"source"``).
    """

    kind: NDArray[np.uint8]
    yarn: NDArray[np.int16]
    yarns: tuple[Yarn, ...]
    gauge: float = DEFAULT_MACHINE.gauge
    course_aspect: float = DEFAULT_MACHINE.course_aspect
    cast_on_courses: int = 2
    bind_off: BindOff = "chain"
    units: tuple[int, int] | None = None
    meta: Any = field(default_factory=dict)
    tuck_first: NDArray[np.bool_] | None = None

    def __post_init__(self) -> None:
        kind = np.asarray(self.kind)
        yarn = np.asarray(self.yarn)
        if kind.ndim != 2 or kind.size == 0:
            raise PatternValidationError(
                f"`kind` must be a non-empty (C, W) array, got shape {kind.shape}"
            )
        if yarn.shape != kind.shape:
            raise PatternValidationError(f"`yarn` must have shape {kind.shape}, got {yarn.shape}")
        if not np.isin(kind, (KNIT, PURL)).all():
            raise PatternValidationError("`kind` must hold only KNIT (0) or PURL (1)")
        yarns = tuple(self.yarns)
        if not yarns:
            raise PatternValidationError("`yarns` must not be empty")
        if yarn.min() < 0 or yarn.max() >= len(yarns):
            raise PatternValidationError(f"yarn indices must lie in 0..{len(yarns) - 1}")
        if not isinstance(self.cast_on_courses, int) or self.cast_on_courses < 0:
            raise PatternValidationError(
                f"`cast_on_courses` must be a non-negative integer, got {self.cast_on_courses!r}"
            )
        if self.bind_off != "chain":
            raise PatternValidationError(f"`bind_off` must be 'chain', got {self.bind_off!r}")
        if not self.gauge > 0 or not self.course_aspect > 0:
            raise PatternValidationError("`gauge` and `course_aspect` must be positive")
        object.__setattr__(self, "kind", _readonly(kind.astype(np.uint8)))
        object.__setattr__(self, "yarn", _readonly(yarn.astype(np.int16)))
        object.__setattr__(self, "yarns", yarns)
        if self.units is not None:
            units = tuple(int(u) for u in self.units)
            if len(units) != 2 or min(units) < 1:
                raise PatternValidationError(
                    f"`units` must be two positive sizes, got {self.units!r}"
                )
            object.__setattr__(self, "units", units)
        object.__setattr__(self, "meta", MappingProxyType(dict(self.meta)))
        if self.tuck_first is not None:
            tf = np.asarray(self.tuck_first)
            if tf.shape != kind.shape or tf.dtype != np.bool_:
                raise PatternValidationError(
                    f"`tuck_first` must be a bool array of shape {kind.shape}, got "
                    f"{tf.dtype} of shape {tf.shape}"
                )
            object.__setattr__(self, "tuck_first", _readonly(tf) if tf.any() else None)

    @property
    def shape(self) -> tuple[int, int]:
        """(courses C, wales W)."""
        return (int(self.kind.shape[0]), int(self.kind.shape[1]))

    @property
    def courses(self) -> int:
        return self.shape[0]

    @property
    def wales(self) -> int:
        return self.shape[1]

    @property
    def size_cm(self) -> tuple[float, float]:
        """Estimated (width, height) of the finished body in cm at this gauge.

        Width is wales x needle pitch; height is courses x pitch x ``course_aspect``. Real fabric
        relaxes differently per yarn and tension: measure a swatch for anything that must fit.
        """
        pitch = 2.54 / self.gauge
        return (self.wales * pitch, self.courses * pitch * self.course_aspect)

    def course_yarns(self, course: int) -> tuple[int, ...]:
        """Distinct yarn indices used in one course, in order of first appearance left to right."""
        row = self.yarn[course]
        _, first = np.unique(row, return_index=True)
        return tuple(int(row[i]) for i in sorted(first))

    def mixed_courses(self) -> NDArray[np.intp]:
        """Indices of courses that use more than one yarn (they need mixed colourwork)."""
        return np.flatnonzero((self.yarn != self.yarn[:, :1]).any(axis=1))

    def used_yarns(self) -> tuple[int, ...]:
        """Yarn indices that occur in the stitches, ascending."""
        return tuple(int(v) for v in np.unique(self.yarn))

    def course_name(self, course: int) -> str:
        """``"course 12 (pattern row 3)"``: how errors name a body course."""
        if self.units is None:
            return f"course {course}"
        return f"course {course} (pattern row {course_row(course, self.units[0])})"

    def __repr__(self) -> str:
        c, w = self.shape
        return f"StitchPattern({w} wales x {c} courses, purls={int(self.kind.sum())})"


def lower_to_stitches(
    pattern: LogicalPattern,
    *,
    machine: MachineSpec = DEFAULT_MACHINE,
    cast_on_courses: int = 2,
    tall_bumps: bool = False,
) -> StitchPattern:
    """Lower a logical pattern to stitches: each unit -> 2 x 2 stitches, bottom row knitted first.

    Parameters
    ----------
    pattern : LogicalPattern
        N x M units.
    machine : MachineSpec
        Gauge and bed width; the pattern must fit on the bed (2 M wales plus parking room).
    cast_on_courses : int
        Plain courses between the cast-on and the first pattern course.
    tall_bumps : bool
        Precede every purl of a bump by a tuck on its needle (tall bumps, see the module
        docstring); False keeps the paper's plain bumps.

    Returns
    -------
    StitchPattern
        ``kind`` and ``yarn`` of shape (2 N, 2 M).

    Raises
    ------
    SchedulingError
        If 2 M wales do not fit on ``machine.needles`` needles.

    Examples
    --------
    >>> import numpy as np
    >>> from illuknit.core.pattern import LogicalPattern, Yarn
    >>> p = LogicalPattern(np.array([[0], [1]]), np.array([[True], [False]]),
    ...                    (Yarn("a", (0, 0, 0)), Yarn("b", (255, 255, 255))))
    >>> s = lower_to_stitches(p)
    >>> s.kind.tolist()   # course 0 = bottom row (flat), courses 2-3 = top row (bump)
    [[0, 0], [0, 0], [0, 0], [1, 1]]
    """
    if not isinstance(pattern, LogicalPattern):
        raise PatternValidationError(
            f"`pattern` must be a LogicalPattern, got {type(pattern).__name__}"
        )
    n, m = pattern.shape
    wales = 2 * m
    if wales > machine.max_fabric_width:
        raise SchedulingError(
            f"pattern is {m} units = {wales} stitches wide but {machine.bed_text} holds at "
            f"most {machine.max_fabric_width} (use a narrower pattern or a wider --machine-width)"
        )
    # Bottom row first; each unit row -> two courses, each unit column -> two wales.
    yarn_rows = np.repeat(np.repeat(pattern.yarn[::-1], 2, axis=0), 2, axis=1)
    raised = np.repeat(pattern.raised[::-1], 2, axis=1)
    kind = np.zeros((2 * n, wales), dtype=np.uint8)
    kind[1::2] = np.where(raised, PURL, KNIT)
    if pattern.upper is not None:
        # A raised unit's second course is knit in its upper yarn (split bumps).
        yarn_rows[1::2] = np.repeat(pattern.upper[::-1], 2, axis=1)
    tuck_first = None
    if tall_bumps:
        tuck_first = np.zeros(kind.shape, dtype=bool)
        tuck_first[1::2] = raised
    return StitchPattern(
        kind=kind,
        yarn=yarn_rows,
        yarns=pattern.yarns,
        gauge=machine.gauge,
        course_aspect=machine.course_aspect,
        cast_on_courses=cast_on_courses,
        bind_off="chain",
        units=(n, m),
        meta={"source": dict(pattern.meta)},
        tuck_first=tuck_first,
    )
