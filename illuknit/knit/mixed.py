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
leaves with ``outhook`` after its last course. Finally :func:`fold_moves` folds each
carrier-placing ``miss`` pass that continues its carrier's previous pass into that pass, and
:func:`~illuknit.knit.float_tucks.tuck_long_floats` tucks floats over the limit onto free back
needles.

**Bind-off**: every loop to the front, then the one-colour chain
(:func:`~illuknit.knit.schedule.bind_off_steps`) in one yarn, started where the last course ended
(the carrier whose last loop is nearest an edge it is parked beyond; the others go out first).
With catching off each run is bound off on its own instead (tail, then the loop is dropped), so
that nothing the scheduler adds joins the regions.

**Passes and the lower bound.** The lower bound per body course is *the number of distinct
carrier sets that knit in it* (the SWG backend merges only operations with the identical carrier
list, so each set -- each carrier and each plated pair -- needs its own pass) *plus one transfer
pass if some loop changes bed* relative to the previous course (both directions share one pass at
racking 0); the cast-on tucks and the bind-off recipe count at their own length. It counts no
carrier moves, and none is unavoidable: parked carriers are in no pass's way (see
``docs/mixed-colourwork.md``). It is a bound for the given carrier plan, not over all plans. The
passes reported for a program are the machine's (:mod:`illuknit.knit.carriage`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from illuknit.errors import OptionError, PatternValidationError, SchedulingError
from illuknit.knit.catching import PlatedStitch, plan_catches
from illuknit.knit.color_runs import ColorPlan, plan_color_runs
from illuknit.knit.float_avoidance import float_crossings, transfers_before
from illuknit.knit.float_tucks import LongFloat, tuck_long_floats
from illuknit.knit.ir import (
    ActionKind,
    Bed,
    CarrierAction,
    Direction,
    Op,
    OpKind,
    Pass,
    PassKind,
    Role,
    Step,
    flip,
)
from illuknit.knit.machine import DEFAULT_MACHINE, MachineSpec
from illuknit.knit.path_planning import (
    STRATEGIES,
    CarrierState,
    Park,
    PlannedPass,
    WorkItem,
    advance,
    pass_cost,
    plan_item,
)
from illuknit.knit.schedule import MixedReport, Schedule, bind_off_steps
from illuknit.knit.stitches import StitchPattern

__all__ = ["fold_moves", "schedule_mixed", "validate_ablation"]


def validate_ablation(*, float_avoidance: object, catching: object, path_planning: object) -> None:
    """Check the ablation switches (booleans and a known strategy name)."""
    for name, v in (("float_avoidance", float_avoidance), ("catching", catching)):
        if not isinstance(v, (bool, np.bool_)):
            raise OptionError(f"`{name}` must be True or False, got {v!r}")
    if path_planning not in STRATEGIES:
        raise OptionError(
            f"`path_planning` must be one of {', '.join(STRATEGIES)}, got {path_planning!r}"
        )


