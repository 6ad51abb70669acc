"""Mixed-colourwork scheduler: colour changes and knit/purl anywhere in a course (paper 7.3).

Double-view and head-on illusions change colour inside courses and put purl bumps anywhere; the
one-colour-per-course scheduler (:mod:`illuknit.knit.schedule`) refuses them. This scheduler
combines stranded colourwork and intarsia with the paper's three compiler passes, each in its own
module, and emits the same :class:`~illuknit.knit.schedule.Schedule` IR, so the knitout writer,
the time model and the checker work unchanged::

    StitchPattern -> color_runs.plan_color_runs   carriers per run: stranded / intarsia
                  -> catching.plan_catches          plated stitches at colour changes (Alg. 2)
                  -> path_planning.plan_item        directions, splits, anchoring (Alg. 3)
                  -> float_avoidance                transfers around floats over purls (Alg. 1)
                  -> Schedule

**Cast-on** follows the first course's colours: each carrier of course 0 comes in on the
inserting hook and tuck-casts-on its own wales (alternate needles leftward from its rightmost
wale, a ``miss`` past its leftmost, the others rightward, ``releasehook``; a carrier ending at the
right edge is then parked right of it), so colour regions run to the edge. ``cast_on_courses``
plain courses in course 0's colours follow, scheduled like the body (caught, path-planned).

**Parking.** Every pass ends with its carriers parked just beyond the fabric edge it runs towards
(a trailing ``miss``, ``MachineSpec.park_distance`` needles out), as the one-colour scheduler
does. The SWG backend treats a carrier as possibly anywhere beyond the last needle it moved to
(its stopping distance is unknown) and moves it out of the way before any stitch or transfer on
that side, each move a carriage pass; a carrier parked outside the fabric is never in the way, so
those passes disappear. A carrier whose yarn would then float across purls of its own next pass
first comes back beside its last loop (one move) and is planned from there.

**Each course**: the work items are every carrier's segment (minus its plated stitches) and one
item per plated carrier pair; catching happens on every ``catch_every``-th course (default 2:
once per unit row). Items are ordered for fewest passes -- branch and bound over every order up
to :data:`EXHAUSTIVE_ITEMS` items, a beam search beyond, each order also charged what the next
course's own work would cost from where it leaves the carriers; a carrier's first item is its
own, so it comes in with exactly the set it first uses -- and each is planned into passes by
Algorithm 3. Then the course's transfers are placed: lazily and batched, with float avoidance
(see :mod:`~illuknit.knit.float_avoidance`). Carriers come in with ``inhook`` right before their
first pass (leftward, as the hook needs) and the hook is released right after it; a carrier
leaves with ``outhook`` after its last course. Finally :func:`~illuknit.knit.move_folding.fold_moves` folds each
carrier-placing ``miss`` pass that continues its carrier's previous pass into that pass, and
:func:`~illuknit.knit.float_tucks.tuck_long_floats` tucks floats over the limit onto free back
needles.

**Bind-off**: a chain in one yarn across both beds
(:func:`~illuknit.knit.mixed_edges.zigzag_bind_off_steps`, two passes a wale), started where the
last course ended (the carrier whose last loop is nearest an edge it is parked beyond; the others
go out first).
With catching off each run is bound off on its own instead (tail, then the loop is dropped), so
that nothing the scheduler adds joins the regions.

**Passes and the lower bound.** The lower bound per body course is *the number of distinct
carrier sets that knit in it* (the SWG backend merges only operations with the identical carrier
list, so each set -- each carrier and each plated pair -- needs its own pass) *plus one transfer
pass if some loop changes bed* relative to the previous course (both directions share one pass at
racking 0); the cast-on tucks and the bind-off recipe count at their own length. It counts no
carrier moves, and none is unavoidable: parked carriers are in no pass's way (see
``docs/mixed-colourwork.md``). It is a bound for the given carrier plan, not over all plans. The
passes reported for a program are the machine's (:mod:`illuknit.knitting.carriage`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from illuknit.core.arguments import check_instance
from illuknit.core.errors import LongFloatError, OptionError, PatternValidationError
from illuknit.core.machine import DEFAULT_MACHINE, MachineSpec, resolve_machine
from illuknit.knit.catching import JoinTuck, PlatedStitch, plan_catches, plan_joins
from illuknit.knit.color_runs import ColorPlan, plan_color_runs
from illuknit.knit.course_order import course_items, order_and_plan
from illuknit.knit.float_avoidance import float_crossings, transfers_before
from illuknit.knit.float_tucks import LongFloat, tuck_long_floats
from illuknit.knit.hookless import YarnEntry, fabric_needles, first_directions
from illuknit.knit.ir import Role, Step
from illuknit.knit.mixed_edges import Emitter, bind_off, cast_on
from illuknit.knit.move_folding import fold_moves
from illuknit.knit.options import Catching, KnitOptions
from illuknit.knit.path_planning import Park, WorkItem
from illuknit.knit.schedule import MixedReport, Schedule
from illuknit.knit.stitches import StitchPattern

__all__ = ["long_float_error", "refuses_long_floats", "schedule_mixed"]

#: Knits on the last needle of the bind-off chain (as in
#: :func:`~illuknit.knit.schedule.schedule_courses`).
TAIL_STITCHES = 4


@dataclass(frozen=True, eq=False)
class _Courses:
    """What every course of :func:`schedule_mixed` reads: the plan, stitches and switches."""

    plan: ColorPlan
    kind: np.ndarray  # (courses incl. cast-on, W): KNIT / PURL per stitch
    beds: list[list[str]]  # the same as "f" / "b"
    k0: int  # cast-on courses
    join: str | None  # "tuck", "plate" or None (no catching)
    catch_every: int
    path_planning: str
    float_avoidance: bool
    park: Park
    last_course: dict[str, int]  # carrier -> last course it knits in
    tuck_passes: bool
    tuck_first: np.ndarray | None = None  # (courses incl. cast-on, W): tall-bump tucks
    entry: int | None = None  # where a new yarn hangs without an inserting hook (right edge)


def _knit_course(em: Emitter, ctx: _Courses, c: int) -> int:
    """Emit course ``c`` (joins, ordered passes, transfers); returns its lower bound.

    The course's work items -- every carrier's segment with its tuck joins, one item per
    plated pair -- are ordered and path-planned, then each pass is emitted after the transfers
    it needs (float avoidance), and carriers whose last course this is go out.
    """
    plan, kind, left = ctx.plan, ctx.kind, em.left
    cp = plan.courses[c]
    label = c - ctx.k0 if c >= ctx.k0 else None
    role = Role.BODY if c >= ctx.k0 else Role.CAST_ON
    beds = ctx.beds[c]
    new = frozenset(s.carrier for s in cp.segments if s.carrier not in em.states)
    tucks: list[JoinTuck] = []
    catches: list[PlatedStitch] = []
    if ctx.join is not None and c % ctx.catch_every == 0:
        if ctx.join == "tuck":
            nxt = kind[c + 1] if c + 1 < len(kind) else np.zeros_like(kind[c])
            tucks, catches = plan_joins(
                cp,
                knit_now=kind[c] == 0,
                knit_next=nxt == 0,
                new_carriers=new,
                # (without path planning the passes keep their given order)
                ordered=ctx.path_planning != "none",
            )
        else:
            catches = plan_catches(cp, new_carriers=new)
    segments = [(s.carrier, s.wales) for s in cp.segments]
    tall = ctx.tuck_first[c] if ctx.tuck_first is not None else None
    items = course_items(segments, catches, beds, left, tucks, tall)
    lookahead: list[WorkItem] = []
    if c + 1 < len(plan.courses):
        # The next course's own segments: orders that leave carriers where that work can
        # start in one pass are preferred (its joins are not known yet).
        nxt_segments = [(s.carrier, s.wales) for s in plan.courses[c + 1].segments]
        lookahead = course_items(nxt_segments, [], ctx.beds[c + 1], left)
    parity = "-" if c % 2 == 0 else "+"
    planned, _ = order_and_plan(items, em.states, ctx.path_planning, parity, lookahead, ctx.park)
    prev = kind[c - 1] if c else np.zeros_like(kind[c])
    changed = bool((kind[c] != prev).any())
    # (A tall-bump tuck and the knit through it cannot share a pass: one more per carrier.)
    bound = len({it.carriers for it in items}) + sum(it.pretuck for it in items) + int(changed)

    required = dict(zip(em.needles, beds, strict=True))
    if not ctx.float_avoidance:
        em.xfer(
            {n: b for n, b in required.items() if em.bed[n] != b},
            role=Role.TRANSFER,
            course=label,
        )
    crossings = float_crossings(planned, em.states, needles=em.needles, entry=ctx.entry)
    # (A tuck join is not the needle's stitch: its own stitch decides when the loop moves.)
    stitch_pass = {
        n: i
        for i, p in enumerate(planned)
        if p.kind != "move"
        for n, _ in p.stitches
        if n not in p.tucks
    }
    for i, p in enumerate(planned):
        if ctx.float_avoidance:
            # Transfers for the pass after a carrier move go before the move: a carrier
            # just moved inside the fabric would be in their way.
            j = next((k for k in range(i, len(planned)) if planned[k].kind != "move"), i)
            moves, for_floats = transfers_before(
                j, planned, crossings, bed=em.bed, required=required, stitch_pass=stitch_pass
            )
            if moves:
                em.float_transfer_passes += int(for_floats)
                em.xfer(
                    moves,
                    role=Role.FLOAT_AVOIDANCE if for_floats else Role.TRANSFER,
                    course=label,
                )
        em.knit(p, role=role, course=label)
    done = [car for car, lc in ctx.last_course.items() if lc == c and c != len(kind) - 1]
    em.outhook(sorted(done, key=em.machine.carriers.index))
    return bound


def _checked_options(stitches: object, options: KnitOptions | None) -> KnitOptions:
    """Check :func:`schedule_mixed`'s input; returns the options to use."""
    if not isinstance(stitches, StitchPattern):
        raise PatternValidationError(
            f"`stitches` must be a StitchPattern, got {type(stitches).__name__}"
        )
    if options is None:
        return KnitOptions()
    if not isinstance(options, KnitOptions):
        raise OptionError(f"`options` must be a KnitOptions, got {type(options).__name__}")
    return options


