"""A knit program's floats against its float limit, placed in the schedule that made it.

:func:`program_float_facts` measures the floats of a lowered program as the checker measures
them (:func:`illuknit.knitout.floats.program_floats`, in :data:`FLOAT_UNIT`), judges them by the
one rule (:func:`~illuknit.knitout.floats.is_long_float`) and places each by provenance: the
operation that ends a float names the schedule step it came from. :func:`~illuknit.knitting.knit_pattern`
reports (and refuses) by it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from illuknit.knit.float_tucks import LongFloat
from illuknit.knit.ir import Pass, Role
from illuknit.knit.schedule import Schedule
from illuknit.knit.stitches import StitchPattern
from illuknit.knitout.program import KnitoutProgram

if TYPE_CHECKING:
    from illuknit.knitout.floats import Float

__all__ = ["FLOAT_UNIT", "FloatFacts", "program_float_facts", "program_long_floats"]


#: The one unit every float figure is in (the checker's, ``docs/knitting.md``, Floats).
FLOAT_UNIT = "needles skipped"


def _skipped(n: int) -> str:
    """``FLOAT_UNIT`` read with ``n``: "1 needle skipped", "20 needles skipped"."""
    return "needle skipped" if n == 1 else FLOAT_UNIT


@dataclass(frozen=True)
class FloatFacts:
    """A program's floats against its float limit, all in needles skipped (:data:`FLOAT_UNIT`:
    the needle slots strictly between two consecutive loops of one carrier, the checker's
    measure, :mod:`illuknit.knitout.floats`).

    Attributes
    ----------
    limit : int
        The float limit: a float of ``limit`` needles skipped is allowed, one longer is not.
    longest : LongFloat or None
        The longest float of the program, placed (None when no float skips a needle).
    at_limit : int
        Floats exactly at the limit (allowed, but as long as a float may be; other tools,
        counting needles spanned or using ``>=``, call these long).
    long : tuple of LongFloat
        Floats over the limit (kept only with ``allow_long_floats``).
    """

    limit: int
    longest: LongFloat | None
    at_limit: int
    long: tuple[LongFloat, ...]

    def text(self, stitches: StitchPattern) -> str:
        """One line (after ``floats:``): the longest float, where it is, and the counts at and over the limit."""
        if self.longest is None:
            return f"no float skips a needle (float limit {self.limit} {FLOAT_UNIT})"
        f = self.longest
        return (
            f"longest {f.length} {_skipped(f.length)} (carrier {f.carrier}, {f.where(stitches)}); "
            f"{self.at_limit} at the float limit of {self.limit}, {len(self.long)} over it"
        )


def program_long_floats(
    program: KnitoutProgram | str, schedule: Schedule, limit: int
) -> tuple[LongFloat, ...]:
    """The floats of ``program`` longer than ``limit``, as the checker measures them
    (:func:`illuknit.knitout.floats.long_floats`), each placed in ``schedule`` (see
    :func:`program_float_facts`)."""
    return program_float_facts(program, schedule, limit).long


def program_float_facts(
    program: KnitoutProgram | str, schedule: Schedule, limit: int
) -> FloatFacts:
    """The floats of ``program`` against ``limit``: the longest, how many sit exactly at the
    limit and the ones over it, measured as the checker measures them
    (:func:`illuknit.knitout.floats.program_floats`: needles skipped) and placed in ``schedule``
    by provenance: the operation that ends a float names the step it came from
    (:attr:`~illuknit.knitout.program.Operation.step`; none: the waste section).

    ``program`` is ``schedule`` lowered (:func:`~illuknit.knit.knitout.lower_to_knitout`). Its
    text is still taken: parsed, with each operation given its step as the lowering would (the
    schedule's operations, one line each, end the program).
    """
    from illuknit.knitout.floats import is_long_float, program_floats

    if isinstance(program, str):
        program = _with_provenance(program, schedule)
    found = program_floats(program)
    if not found:
        return FloatFacts(limit, None, 0, ())
    step_at = {op.line: op.step for op in program.operations}

    def placed(f: Float) -> LongFloat:
        k = step_at[f.line]
        if k is None:
            return LongFloat(-1, f.carrier, f.from_slot, f.to_slot, None, "the waste section")
        step = schedule.steps[k]
        assert isinstance(step, Pass)
        place = "the cast-on" if step.role is Role.CAST_ON else None
        return LongFloat(k, f.carrier, f.from_slot, f.to_slot, step.course, place)

    longest = max(found, key=lambda f: f.length)
    return FloatFacts(
        limit,
        placed(longest),
        sum(f.length == limit for f in found),
        tuple(placed(f) for f in found if is_long_float(f.length, limit)),
    )


def _with_provenance(text: str, schedule: Schedule) -> KnitoutProgram:
    """``text`` parsed, each of the schedule's operations (one line each, at the end of the
    program after anything a machine puts first) given the index of its step."""
    from illuknit.knitout.parse import parse_knitout

    program = parse_knitout(text)
    owner = [
        i
        for i, step in enumerate(schedule.steps)
        for _ in (step.ops if isinstance(step, Pass) else (step,))
    ]
    ops = list(program.operations)
    made = [k for k, op in enumerate(ops) if op.op in _STEP_OPS]
    for k, i in zip(made[len(made) - len(owner) :], owner, strict=True):
        ops[k] = ops[k].at(ops[k].line, i)
    return replace(program, operations=tuple(ops))


#: Knitout operations written one per line for each operation of a schedule's step.
_STEP_OPS = frozenset(
    {
        "knit",
        "tuck",
        "split",
        "miss",
        "xfer",
        "drop",
        "in",
        "inhook",
        "releasehook",
        "out",
        "outhook",
    }
)
