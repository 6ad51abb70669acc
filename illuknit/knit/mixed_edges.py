"""Mixed colourwork: the emitter that writes the steps, the cast-on and the bind-off.

:class:`Emitter` holds the machine state while :func:`~illuknit.knit.mixed.schedule_mixed`
writes a schedule (the steps so far, every carrier's state, the bed of every loop) and turns
planned passes into :class:`~illuknit.knit.ir.Pass` steps, bringing a never-used carrier in on
the inserting hook around its first pass. :func:`cast_on` and :func:`bind_off` are the piece's
two edges (described in :mod:`illuknit.knit.mixed`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from itertools import pairwise

from illuknit.core.machine import MachineSpec
from illuknit.knit.color_runs import CoursePlan, Segment
from illuknit.knit.edges import cast_on_steps
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
    flip,
)
from illuknit.knit.path_planning import (
    CarrierState,
    Park,
    PlannedPass,
    WorkItem,
    advance,
    plan_item,
)

__all__ = ["Emitter", "bind_off", "cast_on", "zigzag_beds", "zigzag_bind_off_steps"]


@dataclass
class Emitter:
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
        self.join_tucks = 0

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
            ops.append(Op(Opcode.XFER, frm, n, to, n))
            self.bed[n] = to
        self.steps.append(Pass(PassKind.XFER, tuple(ops), None, (), 0.0, role, course))

    def knit(
        self,
        p: PlannedPass,
        *,
        role: Role,
        course: int | None,
        op: Opcode = Opcode.KNIT,
        extra: Sequence[Op] = (),
    ) -> None:
        """Emit a planned pass (hooking in a never-used carrier around it)."""
        new = [c for c in p.carriers if self.states.get(c, CarrierState()).needle is None]
        if p.kind == "move":
            n, _ = p.stitches[0]
            self.steps.append(
                Pass(
                    PassKind.KNIT,
                    (Op(Opcode.MISS, Bed.FRONT, n),),
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
            ops = tuple(
                Op(Opcode.TUCK if n in p.tucks else op, Bed(b), n) for n, b in p.stitches
            ) + tuple(extra)
            if not p.pretuck:
                self.join_tucks += len(p.tucks)
            if p.park is not None:
                ops += (Op(Opcode.MISS, Bed.FRONT, p.park),)
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


def cast_on(em: Emitter, segments: Sequence[Segment], *, park: Park | None) -> int:
    """Cast on each carrier of the first course over its own wales; returns the passes made.

    Each carrier comes in on the inserting hook and tuck-casts-on its wales
    (:func:`~illuknit.knit.edges.cast_on_steps`): alternate needles leftward from its rightmost
    wale, then (when parking) the hook is released and the other needles are tucked rightward,
    running on to park the carrier right of the fabric.
    """
    machine, left = em.machine, em.left
    edge = left + em.wales - 1
    cast_sn = machine.cast_on_stitch
    cast_fixed = 0
    for seg in segments:
        needles = [left + w for w in seg.wales]
        car = seg.carrier
        lone = len(needles) == 1
        if park is not None:
            # Release the hook after the leftward tucks: the rightward ones can then run on to
            # park the carrier right of the fabric, out of every other carrier's way (before the
            # release nothing may pass right of the hook). A lone wale has no rightward tucks:
            # its carrier parks left at once.
            steps = cast_on_steps(
                car,
                needles,
                left_end=park[0] if lone else needles[0] - 1,
                right_end=park[1],
                hook="between",
                stitch_number=cast_sn,
            )
        else:
            steps = cast_on_steps(
                car,
                needles,
                left_end=needles[0] - 1,
                right_end=None,
                hook="after",
                stitch_number=cast_sn,
            )
            if not lone and needles[-1] == edge:
                # As in the one-colour cast-on: once the hook is released, park the carrier
                # right of the fabric so that its first course starts leftward from behind.
                to = Op(Opcode.MISS, Bed.FRONT, edge + machine.park_distance)
                steps.append(Pass(PassKind.KNIT, (to,), "+", (car,), 0.0, Role.PARK, None, cast_sn))
        passes = [s for s in steps if isinstance(s, Pass)]
        em.steps.extend(steps)
        cast_fixed += len(passes)
        tucked = [op.needle for p in passes for op in p.ops if op.op is Opcode.TUCK]
        em.states[car] = CarrierState(passes[-1].ops[-1].needle, passes[-1].direction, tucked[-1])
    return cast_fixed


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


def bind_off(
    em: Emitter,
    last: CoursePlan,
    *,
    park: Park | None,
    catching: bool,
    path_planning: str,
    tail_stitches: int,
) -> int:
    """Bind off every wale; returns the passes it takes (carrier moves not counted).

    With parking and catching: the two-bed chain (:func:`zigzag_bind_off_steps`) in one yarn
    from where the last course ended. Otherwise a chain in the last course's colours (each
    needle knit by its run's carrier), or with catching off one chain per run, so that nothing
    the scheduler adds joins regions.
    """
    machine, left = em.machine, em.left
    edge = left + em.wales - 1
    bind_start = len(em.steps)
    one_yarn = catching and park is not None
    late: dict[int, str] = {}
    if one_yarn:
        car, d = _bind_off_start(em.states, left, edge)
        beds = zigzag_beds(d, left, edge)
        # The yarn runs from the carrier's last loop to the chain's first stitch: loops it
        # crosses wait on the front bed until that stitch is made (else it floats over them).
        last_loop = em.states[car].last_loop
        if last_loop is not None:
            lo, hi = sorted((last_loop, edge if d == "-" else left))
            late = {n: "b" for n in range(lo + 1, hi) if beds[n] is Bed.BACK}
    else:
        beds = {n: Bed.FRONT for n in em.needles}
    first_beds = {n: "f" if n in late else str(b) for n, b in beds.items()}
    em.xfer(
        {n: b for n, b in first_beds.items() if em.bed[n] != b}, role=Role.BIND_OFF, course=None
    )
    runs = sorted(
        ((lo, hi, s.carrier) for s in last.segments for lo, hi in s.runs), key=lambda r: r[0]
    )
    drops: list[int] = []
    if one_yarn and park is not None:
        # One chain in one yarn, as the one-colour scheduler binds off: started by the carrier
        # whose last loop is nearest an edge it is parked beyond (where the last course ended),
        # so no yarn floats across the piece into the bind-off. The others go out first.
        em.outhook([c for c in machine.carriers if c in em.states and c != car])
        st = em.states[car]
        if (d == "-") != (st.direction == "+"):
            target = park[1] if d == "-" else park[0]
            em.knit(
                PlannedPass((car,), flip(d), ((target, "f"),), "move"),
                role=Role.BIND_OFF,
                course=None,
            )
        chain = zigzag_bind_off_steps(
            car, d, left, edge, stitch_number=machine.stitch_number, tail_stitches=tail_stitches
        )
        em.steps.append(chain[0])
        em.xfer({n: b for n, b in late.items() if em.bed[n] != b}, role=Role.BIND_OFF, course=None)
        em.steps.extend(chain[1:])
        em.states.pop(car)
    elif catching:
        drops.append(
            _chain_bind_off(
                em, runs, runs[-1][2], path_planning=path_planning, tail_stitches=tail_stitches
            )
        )
    else:
        for lo, hi, car in runs:
            drops.append(
                _chain_bind_off(
                    em,
                    [(lo, hi, car)],
                    car,
                    path_planning=path_planning,
                    tail_stitches=tail_stitches,
                )
            )
    live = [c for c in machine.carriers if c in em.states]
    em.outhook(live)
    if drops:
        em.steps.append(
            Pass(
                PassKind.DROP,
                tuple(Op(Opcode.DROP, Bed.FRONT, n) for n in sorted(drops)),
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
    return bind_fixed


def _chain_bind_off(
    em: Emitter,
    run_list: list[tuple[int, int, str]],
    tail_carrier: str,
    *,
    path_planning: str,
    tail_stitches: int,
) -> int:
    """Chain-bind-off the wales of ``run_list`` (each needle knit by its run's carrier) on
    the front bed, then knit the tail on the last needle; returns that needle (to drop)."""
    left = em.left
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
            extra = (Op(Opcode.MISS, Bed.FRONT, n + 2),)
        em.knit(p, role=Role.BIND_OFF, course=None, extra=extra)
        em.steps.append(
            Pass(
                PassKind.XFER,
                (Op(Opcode.XFER, Bed.FRONT, n, Bed.BACK, n),),
                None,
                (),
                0.0,
                Role.BIND_OFF,
            )
        )
        em.steps.append(
            Pass(
                PassKind.XFER,
                (Op(Opcode.XFER, Bed.BACK, n, Bed.FRONT, n + 1),),
                None,
                (),
                1.0,
                Role.BIND_OFF,
            )
        )
    last = order[-1]
    for t in range(1 + tail_stitches):
        item = WorkItem((tail_carrier,), ((last, "f"),))
        ps = plan_item(item, em.states, strategy=path_planning, parity="+" if t % 2 else "-")
        for p in ps:
            em.knit(p, role=Role.TAIL if t else Role.BIND_OFF, course=None)
    return last


def zigzag_beds(direction: Direction, left: int, right: int) -> dict[int, Bed]:
    """Bed of each needle's loop for :func:`zigzag_bind_off_steps`: alternate from the start."""
    start = left if direction == "+" else right
    return {n: Bed.FRONT if (n - start) % 2 == 0 else Bed.BACK for n in range(left, right + 1)}


def zigzag_bind_off_steps(
    carrier: str,
    direction: Direction,
    left: int,
    right: int,
    *,
    stitch_number: int | None,
    tail_stitches: int = 4,
) -> list[Step]:
    """Chain bind-off of loops alternating between the beds (:func:`zigzag_beds`), two passes
    a needle; then a tail, ``outhook`` and a drop.

    The chain bind-off of :func:`~illuknit.knit.edges.bind_off_steps` moves each loop to the
    next needle on the same bed, which takes two transfers at two rackings (front -> back,
    back -> next front): three passes a needle, the larger part of a mixed-colourwork piece's
    passes. With the loops alternating between the beds, each step knits a needle and moves
    its loop across, at racking -/+1, straight onto the next needle's loop on the other bed:
    one transfer. The links knit on the back bed show as purls along the bound-off edge, as
    in a bind-off of 1x1 rib. ``carrier`` must sit beyond the edge it starts from (right of
    ``right`` for ``"-"``, left of ``left`` for ``"+"``); directions alternate, and every other
    step a miss carries the yarn past the next stitch so every stitch has the carrier behind
    the carriage.
    """
    order = list(range(left, right + 1)) if direction == "+" else list(range(right, left - 1, -1))
    shift = 1 if direction == "+" else -1
    beds = zigzag_beds(direction, left, right)
    steps: list[Step] = []
    d: Direction = direction
    for n, nxt in pairwise(order):
        chain = [Op(Opcode.KNIT, beds[n], n)]
        if d == direction:
            chain.append(Op(Opcode.MISS, Bed.FRONT, n + 2 * shift))
        steps.append(
            Pass(
                PassKind.KNIT, tuple(chain), d, (carrier,), 0.0, Role.BIND_OFF, None, stitch_number
            )
        )
        # back b k faces front f (k + r): f n -> b nxt needs r = n - nxt, b n -> f nxt the other
        rack = float(n - nxt) if beds[n] is Bed.FRONT else float(nxt - n)
        move = (Op(Opcode.XFER, beds[n], n, beds[nxt], nxt),)
        steps.append(Pass(PassKind.XFER, move, None, (), rack, Role.BIND_OFF))
        d = flip(d)
    last = order[-1]
    for _ in range(1 + tail_stitches):
        steps.append(
            Pass(
                PassKind.KNIT,
                (Op(Opcode.KNIT, beds[last], last),),
                d,
                (carrier,),
                0.0,
                Role.TAIL,
                None,
                stitch_number,
            )
        )
        d = flip(d)
    steps.append(CarrierAction(ActionKind.OUTHOOK, (carrier,)))
    steps.append(
        Pass(PassKind.DROP, (Op(Opcode.DROP, beds[last], last),), None, (), 0.0, Role.TAIL)
    )
    return steps
