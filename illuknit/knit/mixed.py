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

from illuknit.core.errors import LongFloatError, OptionError, PatternValidationError
from illuknit.core.machine import DEFAULT_MACHINE, MachineSpec, resolve_machine
from illuknit.knit.catching import JOIN_METHODS, JoinTuck, PlatedStitch, plan_catches, plan_joins
from illuknit.knit.color_runs import ColorPlan, plan_color_runs
from illuknit.knit.course_order import course_items, order_and_plan
from illuknit.knit.float_avoidance import float_crossings, transfers_before
from illuknit.knit.float_tucks import LongFloat, tuck_long_floats
from illuknit.knit.hookless import YarnEntry, fabric_needles, first_directions
from illuknit.knit.ir import Role
from illuknit.knit.mixed_edges import Emitter, bind_off, cast_on
from illuknit.knit.move_folding import fold_moves
from illuknit.knit.path_planning import (
    STRATEGIES,
    Park,
    WorkItem,
)
from illuknit.knit.schedule import MixedReport, Schedule
from illuknit.knit.stitches import StitchPattern

__all__ = ["long_float_error", "schedule_mixed", "validate_ablation"]


def validate_ablation(*, float_avoidance: object, catching: object, path_planning: object) -> None:
    """Check the ablation switches (booleans, a join method and a known strategy name)."""
    if not isinstance(float_avoidance, (bool, np.bool_)):
        raise OptionError(f"`float_avoidance` must be True or False, got {float_avoidance!r}")
    if not isinstance(catching, (bool, np.bool_)) and catching not in JOIN_METHODS:
        raise OptionError(
            f"`catching` must be True, False or one of {', '.join(JOIN_METHODS)}, got {catching!r}"
        )
    if path_planning not in STRATEGIES:
        raise OptionError(
            f"`path_planning` must be one of {', '.join(STRATEGIES)}, got {path_planning!r}"
        )


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
    park: Park | None
    last_course: dict[str, int]  # carrier -> last course it knits in
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


def _checked_options(
    stitches: object,
    *,
    machine: MachineSpec,
    float_avoidance: object,
    catching: object,
    path_planning: object,
    float_limit: object,
    tail_stitches: int,
    catch_every: object,
) -> int:
    """Check :func:`schedule_mixed`'s input and options; returns the float limit to use."""
    if not isinstance(stitches, StitchPattern):
        raise PatternValidationError(
            f"`stitches` must be a StitchPattern, got {type(stitches).__name__}"
        )
    validate_ablation(
        float_avoidance=float_avoidance, catching=catching, path_planning=path_planning
    )
    limit = machine.float_limit if float_limit is None else float_limit
    if isinstance(limit, bool) or not isinstance(limit, (int, np.integer)) or limit < 1:
        raise OptionError(
            f"`float_limit` must be an integer >= 1 (wales a yarn may float across), got {limit!r}"
        )
    if tail_stitches < 1:
        raise OptionError(f"`tail_stitches` must be >= 1, got {tail_stitches}")
    if (
        isinstance(catch_every, bool)
        or not isinstance(catch_every, (int, np.integer))
        or catch_every < 1
    ):
        raise OptionError(f"`catch_every` must be an integer >= 1, got {catch_every!r}")
    return int(limit)


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