def _color_plan(
    stitches: StitchPattern, *, machine: MachineSpec, limit: int, strict: bool
) -> tuple[ColorPlan, np.ndarray]:
    """Carrier plan and stitch kinds of every course, the cast-on courses (course 0's colours,
    all knits) included."""
    k0 = stitches.cast_on_courses
    n_wales = stitches.shape[1]
    yarn = np.vstack([np.repeat(stitches.yarn[:1], k0, axis=0), stitches.yarn])
    kind = np.vstack([np.zeros((k0, n_wales), dtype=np.uint8), stitches.kind])

    def course_name(c: int) -> str:
        return f"cast-on course {c}" if c < k0 else stitches.course_name(c - k0)

    plan = plan_color_runs(
        yarn,
        carriers=machine.carriers,
        float_limit=limit,
        strict=strict,
        course_names=[course_name(c) for c in range(yarn.shape[0])],
    )
    return plan, kind


def refuses_long_floats(long: Sequence[LongFloat], options: KnitOptions) -> bool:
    """The one float policy: floats over the limit (:func:`~illuknit.knitout.floats.is_long_float`)
    are refused unless ``options.allow_long_floats`` (``strict_floats`` refuses them either
    way). :func:`schedule_mixed` and :func:`~illuknit.knitting.knit_pattern` both decide by it."""
    return bool(long) and (options.strict_floats or not options.allow_long_floats)


