"""Scheduling: stitches -> carriage passes, for patterns with one colour per course.

The :class:`Schedule` IR is a sequence of *steps*: carriage passes (:class:`Pass`) and carrier
actions (:class:`CarrierAction`: ``inhook``/``releasehook``/``outhook``/``in``/``out``). A pass has
one kind (``knit`` -- knits, tucks, misses and splits with yarn --, ``xfer`` or ``drop``), one
direction (knit passes), one carrier tuple (plated stitches list the primary carrier first), one
racking, and its needle operations in execution order. The IR is deliberately more general than
this scheduler needs: the mixed-colourwork scheduler emits passes over part of the bed, plated
carrier tuples, float-avoidance transfer passes and anchoring stitches in the same form, and the
knitout writer and the time model work on any schedule.

:func:`schedule_courses` handles every course knitted with a single yarn (all single-view
illusions):

* **cast-on**: the first carrier comes in on the yarn-inserting hook; alternating tucks leftward
  from the right edge (running on to park left of the fabric), the remaining needles tucked
  rightward (ending with a ``miss`` on the edge needle, so the next course starts with the
  carrier behind the carriage), then ``cast_on_courses`` plain courses; the hook lets go of the
  yarn end after the first of them;
* **each course**: one transfer pass first if any loop must change bed (front -> back where a purl
  follows a knit in its wale, back -> front where a knit follows a purl; both directions merge
  into one pass at racking 0), then, for tall bumps (``StitchPattern.tuck_first``), one pass of
  tucks on the needles about to be purled, then one knit pass in which purls (back bed) are knit together
  with their front neighbours. The carrier starts from the side where it is parked, so every
  carrier alternates direction and no kickback pass is ever needed; the pass ends with a ``miss``
  ``park_distance`` needles beyond the fabric edge, which parks the carrier out of the way of the
  others at no extra pass. A carrier enters with ``inhook`` at its first course (leftward from the
  right edge, as the hook requires) and the hook is released right after that pass; a carrier
  leaves with ``outhook`` right after its last course;
* **bind-off**: every loop back on the front bed, then a chain bind-off from the side where the
  last carrier is parked: knit a needle, move its loop onto the next needle (front -> back at
  racking 0, back -> front at racking +/-1), knit that one; directions alternate and a ``miss``
  places the carrier so that each stitch is made from the correct side. A short tail of knits on
  the last needle, ``outhook``, and the last loop is dropped.

**Lower bound.** Each course needs at least one knit pass (its stitches depend on the previous
course's loops, and one pass runs one way), and a course in which some loop changes bed needs a
transfer pass between the two knit passes (transfers never share a pass with stitches). So
``sum over courses of 1 + [some loop changes bed] + [some stitch is tucked first]`` bounds the
body (a tuck and the knit through it cannot share a pass either); the cast-on and bind-off
recipes are counted at their own length. This scheduler meets the bound exactly; the mixed
scheduler reports against the same definition extended with per-course carrier sets.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np

from illuknit.core.errors import (
    MachineRuleError,
    MixedColorworkError,
    OptionError,
    PatternValidationError,
    SchedulingError,
)
from illuknit.core.machine import DEFAULT_MACHINE, MachineSpec
from illuknit.core.pattern import Yarn
from illuknit.knit.edges import bind_off_steps, cast_on_steps
from illuknit.knit.float_tucks import LongFloat
from illuknit.knit.ir import (
    ActionKind,
    Bed,
    CarrierAction,
    Direction,
    Op,
    Opcode,
    Pass,
    PassKind,
    Role,
    Step,
)
from illuknit.knit.stitches import StitchPattern

__all__ = [
    "CarrierAction",
    "MixedReport",
    "Op",
    "Pass",
    "Schedule",
    "ScheduleStats",
    "count_kickbacks",
    "schedule_courses",
]


@dataclass(frozen=True)
class ScheduleStats:
    """Pass counts of a schedule.

    :attr:`Schedule.stats` counts the schedule's own passes: ``passes`` are its carriage passes;
    ``hook_passes`` the extra empty passes the SWG backend adds for each ``releasehook`` and
    ``outhook`` (counted apart); ``kickbacks`` the times a carrier runs two passes in the same
    direction, each of which costs the SWG backend an extra pass.
    :func:`illuknit.knitting.carriage.machine_stats` counts what the machine runs instead: there
    ``passes`` is every machine pass (hook passes, carrier moves and kickbacks included),
    ``kickbacks`` the passes the machine adds to move carriers out of the way, and
    ``schedule_passes`` the schedule's own count. ``ratio`` is ``passes / lower_bound``.
    """

    passes: int
    knit_passes: int
    transfer_passes: int
    miss_passes: int
    cast_on_passes: int
    bind_off_passes: int
    body_passes: int
    body_lower_bound: int
    lower_bound: int
    hook_passes: int
    kickbacks: int = 0
    schedule_passes: int | None = None

    @property
    def ratio(self) -> float:
        return self.passes / self.lower_bound if self.lower_bound else 1.0

    def as_dict(self) -> dict[str, Any]:
        d = {k: getattr(self, k) for k in self.__dataclass_fields__}
        d["ratio"] = round(self.ratio, 4)
        return d


@dataclass(frozen=True)
class MixedReport:
    """What the mixed-colourwork scheduler did: its switches and what they added."""

    float_avoidance: bool
    catching: bool
    path_planning: str
    catch_every: int
    float_limit: int
    strict_floats: bool
    plated_stitches: int
    float_avoidance_transfers: int
    carriers: int
    stranded_segments: int
    join_method: str = "plate"
    tuck_joins: int = 0

    def as_dict(self) -> dict[str, Any]:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


@dataclass(frozen=True, eq=False)
class Schedule:
    """Carriage passes and carrier actions for one piece, in execution order.

    Parameters
    ----------
    steps : tuple of Pass or CarrierAction
    machine : MachineSpec
    yarns : tuple of Yarn
        The palette of the stitch pattern.
    carrier_of_yarn : mapping of int to tuple of str
        Carrier(s) knitting each used yarn (more than one for a yarn knit by several carriers).
    left : int
        Needle of wale 0.
    wales, courses : int
        Size of the body in stitches.
    lower_bound : int
        Lower bound on ``len(passes)`` (see the module docstring).
    body_lower_bound : int
        The same bound for the body courses alone.
    units : (int, int) or None
        Shape of the logical pattern (for course -> pattern row, :func:`~illuknit.knit.ir.course_row`).
    scheduler : str
        Which scheduler made it: ``"one-colour-per-course"`` or ``"mixed-colourwork"``.
    mixed : MixedReport or None
        What the mixed-colourwork scheduler did (None for the one-colour scheduler).
    long_floats : tuple of LongFloat
        Floats longer than the machine's float limit that the scheduler could not shorten; in a
        :class:`~illuknit.knitting.pipeline.KnitResult`, those of the written program, measured as
        the checker measures them (:mod:`illuknit.knitout.floats`).
    """

    steps: tuple[Step, ...]
    machine: MachineSpec
    yarns: tuple[Yarn, ...]
    carrier_of_yarn: Mapping[int, tuple[str, ...]]
    left: int
    wales: int
    courses: int
    lower_bound: int
    body_lower_bound: int
    units: tuple[int, int] | None = None
    scheduler: str = "one-colour-per-course"
    mixed: MixedReport | None = None
    long_floats: tuple[LongFloat, ...] = ()

    def __post_init__(self) -> None:
        m = self.machine
        carriers = set(m.carriers)
        for i, step in enumerate(self.steps):
            if isinstance(step, CarrierAction):
                bad = [c for c in step.carriers if c not in carriers]
                if bad:
                    raise MachineRuleError(
                        f"step {i}: carrier {bad[0]!r} is not on the machine", carrier=bad[0]
                    )
                continue
            if not isinstance(step, Pass):
                raise SchedulingError(f"step {i} is neither a Pass nor a CarrierAction")
            if abs(step.racking) > m.max_racking:
                raise MachineRuleError(
                    f"step {i}: racking {step.racking} exceeds +/-{m.max_racking}",
                    racking=step.racking,
                )
            lo, hi = step.needle_span
            if lo < 0 or hi >= m.needles:
                raise MachineRuleError(
                    f"step {i}: needles {lo}..{hi} outside the bed 0..{m.needles - 1}",
                    needle=str(lo if lo < 0 else hi),
                )
            bad = [c for c in step.carriers if c not in carriers]
            if bad:
                raise MachineRuleError(
                    f"step {i}: carrier {bad[0]!r} is not on the machine", carrier=bad[0]
                )
            if step.kind == "xfer" or any(o.op == "split" for o in step.ops):
                for o in step.ops:
                    if o.op not in ("xfer", "split"):
                        continue
                    if o.to_bed is None or o.to_needle is None or o.to_bed == o.bed:
                        raise MachineRuleError(
                            f"step {i}: {o.op} {o.bed}{o.needle} needs a target on the other bed",
                            needle=f"{o.bed}{o.needle}",
                        )
                    front, back = (
                        (o.needle, o.to_needle) if o.bed == "f" else (o.to_needle, o.needle)
                    )
                    # Knitout alignment: front needle k + R faces back needle k.
                    if front - back != step.racking:
                        raise MachineRuleError(
                            f"step {i}: {o.op} f{front} <-> b{back} is not aligned at racking {step.racking}",
                            needle=f"{o.bed}{o.needle}",
                            racking=step.racking,
                        )
        object.__setattr__(self, "steps", tuple(self.steps))
        object.__setattr__(
            self,
            "carrier_of_yarn",
            MappingProxyType({int(k): tuple(v) for k, v in self.carrier_of_yarn.items()}),
        )

    @property
    def passes(self) -> list[Pass]:
        return [s for s in self.steps if isinstance(s, Pass)]

    @property
    def stats(self) -> ScheduleStats:
        ps = self.passes
        acts = [s for s in self.steps if isinstance(s, CarrierAction)]
        return ScheduleStats(
            passes=len(ps),
            knit_passes=sum(p.kind == "knit" and any(o.op != "miss" for o in p.ops) for p in ps),
            transfer_passes=sum(p.kind == "xfer" for p in ps),
            miss_passes=sum(p.kind == "knit" and all(o.op == "miss" for o in p.ops) for p in ps),
            cast_on_passes=sum(p.role in (Role.CAST_ON, Role.PARK) for p in ps),
            bind_off_passes=sum(p.role in (Role.BIND_OFF, Role.TAIL) for p in ps),
            body_passes=sum(
                p.role in (Role.BODY, Role.TRANSFER, Role.FLOAT_AVOIDANCE, Role.ANCHOR) for p in ps
            ),
            body_lower_bound=self.body_lower_bound,
            lower_bound=self.lower_bound,
            hook_passes=sum(a.action in ("releasehook", "outhook", "out") for a in acts),
            kickbacks=count_kickbacks(self.steps),
        )


def count_kickbacks(steps: Sequence[Step]) -> int:
    """Knit passes whose carrier last moved in the same direction (the backend kicks it back first).

    A carrier that goes out (``out``/``outhook``) forgets its direction: it comes back in fresh.
    """
    last: dict[str, str | None] = {}
    n = 0
    for s in steps:
        if isinstance(s, CarrierAction):
            if s.action in ("out", "outhook"):
                for c in s.carriers:
                    last.pop(c, None)
            continue
        if s.kind != "knit":
            continue
        n += any(last.get(c) == s.direction for c in s.carriers)
        for c in s.carriers:
            last[c] = s.direction
    return n


def _knit_ops(needles: Sequence[int], beds: Sequence[str], op: Opcode = Opcode.KNIT) -> list[Op]:
    bed = Bed._value2member_map_  # (Bed(b) is enum's slow call)
    return [Op(op, bed[b], n) for n, b in zip(needles, beds, strict=True)]  # type: ignore[arg-type]


def schedule_courses(
    stitches: StitchPattern,
    *,
    machine: MachineSpec = DEFAULT_MACHINE,
    tail_stitches: int = 4,
) -> Schedule:
    """Schedule a stitch pattern with one yarn per course (see the module docstring).

    Parameters
    ----------
    stitches : StitchPattern
        C courses x W wales; every course must use a single yarn.
    machine : MachineSpec
        Bed width, carriers, parking distance, stitch numbers.
    tail_stitches : int
        Knits on the last needle after the bind-off, so the final loop cannot unravel.

    Returns
    -------
    Schedule

    Raises
    ------
    MixedColorworkError
        If a course uses more than one yarn (the mixed-colourwork scheduler's job).
    SchedulingError
        If the piece is wider than the bed or uses more yarns than the machine has carriers.
    """
    carrier_of = _checked_carriers(stitches, machine=machine, tail_stitches=tail_stitches)
    n_courses, n_wales = stitches.shape
    course_carrier = [carrier_of[int(stitches.yarn[c, 0])] for c in range(n_courses)]
    left = machine.fabric_left
    right = left + n_wales - 1
    park = {"+": right + machine.park_distance, "-": left - machine.park_distance}
    knitter = _CourseKnitter([], list(range(left, right + 1)), park)
    cast_on_fixed = _cast_on(knitter, stitches, course_carrier[0], machine=machine)
    bed, body_bound = _body(knitter, stitches, course_carrier, machine=machine)
    cb = course_carrier[n_courses - 1]
    bind_fixed = _bind_off(
        knitter.steps,
        bed,
        cb,
        knitter.next_dir[cb],
        left,
        right,
        stitch_number=machine.stitch_number,
        tail_stitches=tail_stitches,
    )
    return Schedule(
        steps=tuple(knitter.steps),
        machine=machine,
        yarns=stitches.yarns,
        carrier_of_yarn={y: (c,) for y, c in carrier_of.items()},
        left=left,
        wales=n_wales,
        courses=n_courses,
        lower_bound=cast_on_fixed + body_bound + bind_fixed,
        body_lower_bound=body_bound,
        units=stitches.units,
        scheduler="one-colour-per-course",
    )


@dataclass
class _CourseKnitter:
    """The steps of a one-colour-per-course schedule as they are written, and where each live
    carrier is parked (the direction its next pass must run)."""

    steps: list[Step]
    needles_up: list[int]
    park: dict[str, int]
    next_dir: dict[str, Direction] = field(default_factory=dict)
    #: The carrier whose yarn end the inserting hook holds, until it is released.
    hook_held: str | None = None

    def knit_course(
        self, car: str, beds: Sequence[str], role: Role, course: int | None, sn: int | None
    ) -> None:
        d = self.next_dir.get(car, "-")
        order = self.needles_up if d == "+" else self.needles_up[::-1]
        b = list(beds) if d == "+" else list(beds)[::-1]
        ops = _knit_ops(order, b)
        ops.append(Op(Opcode.MISS, Bed.FRONT, self.park[d]))
        self.steps.append(Pass(PassKind.KNIT, tuple(ops), d, (car,), 0.0, role, course, sn))
        self.next_dir[car] = "-" if d == "+" else "+"

    def tuck_pass(
        self, car: str, tucked: np.ndarray, beds: Sequence[str], course: int, machine: MachineSpec
    ) -> None:
        """A pass of ``car`` tucking the needles ``tucked`` marks (on their stitches' beds).

        Where the yarn would float further than ``machine.float_limit`` between the carrier's
        last loop (the edge it starts from), its tucks and the far edge (where the knit pass
        through them starts), it also tucks front needles this course knits, which the knit
        pass then knits through (so the tuck sits behind a face stitch, as a tuck join does).
        """
        d = self.next_dir.get(car)
        seq = self.needles_up if d != "-" and d is not None else self.needles_up[::-1]
        want = {n for n, t in zip(self.needles_up, tucked, strict=True) if t}
        front = [n for n, b in zip(self.needles_up, beds, strict=True) if b == "f"]
        pos = {n: i for i, n in enumerate(seq)}
        limit = machine.float_limit
        chosen: set[int] = set()
        prev = seq[0] if d is not None else None  # a new yarn starts at its first tuck
        for target in [*(n for n in seq if n in want), seq[-1]]:
            while prev is not None and abs(target - prev) > limit:
                reach = [
                    n for n in front if pos[prev] < pos[n] < pos[target] and abs(n - prev) <= limit
                ]
                if not reach:
                    break
                prev = max(reach, key=lambda n: pos[n])
                chosen.add(prev)
            if target in want:
                chosen.add(target)
                prev = target
        bed = dict(zip(self.needles_up, beds, strict=True))
        d = d or "-"
        ops = [Op(Opcode.TUCK, Bed(bed[n]), n) for n in seq if n in chosen]
        ops.append(Op(Opcode.MISS, Bed.FRONT, self.park[d]))
        sn = machine.stitch_number
        self.steps.append(Pass(PassKind.KNIT, tuple(ops), d, (car,), 0.0, Role.BODY, course, sn))
        self.next_dir[car] = "-" if d == "+" else "+"

    def release_hook(self) -> None:
        if self.hook_held is not None:
            self.steps.append(CarrierAction(ActionKind.RELEASEHOOK, (self.hook_held,)))
            self.hook_held = None


def _cast_on(k: _CourseKnitter, stitches: StitchPattern, c0: str, *, machine: MachineSpec) -> int:
    """The cast-on and the plain cast-on courses; their fixed passes."""
    cast_sn = machine.cast_on_stitch
    k.steps.extend(
        cast_on_steps(
            c0,
            k.needles_up,
            left_end=k.park["-"],
            right_end=k.needles_up[-1],
            hook="held",
            stitch_number=cast_sn,
        )
    )
    k.next_dir[c0] = "-"
    # The hook holds the yarn end through the first full course (it parks left, clear of the hook).
    k.hook_held = c0
    for _ in range(stitches.cast_on_courses):
        k.knit_course(c0, ["f"] * len(k.needles_up), Role.CAST_ON, None, cast_sn)
        k.release_hook()
    return 2 + stitches.cast_on_courses


def _body(
    k: _CourseKnitter,
    stitches: StitchPattern,
    course_carrier: list[str],
    *,
    machine: MachineSpec,
) -> tuple[np.ndarray, int]:
    """The pattern's courses, each after the transfers it needs; the beds that hold the last
    course's loops and the body's lower bound (one pass per course and per transfer course)."""
    n_courses, n_wales = stitches.shape
    left = machine.fabric_left
    last_course = {car: c for c, car in enumerate(course_carrier)}
    bed = np.zeros(n_wales, dtype=np.uint8)  # which bed holds each wale's loop: 0 front, 1 back
    bed_letter = np.array(["f", "b"])
    transfer_courses = 0
    tuck_courses = 0
    for c in range(n_courses):
        need = stitches.kind[c]
        moving = np.flatnonzero(need != bed)
        if moving.size:
            transfer_courses += 1
            ops = tuple(
                Op(Opcode.XFER, Bed.BACK, left + int(w), Bed.FRONT, left + int(w))
                if bed[w]
                else Op(Opcode.XFER, Bed.FRONT, left + int(w), Bed.BACK, left + int(w))
                for w in moving
            )
            k.steps.append(Pass(PassKind.XFER, ops, None, (), 0.0, Role.TRANSFER, c))
            bed = need.copy()
        car = course_carrier[c]
        if car not in k.next_dir:
            k.steps.append(CarrierAction(ActionKind.INHOOK, (car,)))
            k.hook_held = car
        if stitches.tuck_first is not None and stitches.tuck_first[c].any():
            # Tall bumps: the tucks go in a pass of their own (a needle is used once a pass);
            # the course's knit pass then runs back and knits through them.
            k.tuck_pass(car, stitches.tuck_first[c], bed_letter[need].tolist(), c, machine)
            k.release_hook()
            tuck_courses += 1
        k.knit_course(car, bed_letter[need].tolist(), Role.BODY, c, machine.stitch_number)
        # Release at once: while the hook holds the yarn nothing may touch the right edge.
        k.release_hook()
        if last_course[car] == c and c != n_courses - 1:
            k.steps.append(CarrierAction(ActionKind.OUTHOOK, (car,)))
            del k.next_dir[car]
    return bed, n_courses + transfer_courses + tuck_courses


def _checked_carriers(
    stitches: object, *, machine: MachineSpec, tail_stitches: int
) -> dict[int, str]:
    """Check :func:`schedule_courses`'s input; returns the carrier of each used yarn."""
    if not isinstance(stitches, StitchPattern):
        raise PatternValidationError(
            f"`stitches` must be a StitchPattern, got {type(stitches).__name__}"
        )
    if stitches.wales < 2:
        raise SchedulingError(f"the cast-on needs at least 2 wales, got {stitches.wales}")
    if tail_stitches < 1:
        raise OptionError(f"`tail_stitches` must be >= 1, got {tail_stitches}")
    n_wales = stitches.shape[1]
    machine.check_width(n_wales)
    mixed = stitches.mixed_courses()
    if mixed.size:
        c = int(mixed[0])
        raise MixedColorworkError(
            f"{mixed.size} course(s) change colour, first {stitches.course_name(c)} uses yarns "
            f"{list(stitches.course_yarns(c))}; this needs the mixed-colourwork scheduler "
            f"(one colour per course is all the current scheduler knits)"
        )
    used = stitches.used_yarns()
    if len(used) > len(machine.carriers):
        raise SchedulingError(
            f"pattern uses {len(used)} yarns but the {machine.label} has {len(machine.carriers)} carriers"
        )
    return {y: machine.carriers[i] for i, y in enumerate(used)}


def _bind_off(
    steps: list[Step],
    bed: np.ndarray,
    carrier: str,
    direction: Direction,
    left: int,
    right: int,
    *,
    stitch_number: int | None,
    tail_stitches: int,
) -> int:
    """Append the bind-off (back loops to the front, then the chain); returns its passes."""
    bind_fixed = 0
    back = np.flatnonzero(bed)
    if back.size:
        steps.append(
            Pass(
                PassKind.XFER,
                tuple(
                    Op(Opcode.XFER, Bed.BACK, left + int(w), Bed.FRONT, left + int(w)) for w in back
                ),
                None,
                (),
                0.0,
                Role.BIND_OFF,
            )
        )
        bind_fixed += 1
    chain = bind_off_steps(
        carrier, direction, left, right, stitch_number=stitch_number, tail_stitches=tail_stitches
    )
    steps.extend(chain)
    bind_fixed += sum(isinstance(x, Pass) for x in chain)
    return bind_fixed