@dataclass
class _Emitter:
    """Mutable machine state while the schedule is written (carriers, beds, steps)."""

    machine: MachineSpec
    left: int
    wales: int
    strategy: str
    float_avoidance: bool

    def __post_init__(self) -> None:
        self.steps: list[Step] = []
        self.states: dict[str, CarrierState] = {}
        self.bed: dict[int, str] = {}
        self.float_transfer_passes = 0
        self.moves = 0
        self.plated = 0

    @property
    def needles(self) -> range:
        return range(self.left, self.left + self.wales)

    # -- primitive steps --------------------------------------------------------------------
    def xfer(self, moves: dict[int, str], *, role: Role, course: int | None) -> None:
        if not moves:
            return
        ops = []
        for n in sorted(moves):
            to = Bed(moves[n])
            frm = Bed.BACK if to is Bed.FRONT else Bed.FRONT
            ops.append(Op(OpKind.XFER, frm, n, to, n))
            self.bed[n] = to
        self.steps.append(Pass(PassKind.XFER, tuple(ops), None, (), 0.0, role, course))

    def knit(
        self,
        p: PlannedPass,
        *,
        role: Role,
        course: int | None,
        op: OpKind = OpKind.KNIT,
        extra: Sequence[Op] = (),
    ) -> None:
        """Emit a planned pass (hooking in a never-used carrier around it)."""
        new = [c for c in p.carriers if self.states.get(c, CarrierState()).needle is None]
        if p.kind == "move":
            n, _ = p.stitches[0]
            self.steps.append(
                Pass(
                    PassKind.KNIT,
                    (Op(OpKind.MISS, Bed.FRONT, n),),
                    p.direction,
                    p.carriers,
                    0.0,
                    Role.ANCHOR,
                    course,
                    self.machine.stitch_number,
                )
            )
            self.moves += 1
        else:
            if new:
                self.steps.append(CarrierAction(ActionKind.INHOOK, p.carriers))
            ops = tuple(Op(op, Bed(b), n) for n, b in p.stitches) + tuple(extra)
            if p.park is not None:
                ops += (Op(OpKind.MISS, Bed.FRONT, p.park),)
            self.steps.append(
                Pass(
                    PassKind.KNIT,
                    ops,
                    p.direction,
                    p.carriers,
                    0.0,
                    role,
                    course,
                    self.machine.stitch_number,
                )
            )
            if len(p.carriers) > 1:
                self.plated += len(p.stitches)
            if new:
                self.steps.append(CarrierAction(ActionKind.RELEASEHOOK, p.carriers))
        self.states = advance(self.states, p)
        if extra:
            last = extra[-1]
            for c in p.carriers:
                st = self.states[c]
                self.states[c] = CarrierState(last.needle, p.direction, st.last_loop)

    def outhook(self, carriers: Sequence[str]) -> None:
        for c in carriers:
            self.steps.append(CarrierAction(ActionKind.OUTHOOK, (c,)))
            self.states.pop(c, None)


def _bind_off_start(
    states: dict[str, CarrierState], left: int, right: int
) -> tuple[str, Direction]:
    """Carrier and direction of a one-yarn bind-off: the shortest float into its first stitch.

    A carrier parked beyond the right edge starts leftward from the right edge wale, one parked
    left rightward from the left one; ties go to the carrier that needs no move to that side.
    """
    best: tuple[int, int, str, Direction] | None = None
    for car, st in sorted(states.items()):
        if st.needle is None or st.last_loop is None:
            continue
        for d, start in (("-", right), ("+", left)):
            move = int((d == "-") != (st.direction == "+"))
            key = (abs(st.last_loop - start), move, car, d)
            if best is None or key < best:
                best = key  # type: ignore[assignment]
    assert best is not None, "a piece always has a live carrier at its bind-off"
    return best[2], best[3]


def _course_items(
    plan_segments: Sequence[tuple[str, list[int]]],
    catches: Sequence[PlatedStitch],
    beds: Sequence[str],
    left: int,
) -> list[WorkItem]:
    plated_wales = {p.wale for p in catches}
    items: list[WorkItem] = []
    for car, wales in plan_segments:
        st = tuple((left + w, beds[w]) for w in wales if w not in plated_wales)
        if st:
            items.append(WorkItem((car,), st))
    groups: dict[tuple[str, str], list[int]] = {}
    for p in catches:
        groups.setdefault(p.carriers, []).append(p.wale)
    for cars, wales in groups.items():
        items.append(WorkItem(cars, tuple((left + w, beds[w]) for w in sorted(wales)), plated=True))
    return items


#: Courses with at most this many work items are ordered by exhaustive search (branch and
#: bound over permutations); larger ones greedily.
EXHAUSTIVE_ITEMS = 6
#: Partial orders kept per step when a course has more items than that (scaled down as the
#: item count grows, to keep the time per course bounded).
BEAM_WIDTH = 8