def long_float_error(
    long: Sequence[LongFloat], stitches: StitchPattern, limit: int
) -> LongFloatError:
    """The error for floats that stay long: how many, the longest, where, what to change."""
    worst = max(long, key=lambda f: f.length)
    where = worst.where(stitches)
    fewer = "fewer --colors / --yarns, or " if len(stitches.yarns) > 2 else ""
    fix = (
        f"use fewer colour regions per row there ({fewer}a smoothed picture), a wider float "
        f"limit (illuknit knit --float-limit N, now {limit}), or keep the long floats "
        "(--allow-long-floats)"
    )
    waste = [f.length for f in long if f.place == "the waste section"]
    if waste:
        # (Its yarn-in tucks are every k-th needle for k yarns: they float k - 1 needles.)
        fix += (
            f"; in the waste section the yarns come in with tucks {max(waste) + 1} needles "
            f"apart: a float limit below {max(waste)} needs fewer yarns (--colors / --yarns)"
        )
    return LongFloatError(
        f"{len(long)} float(s) stay longer than the float limit of {limit} needles skipped; "
        f"the longest, {worst.length} needles skipped of carrier {worst.carrier} (needles "
        f"{worst.from_needle} to {worst.to_needle}), is at {where}: {fix}",
        length=worst.length,
        carrier=worst.carrier,
        from_needle=worst.from_needle,
        to_needle=worst.to_needle,
        course=worst.course,
        where=where,
        limit=limit,
        count=len(long),
    )


