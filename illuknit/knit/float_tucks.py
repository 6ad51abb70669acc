"""Short floats: tuck long floats onto free back-bed needles (a machine knitter's float catch).

A *float* is the yarn between two consecutive loops of one carrier. Stranded colourwork floats
across other colours' runs, and a carrier whose colour region moves between courses floats from
its last loop to its next one; anything longer than ``MachineSpec.float_limit`` snags. Machine
knitters cut such floats with *tucks on the back bed*: the floating yarn is tucked onto empty
back needles at intervals, which holds it against the fabric's technical back.

:func:`tuck_long_floats` does this on a finished step list (any scheduler's). For every float
longer than the limit it finds the carriage pass that lays the yarn across the gap -- the pass
that makes the far loop when the carrier travels towards it, or else the carrier's previous pass
on its way out to its parking needle -- and adds tucks on back needles inside the gap, at most
``limit`` needles apart, choosing needles whose back bed is empty at that moment and that the
pass does not otherwise use. Right after that pass one transfer pass moves those tuck loops onto
the front needles (``xfer b n f n``), where the next stitch on the needle knits through them: the
tuck is caught into the fabric and sits behind the face stitch, and no loop is left on the back
bed for another carrier's float to cross in front of. Each pass that tucks therefore costs one
transfer pass.

A float the pass that lays it cannot reach (a racked pass, no free needle in a stretch longer
than the limit) stays long; :func:`tuck_long_floats` reports it, and the caller decides whether
that is an error. Where to tuck is planned by :class:`~illuknit.knit.tuck_planning.TuckPlan`;
this module walks the steps, applies the plan and measures what stays long.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from illuknit.knit.ir import (
    ActionKind,
    Bed,
    CarrierAction,
    Op,
    Opcode,
    Pass,
    PassKind,
    Role,
    Step,
    flip,
)
from illuknit.knit.tuck_planning import LOOP_OPS, Solo, TuckPlan, knit_pass
from illuknit.knitout.floats import is_long_float

if TYPE_CHECKING:
    from illuknit.knit.stitches import StitchPattern

__all__ = ["LongFloat", "measure_long_floats", "tuck_long_floats"]


@dataclass(frozen=True)
class LongFloat:
    """A float still too long: ``carrier`` crosses ``length`` needle slots before ``step``.

    ``step`` indexes the steps the float was measured on (the tucked program's); ``place``,
    when given, names where it is instead of ``course`` (e.g. ``"the cast-on"``)."""

    step: int
    carrier: str
    from_needle: int
    to_needle: int
    course: int | None
    place: str | None = None

    @property
    def length(self) -> int:
        return abs(self.to_needle - self.from_needle) - 1

    def where(self, stitches: StitchPattern) -> str:
        """The course the float is at, named as ``stitches`` names it, or ``place``, or the
        bind-off."""
        if self.course is not None:
            return stitches.course_name(self.course)
        return self.place or "the bind-off"


def tuck_long_floats(
    steps: Sequence[Step],
    *,
    limit: int,
    left: int,
    right: int,
    alone: bool = False,
    entries: Mapping[str, int] | None = None,
) -> tuple[list[Step], list[LongFloat]]:
    """Cut every float longer than ``limit`` with back-bed tucks (see the module docstring).

    Parameters
    ----------
    steps : sequence of Pass or CarrierAction
        A complete schedule's steps.
    limit : int
        Longest allowed float, in needles crossed.
    left, right : int
        The fabric's needles; tucks go only there.
    alone : bool
        Where a plated pass cannot tuck a float, let the floating yarn tuck alone in a pass of
        its own right before (a knit pass and a transfer pass more); False keeps those floats.
    entries : mapping of str to int, optional
        Carriers whose yarn already hangs from a loop when the steps start (a machine without
        an inserting hook brings its yarns in before the piece): the needle of that loop. The
        float from there to the carrier's first stitch is tucked like any other, in the
        carrier's first pass (it starts beyond that needle, where the yarn came in).

    Returns
    -------
    steps : list of Pass or CarrierAction
        With tucks added and one transfer pass after each pass that tucks.
    long : list of LongFloat
        Floats still longer than ``limit``.
    """
    passes = list(steps)
    entries = dict(entries or {})
    plan = TuckPlan.for_steps(
        passes, limit=limit, left=left, right=right, alone=alone, entries=entries
    )
    # carrier -> (needle of its last loop, index of the pass that made it, index of its last
    # pass); -1: before the steps (an entry)
    last: dict[str, tuple[int, int, int]] = {c: (n, -1, -1) for c, n in entries.items()}
    for i, step in enumerate(passes):
        if (s := knit_pass(step, last)) is None:
            continue
        for o in s.ops:
            if o.op not in LOOP_OPS:
                continue
            for c in s.carriers:
                got = last.get(c)
                if got is not None and is_long_float(abs(o.needle - got[0]) - 1, limit):
                    plan.plan(i, c, o.needle, got)
                last[c] = (o.needle, i, i)
        for c in s.carriers:
            prev = last.get(c)
            if prev is not None:
                last[c] = (prev[0], prev[1], i)
    out = _apply(passes, plan.adds, plan.solo, plan.clear)
    # One yarn's tucks may cut another's float too (a plated pass tucks every yarn): what stays
    # long is measured on the result, loop to loop, as the checker's simulator measures it.
    return out, measure_long_floats(out, limit=limit, entries=entries)


def measure_long_floats(
    steps: Sequence[Step], *, limit: int, entries: Mapping[str, int] | None = None
) -> list[LongFloat]:
    """Every float longer than ``limit`` in ``steps``: from a carrier's loop to its next one.

    Needle slots as the machine sees them (a back needle at racking ``r`` sits at slot
    ``needle + floor(r)``); a carrier taken out (``out``/``outhook``) starts afresh; a carrier
    in ``entries`` starts from the loop its yarn hangs from there.
    """
    long: list[LongFloat] = []
    last: dict[str, int] = dict(entries or {})
    for i, step in enumerate(steps):
        if (s := knit_pass(step, last)) is None:
            continue
        shift = math.floor(s.racking)
        for o in s.ops:
            if o.op not in LOOP_OPS:
                continue
            slot = o.needle + (shift if o.bed is Bed.BACK else 0)
            for c in s.carriers:
                got = last.get(c)
                if got is not None and is_long_float(abs(slot - got) - 1, limit):
                    long.append(LongFloat(i, c, got, slot, s.course))
                last[c] = slot
    return long


def _apply(
    passes: list[Step],
    adds: dict[int, set[int]],
    solo: dict[int, list[Solo]],
    clear: dict[int, set[int]],
) -> list[Step]:
    """The steps with the planned tucks (see :class:`~illuknit.knit.tuck_planning.TuckPlan`)
    and a transfer pass after each pass that tucks."""
    out: list[Step] = []
    pending: Pass | None = None
    for i, s in enumerate(passes):
        release = isinstance(s, CarrierAction) and s.action is ActionKind.RELEASEHOOK
        if pending is not None and not release:
            # (After a hook release that follows the tucking pass: the machine releases the hook
            # on a pass running the hook's way, which a transfer in between would upset.)
            out.append(pending)
            pending = None
        alone: set[int] = set()
        for carrier, picks, back_to in solo.get(i, []):
            assert isinstance(s, Pass) and s.direction is not None
            d = s.direction
            trail: tuple[Op, ...] = ()
            if back_to is not None:
                # Back beside the last loop, then tuck towards the pass's first needle and stop
                # just beyond it, behind the carriage for the pass.
                d = "+" if s.ops[0].needle > back_to else "-"
                step = 1 if d == "+" else -1
                out.append(
                    Pass(
                        PassKind.KNIT,
                        (Op(Opcode.MISS, Bed.FRONT, back_to + step),),
                        flip(d),
                        (carrier,),
                        0.0,
                        Role.ANCHOR,
                        s.course,
                    )
                )
                trail = (Op(Opcode.MISS, Bed.FRONT, s.ops[0].needle + step),)
            sign = 1 if d == "+" else -1
            tucks_op = tuple(Op(Opcode.TUCK, Bed.BACK, t) for t in sorted(picks, key=sign.__mul__))
            out.append(
                Pass(
                    PassKind.KNIT,
                    tucks_op + trail,
                    d,
                    (carrier,),
                    0.0,
                    Role.FLOAT_AVOIDANCE,
                    s.course,
                )
            )
            alone |= picks
        tucks = adds.get(i, set())
        if not isinstance(s, Pass) or not (tucks or alone):
            out.append(s)
            continue
        purls = sorted(clear.get(i, set()))
        if purls:
            out.append(_xfers([(t, Bed.BACK, Bed.FRONT) for t in purls], s.course))
        sign = 1 if s.direction == "+" else -1
        ops = [*s.ops, *(Op(Opcode.TUCK, Bed.BACK, t) for t in tucks)]
        # Back and front of one needle are one slot at racking 0: order by needle, and a tuck
        # lands between the pass's own operations (its needles were excluded when choosing).
        ops.sort(key=lambda o: sign * o.needle)
        out.append(replace(s, ops=tuple(ops)))
        pending = _xfers(
            sorted(
                [
                    *((t, Bed.BACK, Bed.FRONT) for t in tucks | alone),
                    *((t, Bed.FRONT, Bed.BACK) for t in purls),
                ]
            ),
            s.course,
        )
    if pending is not None:
        out.append(pending)
    return out


def _xfers(moves: list[tuple[int, Bed, Bed]], course: int | None) -> Pass:
    """One transfer pass at racking 0: ``(needle, from bed, to bed)`` each."""
    ops = tuple(Op(Opcode.XFER, frm, n, to, n) for n, frm, to in moves)
    return Pass(PassKind.XFER, ops, None, (), 0.0, Role.FLOAT_AVOIDANCE, course)