def _order_and_plan(
    items: list[WorkItem],
    states: dict[str, CarrierState],
    strategy: str,
    parity: str,
    lookahead: Sequence[WorkItem] = (),
    park: Park | None = None,
) -> tuple[list[PlannedPass], dict[str, CarrierState]]:
    """Order a course's items for fewest passes; a carrier's own item comes before plating.

    Up to :data:`EXHAUSTIVE_ITEMS` items every order is tried (branch and bound on the pass
    count, plans cached per item and carrier states); beyond, a beam search keeps the
    :data:`BEAM_WIDTH` cheapest partial orders. ``none`` keeps the given order.
    """
    if strategy == "none":
        planned: list[PlannedPass] = []
        st = dict(states)
        order = [it for it in items if len(it.carriers) == 1] + [
            it for it in items if len(it.carriers) > 1
        ]
        for it in order:
            for p in plan_item(it, st, strategy=strategy, parity=parity, park=park):  # type: ignore[arg-type]
                st = advance(st, p)
                planned.append(p)
        return planned, st

    Entry = tuple[list[PlannedPass], int, dict[str, CarrierState]]
    cache: dict[tuple[int, tuple[CarrierState, ...]], Entry] = {}
    unused = CarrierState()

    def plan(i: int, st: dict[str, CarrierState]) -> Entry:
        """Passes of item ``i`` from ``st``, their cost and the item carriers' new states."""
        it = items[i]
        key = (i, tuple(st.get(c, unused) for c in it.carriers))
        got = cache.get(key)
        if got is None:
            ps = plan_item(it, st, strategy=strategy, parity=parity, park=park)  # type: ignore[arg-type]
            sub = {c: st.get(c, unused) for c in it.carriers}
            cost = pass_cost(ps, sub)
            for p in ps:
                sub = advance(sub, p)
            got = (ps, cost, sub)
            cache[key] = got
        return got

    def ready(i: int, st: dict[str, CarrierState]) -> bool:
        it = items[i]
        return len(it.carriers) == 1 or all(
            st.get(c, unused).needle is not None for c in it.carriers
        )

    ahead_cache: dict[tuple[int, CarrierState], int] = {}

    def ahead(st: dict[str, CarrierState]) -> int:
        """Extra passes the next course's own segments would need from these states."""
        extra = 0
        for k, it in enumerate(lookahead):
            car = it.carriers[0]
            cs = st.get(car, unused)
            if cs.needle is None:
                continue
            key = (k, cs)
            got = ahead_cache.get(key)
            if got is None:
                ps = plan_item(it, {car: cs}, strategy=strategy, parity=parity, park=park)  # type: ignore[arg-type]
                got = pass_cost(ps, {car: cs}) - 1
                ahead_cache[key] = got
            extra += got
        return extra

    if len(items) <= EXHAUSTIVE_ITEMS:
        best: list[object] = [None, None, None]  # cost, passes, states

        def search(
            left: list[int], st: dict[str, CarrierState], acc: list[PlannedPass], cost: int
        ) -> None:
            if best[0] is not None and cost >= best[0]:  # type: ignore[operator]
                return
            if not left:
                total = cost + ahead(st)
                if best[0] is None or total < best[0]:  # type: ignore[operator]
                    best[0], best[1], best[2] = total, list(acc), st
                return
            for i in left:
                if not ready(i, st):
                    continue
                ps, c, sub = plan(i, st)
                search([j for j in left if j != i], {**st, **sub}, acc + ps, cost + c)

        search(list(range(len(items))), dict(states), [], 0)
        if best[1] is None:  # pragma: no cover - catching never pairs an unused carrier
            raise SchedulingError("plated stitch with a carrier that never knit")
        return best[1], best[2]  # type: ignore[return-value]

    # Beam search: keep the BEAM_WIDTH cheapest partial orders at each depth.
    beam: list[tuple[int, list[int], dict[str, CarrierState], list[PlannedPass]]] = [
        (0, list(range(len(items))), dict(states), [])
    ]
    width = max(2, BEAM_WIDTH * EXHAUSTIVE_ITEMS // len(items))
    for _ in range(len(items)):
        grown = []
        for cost, left, st, acc in beam:
            for i in left:
                if not ready(i, st):
                    continue
                ps, c, sub = plan(i, st)
                grown.append((cost + c, [j for j in left if j != i], {**st, **sub}, acc + ps))
        if not grown:  # pragma: no cover - catching never pairs an unused carrier
            raise SchedulingError("plated stitch with a carrier that never knit")
        grown.sort(key=lambda t: t[0])
        beam = grown[:width]
    _, _, st, planned = min(beam, key=lambda t: t[0] + ahead(t[2]))
    return planned, st


def _others_turn(steps: Sequence[Step], j: int, prev: Pass, c: str) -> bool:
    """True when every other carrier of pass ``j`` next knits in the opposite direction.

    Parking them further along their last direction then only puts them further behind the
    carriage for that next pass, so a miss may be appended to ``prev`` for ``c``'s sake.
    """
    others = [x for x in prev.carriers if x != c]
    for x in others:
        for s in steps[j + 1 :]:
            if isinstance(s, CarrierAction):
                if x in s.carriers:
                    return False
                continue
            if x in s.carriers:
                if all(o.op == "miss" for o in s.ops) or s.direction == prev.direction:
                    return False
                break
        else:
            return False
    return True


def fold_moves(steps: Sequence[Step]) -> list[Step]:
    """Fold each carrier-placing ``miss`` pass into the carrier's previous pass where possible.

    A move that continues, in the same direction, the last pass its carrier made on its own
    (no other pass or carrier action of that carrier in between; transfers may be) is the same
    as parking the carrier a little further at the end of that pass: the miss is appended there
    and the extra pass disappears. Loops are unchanged, so floats and transfers stay valid.
    """
    out: list[Step] = list(steps)
    last_own: dict[str, int] = {}  # carrier -> index in out of its last pass or action
    i = 0
    while i < len(out):
        s = out[i]
        if isinstance(s, CarrierAction):
            for c in s.carriers:
                last_own[c] = -1
            i += 1
            continue
        if s.kind != "knit":
            i += 1
            continue
        is_move = all(o.op == "miss" for o in s.ops) and len(s.carriers) == 1
        if is_move:
            c = s.carriers[0]
            j = last_own.get(c, -1)
            prev = out[j] if j >= 0 else None
            target = s.ops[-1].needle
            if (
                isinstance(prev, Pass)
                and (prev.carriers == s.carriers or _others_turn(out, j, prev, c))
                and prev.direction == s.direction
                and (
                    target > prev.ops[-1].needle
                    if s.direction == "+"
                    else target < prev.ops[-1].needle
                )
            ):
                ops = prev.ops
                if ops[-1].op == "miss":
                    ops = ops[:-1]
                out[j] = Pass(
                    prev.kind,
                    (*ops, Op(OpKind.MISS, Bed.FRONT, target)),
                    prev.direction,
                    prev.carriers,
                    prev.racking,
                    prev.role,
                    prev.course,
                    prev.stitch_number,
                )
                del out[i]
                continue
        for c in s.carriers:
            last_own[c] = i
        i += 1
    return out


def schedule_mixed(
    stitches: StitchPattern,
    *,
    machine: MachineSpec = DEFAULT_MACHINE,
    float_avoidance: bool = True,
    catching: bool = True,
    path_planning: str = "anchor",
    catch_every: int = 2,
    float_limit: int | None = None,
    strict_floats: bool = False,
    tail_stitches: int = 4,
    park_carriers: bool = True,
) -> Schedule:
    """Schedule a stitch pattern whose courses may change colour (see the module docstring).

    Parameters
    ----------
    stitches : StitchPattern
        C courses x W wales, any yarns and knit/purl anywhere.
    machine : MachineSpec
        Bed, carriers, float limit, parking, stitch numbers.
    float_avoidance : bool
        Algorithm 1: move purls to the front around floats that cross them.
    catching : bool
        Algorithm 2: plated stitches joining neighbouring carriers' regions.
    path_planning : {"anchor", "split", "none"}
        Algorithm 3 strategy; ``none`` knits every pass in the course's parity direction.
    catch_every : int
        Catch on every ``catch_every``-th course. The default 2 catches once per unit row (a
        unit is two courses), so no join stays open for more than one course; 1 plates at every
        colour change of every course, as the paper does, at the price of more passes.
    float_limit : int, optional
        Longest float in wales; defaults to ``machine.float_limit``.
    strict_floats : bool
        Raise :class:`~illuknit.errors.CarrierShortageError` when a course needs more carriers
        than the machine has to keep every float within the limit, and
        :class:`~illuknit.errors.SchedulingError` naming the course when a float stays longer
        than the limit after tucking; by default such floats are kept and listed in
        ``Schedule.long_floats`` (the checker warns about them).
    tail_stitches : int
        Knits on the last needle of the bind-off chain.
    park_carriers : bool
        End every pass with its carriers parked just beyond the fabric edge it runs towards
        (the default), so that no carrier waits inside the fabric where the machine would have
        to move it out of other passes' way; False leaves each carrier at its last stitch (the
        paper's intarsia behaviour, which the SWG backend pays for with extra passes).

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
    n_courses, n_wales = stitches.shape
    machine.check_width(n_wales)
    k0 = stitches.cast_on_courses
    yarn = np.vstack([np.repeat(stitches.yarn[:1], k0, axis=0), stitches.yarn])
    kind = np.vstack([np.zeros((k0, n_wales), dtype=np.uint8), stitches.kind])

    def course_name(c: int) -> str:
        return f"cast-on course {c}" if c < k0 else stitches.course_name(c - k0)

    plan: ColorPlan = plan_color_runs(
        yarn,
        carriers=machine.carriers,
        float_limit=int(limit),
        strict=bool(strict_floats),
        course_names=[course_name(c) for c in range(yarn.shape[0])],
    )
    left = machine.fabric_left
    em = _Emitter(machine, left, n_wales, path_planning, bool(float_avoidance))
    last_course: dict[str, int] = {}
    for cp in plan.courses:
        for s in cp.segments:
            last_course[s.carrier] = cp.course

    # -- cast-on: each carrier of the first course tucks its own wales -------------------------
    cast_sn = machine.cast_on_stitch
    cast_fixed = 0
    edge = left + n_wales - 1
    park: Park | None = (
        (left - machine.park_distance, edge + machine.park_distance) if park_carriers else None
    )
    for seg in plan.courses[0].segments:
        needles = [left + w for w in seg.wales]
        down = needles[::-1][0::2]
        up = sorted(set(needles) - set(down))
        car = seg.carrier
        em.steps.append(CarrierAction(ActionKind.INHOOK, (car,)))
        # A lone wale has no rightward tucks: its carrier parks left at once (when parking).
        end = park[0] if park is not None and not up else needles[0] - 1
        ops = [Op(OpKind.TUCK, Bed.FRONT, n) for n in down] + [Op(OpKind.MISS, Bed.FRONT, end)]
        em.steps.append(
            Pass(PassKind.KNIT, tuple(ops), "-", (car,), 0.0, Role.CAST_ON, None, cast_sn)
        )
        state = CarrierState(end, "-", down[-1])
        cast_fixed += 1
        if park is not None:
            # Release the hook after the leftward tucks: the rightward ones can then run on to
            # park the carrier right of the fabric, out of every other carrier's way (before the
            # release nothing may pass right of the hook).
            em.steps.append(CarrierAction(ActionKind.RELEASEHOOK, (car,)))
        if up:
            ops = [Op(OpKind.TUCK, Bed.FRONT, n) for n in up]
            if park is not None:
                ops.append(Op(OpKind.MISS, Bed.FRONT, park[1]))
            em.steps.append(
                Pass(PassKind.KNIT, tuple(ops), "+", (car,), 0.0, Role.CAST_ON, None, cast_sn)
            )
            state = CarrierState(ops[-1].needle, "+", up[-1])
            cast_fixed += 1
        if park is None:
            em.steps.append(CarrierAction(ActionKind.RELEASEHOOK, (car,)))
            if up and needles[-1] == edge:
                # As in the one-colour cast-on: once the hook is released, park the carrier
                # right of the fabric so that its first course starts leftward from behind.
                to = Op(OpKind.MISS, Bed.FRONT, edge + machine.park_distance)
                em.steps.append(
                    Pass(PassKind.KNIT, (to,), "+", (car,), 0.0, Role.PARK, None, cast_sn)
                )
                state = CarrierState(to.needle, "+", up[-1])
                cast_fixed += 1
        em.states[car] = state
    for n in em.needles:
        em.bed[n] = "f"

    # -- courses -------------------------------------------------------------------------------
    # Bed of every stitch ("f" knit, "b" purl), once: each course also reads the next one's.
    course_beds: list[list[str]] = np.array(["f", "b"])[kind].tolist()
    body_bound = 0
    cast_courses_bound = 0
    prev_kind = np.zeros(n_wales, dtype=np.uint8)
    for cp in plan.courses:
        c = cp.course
        body = c >= k0
        role = Role.BODY if body else Role.CAST_ON
        label = c - k0 if body else None
        need = kind[c]
        beds = course_beds[c]
        new = frozenset(s.carrier for s in cp.segments if s.carrier not in em.states)
        caught = catching and c % catch_every == 0
        catches = plan_catches(cp, new_carriers=new) if caught else []
        items = _course_items([(s.carrier, s.wales) for s in cp.segments], catches, beds, left)
        parity = "-" if c % 2 == 0 else "+"
        lookahead: list[WorkItem] = []
        if c + 1 < len(plan.courses):
            # The next course's own segments: orders that leave carriers where that work can
            # start in one pass are preferred (its plated stitches are not known yet).
            nxt = plan.courses[c + 1]
            lookahead = _course_items(
                [(s.carrier, s.wales) for s in nxt.segments], [], course_beds[c + 1], left
            )
        planned, _ = _order_and_plan(items, em.states, path_planning, parity, lookahead, park)
        bound = len({it.carriers for it in items}) + int(bool((need != prev_kind).any()))
        prev_kind = need
        if body:
            body_bound += bound
        else:
            cast_courses_bound += bound

        required = dict(zip(em.needles, beds, strict=True))
        if not float_avoidance:
            em.xfer(
                {n: b for n, b in required.items() if em.bed[n] != b},
                role=Role.TRANSFER,
                course=label,
            )
        crossings = float_crossings(planned, em.states, needles=em.needles)
        stitch_pass = {
            n: i for i, p in enumerate(planned) if p.kind != "move" for n, _ in p.stitches
        }
        for i, p in enumerate(planned):
            if float_avoidance:
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
        done = [car for car, lc in last_course.items() if lc == c and c != yarn.shape[0] - 1]
        em.outhook(sorted(done, key=machine.carriers.index))

    # -- bind-off --------------------------------------------------------------------------------
    bind_start = len(em.steps)
    back = {n: "f" for n in em.needles if em.bed[n] == "b"}
    em.xfer(back, role=Role.BIND_OFF, course=None)
    last_plan = plan.courses[-1]
    runs = sorted(
        ((lo, hi, s.carrier) for s in last_plan.segments for lo, hi in s.runs), key=lambda r: r[0]
    )
    drops: list[int] = []

    def chain(run_list: list[tuple[int, int, str]], tail_needle_carrier: str) -> None:
        owner = {left + w: car for lo, hi, car in run_list for w in range(lo, hi + 1)}
        order = sorted(owner)
        for idx, n in enumerate(order[:-1]):
            car = owner[n]
            item = WorkItem((car,), ((n, "f"),))
            ps = plan_item(item, em.states, strategy=path_planning, parity="+" if idx % 2 else "-")
            for p in ps[:-1]:
                em.knit(p, role=Role.BIND_OFF, course=None)
            p = ps[-1]
            extra: tuple[Op, ...] = ()
            if p.direction == "+" and owner[order[idx + 1]] == car:
                # Carry the yarn past the next needle so its opposite-direction stitch is made
                # with the carrier behind the carriage.
                extra = (Op(OpKind.MISS, Bed.FRONT, n + 2),)
            em.knit(p, role=Role.BIND_OFF, course=None, extra=extra)
            em.steps.append(
                Pass(
                    PassKind.XFER,
                    (Op(OpKind.XFER, Bed.FRONT, n, Bed.BACK, n),),
                    None,
                    (),
                    0.0,
                    Role.BIND_OFF,
                )
            )
            em.steps.append(
                Pass(
                    PassKind.XFER,
                    (Op(OpKind.XFER, Bed.BACK, n, Bed.FRONT, n + 1),),
                    None,
                    (),
                    1.0,
                    Role.BIND_OFF,
                )
            )
        last = order[-1]
        car = tail_needle_carrier
        for t in range(1 + tail_stitches):
            item = WorkItem((car,), ((last, "f"),))
            ps = plan_item(item, em.states, strategy=path_planning, parity="+" if t % 2 else "-")
            for p in ps:
                em.knit(p, role=Role.TAIL if t else Role.BIND_OFF, course=None)
        drops.append(last)

    if catching and park is not None:
        # One chain in one yarn, as the one-colour scheduler binds off: started by the carrier
        # whose last loop is nearest an edge it is parked beyond (where the last course ended),
        # so no yarn floats across the piece into the bind-off. The others go out first.
        car, d = _bind_off_start(em.states, left, edge)
        em.outhook([c for c in machine.carriers if c in em.states and c != car])
        st = em.states[car]
        if (d == "-") != (st.direction == "+"):
            target = park[1] if d == "-" else park[0]
            em.knit(
                PlannedPass((car,), flip(d), ((target, "f"),), "move"),
                role=Role.BIND_OFF,
                course=None,
            )
        em.steps.extend(
            bind_off_steps(
                car, d, left, edge, stitch_number=machine.stitch_number, tail_stitches=tail_stitches
            )
        )
        em.states.pop(car)
    elif catching:
        chain(runs, runs[-1][2])
    else:
        for lo, hi, car in runs:
            chain([(lo, hi, car)], car)
    live = [c for c in machine.carriers if c in em.states]
    em.outhook(live)
    if drops:
        em.steps.append(
            Pass(
                PassKind.DROP,
                tuple(Op(OpKind.DROP, Bed.FRONT, n) for n in sorted(drops)),
                None,
                (),
                0.0,
                Role.TAIL,
            )
        )
    bind_passes = [s for s in em.steps[bind_start:] if isinstance(s, Pass)]
    bind_fixed = sum(
        not all(o.op == "miss" for o in p.ops) or p.kind != "knit" for p in bind_passes
    )

    em.steps = fold_moves(em.steps)
    long: list[LongFloat] = []
    if park is not None:
        em.steps, long = tuck_long_floats(em.steps, limit=int(limit), left=left, right=edge)
        if long and strict_floats:
            worst = max(long, key=lambda f: f.length)
            where = "the bind-off" if worst.course is None else stitches.course_name(worst.course)
            raise SchedulingError(
                f"{len(long)} float(s) stay longer than the float limit of {limit} needles; the "
                f"longest, {worst.length} needles of carrier {worst.carrier} (needles "
                f"{worst.from_needle} to {worst.to_needle}), is at {where}: use fewer colour "
                "regions per row there, catching off, or a wider float limit"
            )
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
            catching=bool(catching),
            path_planning=path_planning,
            catch_every=int(catch_every),
            float_limit=int(limit),
            strict_floats=bool(strict_floats),
            plated_stitches=em.plated,
            float_avoidance_transfers=em.float_transfer_passes,
            carriers=len(plan.carriers),
            stranded_segments=plan.stranded_segments,
        ),
    )