def schedule_mixed(
    stitches: StitchPattern,
    *,
    machine: str | MachineSpec = DEFAULT_MACHINE,
    options: KnitOptions | None = None,
    yarn_entry: YarnEntry | None = None,
) -> Schedule:
    """Schedule a stitch pattern whose courses may change colour (see the module docstring).

    Parameters
    ----------
    stitches : StitchPattern
        C courses x W wales, any yarns and knit/purl anywhere (its cast-on courses included).
    machine : str or MachineSpec
        Bed, carriers, float limit, parking, stitch numbers (a preset name is read by
        :func:`~illuknit.core.machine.resolve_machine`).
    options : KnitOptions, optional
        The scheduler's switches (:class:`~illuknit.knit.options.KnitOptions`; its
        ``cast_on_courses`` is the lowering's and is read from ``stitches``): float avoidance
        (Algorithm 1), catching (tuck joins, the paper's plated stitches of Algorithm 2, or
        none) on every ``catch_every``-th course, the path-planning strategy (Algorithm 3), and
        the float policy. A float longer than ``machine.float_limit`` after tucking raises
        :class:`~illuknit.core.errors.LongFloatError` naming the course unless
        ``allow_long_floats`` (then it is listed in ``Schedule.long_floats``; ``strict_floats``
        refuses it either way, and also a course that needs more carriers than the machine has
        to keep every float within the limit). Defaults: ``KnitOptions()``.
    yarn_entry : YarnEntry, optional
        Where the yarns enter on a machine without an inserting hook
        (:func:`~illuknit.knit.hookless.yarn_entry`): each yarn's float from its entry to its
        first stitch is then tucked like any other long float. None (machines with a hook): a
        yarn starts at its first stitch.

    Returns
    -------
    Schedule
        ``mixed`` (a :class:`~illuknit.knit.schedule.MixedReport`) holds the switches used,
        ``plated_stitches``, ``float_avoidance_transfers``, ``carriers`` and
        ``stranded_segments``.

    Raises
    ------
    CarrierShortageError
        If a course needs more carriers at once than the machine has (with ``strict_floats``,
        or when it uses more yarns than there are carriers).
    LongFloatError
        If a float stays longer than the float limit (see ``options``).
    SchedulingError
        If the piece is wider than the bed.
    OptionError
        If ``options`` is not a KnitOptions.
    PatternValidationError
        If ``stitches`` is not a StitchPattern.
    """
    machine = resolve_machine(machine)
    opts = _checked_options(stitches, options)
    if yarn_entry is not None:
        check_instance(yarn_entry, YarnEntry, "yarn_entry")
    machine.check_width(stitches.shape[1])
    ctx = _courses(stitches, machine, opts, hookless=yarn_entry is not None)
    em = Emitter(
        machine, machine.fabric_left, stitches.shape[1], ctx.path_planning, ctx.float_avoidance
    )
    cast_fixed = cast_on(em, ctx.plan.courses[0].segments, park=ctx.park)
    for n in em.needles:
        em.bed[n] = "f"
    bounds = [_knit_course(em, ctx, cp.course) for cp in ctx.plan.courses]
    bind_fixed = bind_off(
        em,
        ctx.plan.courses[-1],
        park=ctx.park,
        catching=ctx.join is not None,
        path_planning=ctx.path_planning,
        tail_stitches=TAIL_STITCHES,
    )
    steps, long = _finished_steps(em, ctx, yarn_entry)
    if refuses_long_floats(long, opts):
        raise long_float_error(long, stitches, machine.float_limit)
    body_bound = sum(bounds[ctx.k0 :])
    return Schedule(
        steps=tuple(steps),
        machine=machine,
        yarns=stitches.yarns,
        carrier_of_yarn=ctx.plan.carrier_of_yarn,
        left=em.left,
        wales=em.wales,
        courses=stitches.shape[0],
        lower_bound=cast_fixed + sum(bounds[: ctx.k0]) + body_bound + bind_fixed,
        body_lower_bound=body_bound,
        units=stitches.units,
        scheduler="mixed-colourwork",
        long_floats=tuple(long),
        mixed=_report(em, ctx, opts),
    )