def long_float_error(
    long: Sequence[LongFloat], stitches: StitchPattern, limit: int
) -> LongFloatError:
    """The error for floats that stay long: how many, the longest, where, what to change."""
    worst = max(long, key=lambda f: f.length)
    where = worst.where(stitches)
    fix = (
        "use fewer colour regions per row there (fewer --colors / --yarns, or a smoothed "
        f"picture), a wider float limit (illuknit knit --float-limit N, now {limit}), or keep "
        "the long floats (--allow-long-floats)"
    )
    waste = [f.length for f in long if f.place == "the waste section"]
    if waste:
        # (Its yarn-in tucks are every k-th needle for k yarns: they float k - 1 needles.)
        fix += (
            f"; in the waste section the yarns come in with tucks {max(waste) + 1} needles "
            f"apart: a float limit below {max(waste)} needs fewer yarns (--colors / --yarns)"
        )
    return LongFloatError(
        f"{len(long)} float(s) stay longer than the float limit of {limit} needles; the "
        f"longest, {worst.length} needles of carrier {worst.carrier} (needles "
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
    float_avoidance: bool = True,
    catching: bool | str = True,
    path_planning: str = "anchor",
    catch_every: int = 2,
    float_limit: int | None = None,
    strict_floats: bool = False,
    allow_long_floats: bool = True,
    tail_stitches: int = 4,
    park_carriers: bool = True,
    tuck_passes: bool = False,
    yarn_entry: YarnEntry | None = None,
) -> Schedule:
    """Schedule a stitch pattern whose courses may change colour (see the module docstring).

    Parameters
    ----------
    stitches : StitchPattern
        C courses x W wales, any yarns and knit/purl anywhere.
    machine : str or MachineSpec
        Bed, carriers, float limit, parking, stitch numbers (a preset name is read by
        :func:`~illuknit.core.machine.resolve_machine`).
    float_avoidance : bool
        Algorithm 1: move purls to the front around floats that cross them.
    catching : bool or {"tuck", "plate"}
        Join neighbouring carriers' regions. True or ``"tuck"`` (the default): tuck joins, a
        carrier tucking on the neighbour's edge needle in its own pass, plated stitches only
        where no tuck is safe (:func:`~illuknit.knit.catching.plan_joins`); ``"plate"``: the
        paper's plated stitches everywhere (Algorithm 2); False: no joins (the ablation).
    path_planning : {"anchor", "split", "none"}
        Algorithm 3 strategy; ``none`` knits every pass in the course's parity direction.
    catch_every : int
        Catch on every ``catch_every``-th course. The default 2 catches once per unit row (a
        unit is two courses), so no join stays open for more than one course; 1 plates at every
        colour change of every course, as the paper does, at the price of more passes.
    float_limit : int, optional
        Longest float in wales; defaults to ``machine.float_limit``.
    strict_floats : bool
        Raise :class:`~illuknit.core.errors.CarrierShortageError` when a course needs more carriers
        than the machine has to keep every float within the limit, and
        :class:`~illuknit.core.errors.LongFloatError` naming the course when a float stays longer
        than the limit after tucking; by default such floats are kept and listed in
        ``Schedule.long_floats`` (the checker warns about them).
    allow_long_floats : bool
        False: raise :class:`~illuknit.core.errors.LongFloatError` naming the course when a float
        stays longer than the limit after tucking (the default of
        :func:`~illuknit.knitting.pipeline.knit_pattern` and of every command); True (this
        stage's default, so that its caller decides): keep it, list it in
        ``Schedule.long_floats``.
    tail_stitches : int
        Knits on the last needle of the bind-off chain.
    park_carriers : bool
        End every pass with its carriers parked just beyond the fabric edge it runs towards
        (the default), so that no carrier waits inside the fabric where the machine would have
        to move it out of other passes' way; False leaves each carrier at its last stitch (the
        paper's intarsia behaviour, which the SWG backend pays for with extra passes).
    tuck_passes : bool
        Where a plated catching pass cannot tuck a long float (its other yarn comes from
        elsewhere), tuck the floating yarn alone in a pass of its own right before it. Off by
        default; it matters with ``catching="plate"`` only (on the plated bundled programs it
        cost 1-29 % more machine passes, ``docs/mixed-colourwork.md``).
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
    SchedulingError
        If the piece is wider than the bed.
    OptionError
        For bad options (float limit below 1, unknown strategy, non-boolean switches).
    PatternValidationError
        If ``stitches`` is not a StitchPattern.
    """
    machine = resolve_machine(machine)
    limit = _checked_options(
        stitches,
        machine=machine,
        float_avoidance=float_avoidance,
        catching=catching,
        path_planning=path_planning,
        float_limit=float_limit,
        tail_stitches=tail_stitches,
        catch_every=catch_every,
    )
    join = (str(catching) if isinstance(catching, str) else "tuck") if catching else None
    n_courses, n_wales = stitches.shape
    machine.check_width(n_wales)
    k0 = stitches.cast_on_courses
    plan, kind = _color_plan(stitches, machine=machine, limit=limit, strict=bool(strict_floats))
    left = machine.fabric_left
    em = Emitter(machine, left, n_wales, path_planning, bool(float_avoidance))
    last_course = {s.carrier: cp.course for cp in plan.courses for s in cp.segments}

    edge = left + n_wales - 1
    park: Park | None = (
        (left - machine.park_distance, edge + machine.park_distance) if park_carriers else None
    )
    cast_fixed = cast_on(em, plan.courses[0].segments, park=park)
    for n in em.needles:
        em.bed[n] = "f"

    ctx = _Courses(
        plan=plan,
        kind=kind,
        beds=np.array(["f", "b"])[kind].tolist(),
        k0=k0,
        join=join,
        catch_every=int(catch_every),
        path_planning=path_planning,
        float_avoidance=bool(float_avoidance),
        park=park,
        last_course=last_course,
        entry=None if yarn_entry is None else edge + 1,
        tuck_first=None
        if stitches.tuck_first is None
        else np.vstack([np.zeros((k0, n_wales), dtype=bool), stitches.tuck_first]),
    )
    body_bound = 0
    cast_courses_bound = 0
    for cp in plan.courses:
        bound = _knit_course(em, ctx, cp.course)
        if cp.course >= k0:
            body_bound += bound
        else:
            cast_courses_bound += bound

    bind_fixed = bind_off(
        em,
        plan.courses[-1],
        park=park,
        catching=join is not None,
        path_planning=path_planning,
        tail_stitches=tail_stitches,
    )

    em.steps = fold_moves(em.steps)
    entries: dict[str, int] = {}
    if yarn_entry is not None:
        entries = yarn_entry.needles(first_directions(em.steps), *fabric_needles(em.steps))
    long: list[LongFloat] = []
    if park is not None:
        em.steps, long = tuck_long_floats(
            em.steps,
            limit=limit,
            left=left,
            right=edge,
            alone=bool(tuck_passes),
            entries=entries,
        )
        if long and (strict_floats or not allow_long_floats):
            raise long_float_error(long, stitches, limit)
    lower = cast_fixed + cast_courses_bound + body_bound + bind_fixed
    return Schedule(
        steps=tuple(em.steps),
        machine=machine,
        yarns=stitches.yarns,
        carrier_of_yarn=plan.carrier_of_yarn,
        left=left,
        wales=n_wales,
        courses=n_courses,
        lower_bound=lower,
        body_lower_bound=body_bound,
        units=stitches.units,
        scheduler="mixed-colourwork",
        long_floats=tuple(long),
        mixed=MixedReport(
            float_avoidance=bool(float_avoidance),
            catching=join is not None,
            join_method=join or "none",
            tuck_joins=em.join_tucks,
            path_planning=path_planning,
            catch_every=int(catch_every),
            float_limit=limit,
            strict_floats=bool(strict_floats),
            plated_stitches=em.plated,
            float_avoidance_transfers=em.float_transfer_passes,
            carriers=len(plan.carriers),
            stranded_segments=plan.stranded_segments,
        ),
    )