def _courses(
    stitches: StitchPattern, machine: MachineSpec, opts: KnitOptions, *, hookless: bool = False
) -> _Courses:
    """The carrier plan of every course and what the courses read while they are scheduled
    (``hookless``: the yarns enter from beyond the right edge, not on an inserting hook)."""
    plan, kind = _color_plan(
        stitches, machine=machine, limit=machine.float_limit, strict=opts.strict_floats
    )
    edge = machine.fabric_left + stitches.shape[1] - 1
    return _Courses(
        plan=plan,
        kind=kind,
        beds=np.array(["f", "b"])[kind].tolist(),
        k0=stitches.cast_on_courses,
        join=None if opts.catching is Catching.OFF else opts.catching.value,
        catch_every=opts.catch_every,
        path_planning=opts.path_planning.value,
        float_avoidance=opts.float_avoidance,
        park=(machine.fabric_left - machine.park_distance, edge + machine.park_distance),
        last_course={s.carrier: cp.course for cp in plan.courses for s in cp.segments},
        tuck_passes=opts.tuck_passes,
        tuck_first=None
        if stitches.tuck_first is None
        else np.vstack(
            [np.zeros((stitches.cast_on_courses, stitches.shape[1]), bool), stitches.tuck_first]
        ),
        entry=edge + 1 if hookless else None,
    )


def _finished_steps(
    em: Emitter, ctx: _Courses, yarn_entry: YarnEntry | None
) -> tuple[list[Step], list[LongFloat]]:
    """The emitted steps with continuing carrier moves folded into their passes and long floats
    tucked (each yarn's float from where it enters included); the floats that stay long."""
    steps = fold_moves(em.steps)
    entries: dict[str, int] = {}
    if yarn_entry is not None:
        entries = yarn_entry.needles(first_directions(steps), *fabric_needles(steps))
    return tuck_long_floats(
        steps,
        limit=em.machine.float_limit,
        left=em.left,
        right=em.left + em.wales - 1,
        alone=ctx.tuck_passes,
        entries=entries,
    )


def _report(em: Emitter, ctx: _Courses, opts: KnitOptions) -> MixedReport:
    """The switches used and what they added."""
    return MixedReport(
        float_avoidance=ctx.float_avoidance,
        catching=ctx.join is not None,
        join_method=ctx.join or "none",
        tuck_joins=em.join_tucks,
        path_planning=ctx.path_planning,
        catch_every=ctx.catch_every,
        float_limit=em.machine.float_limit,
        strict_floats=opts.strict_floats,
        plated_stitches=em.plated,
        float_avoidance_transfers=em.float_transfer_passes,
        carriers=len(ctx.plan.carriers),
        stranded_segments=ctx.plan.stranded_segments,
    )
