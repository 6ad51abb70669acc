"""The one-colour-per-course scheduler, checked by replaying its passes on a tiny machine model."""

from __future__ import annotations

from collections import defaultdict

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.core.errors import MachineRuleError, MixedColorworkError, OptionError, SchedulingError
from illuknit.core.machine import MachineSpec
from illuknit.core.pattern import LogicalPattern, Yarn
from illuknit.knit import (
    CarrierAction,
    Op,
    Pass,
    Schedule,
    estimate_knit_time,
    lower_to_stitches,
    schedule_courses,
)

YARNS = tuple(Yarn(f"y{i}", (i * 20, 255 - i * 20, 7 * i)) for i in range(12))


@st.composite
def single_view(draw, max_rows=7, max_cols=6):
    """Stripe rows (row r has yarn r % k) with any raised subset: every single-view illusion."""
    n = draw(st.integers(1, max_rows))
    m = draw(st.integers(1, max_cols))
    k = draw(st.integers(1, 3))
    stripe = draw(st.sampled_from([1, 2]))
    yarn = np.repeat(((np.arange(n) // stripe) % k)[:, None], m, axis=1)
    raised = np.array(draw(st.lists(st.booleans(), min_size=n * m, max_size=n * m))).reshape(n, m)
    return LogicalPattern(yarn, raised, YARNS[:k])


def replay(schedule: Schedule) -> dict:
    """Execute a schedule on a minimal model; assert machine and fabric invariants on the way.

    Returns which stitches each body course made: {(course, needle): (bed, carriers)}.
    """
    loops: dict[tuple[str, int], int] = defaultdict(int)
    pos: dict[str, float] = {}  # carrier -> logical position (n +/- 0.5)
    live: set[str] = set()
    pending: set[str] = set()  # announced by inhook, not yet used
    hook: str | None = None
    last_dir: dict[str, str] = {}
    made = {}
    rack = 0.0
    hook_slot = float("inf")
    for step in schedule.steps:
        if isinstance(step, CarrierAction):
            (c,) = step.carriers
            if step.action == "inhook":
                assert hook is None and c not in live
                hook, live = c, live | {c}
                hook_slot = float("inf")
                pending.add(c)
            elif step.action == "releasehook":
                assert hook == c and c not in pending, "release after the first stitch"
                hook = None
            elif step.action == "outhook":
                assert hook is None and c in live and c not in pending
                live.discard(c)
                pos.pop(c)
            continue
        rack = step.racking
        if step.kind == "knit":
            (c,) = step.carriers
            assert c in live
            assert last_dir.get(c) != step.direction, "same-direction passes cost a kickback"
            last_dir[c] = step.direction
            for op in step.ops:
                n = op.needle
                if hook is not None:
                    assert n < hook_slot, "nothing at or right of the hook"
                if op.op != "miss":
                    if c in pending:
                        assert step.direction == "-", "hooked yarn starts leftward"
                        pending.discard(c)
                        hook_slot = n + 1
                    else:
                        p = pos[c]
                        assert (p < n) if step.direction == "+" else (p > n), (
                            f"carrier {c} at {p} ahead of the carriage at {n} going {step.direction}"
                        )
                    if op.op == "knit":
                        assert loops[(op.bed, n)] > 0, f"knit on empty {op.bed}{n}"
                        loops[(op.bed, n)] = 1
                    else:
                        loops[(op.bed, n)] += 1
                    if step.role == "body":
                        key = (step.course, n)
                        assert key not in made
                        made[key] = (op.bed, step.carriers)
                pos[c] = n + (0.5 if step.direction == "+" else -0.5)
        elif step.kind == "xfer":
            for op in step.ops:
                front = op.needle if op.bed == "f" else op.to_needle
                back = op.to_needle if op.bed == "f" else op.needle
                assert front - back == rack
                assert loops[(op.bed, op.needle)] > 0, "transfer of nothing"
                loops[(op.to_bed, op.to_needle)] += loops.pop((op.bed, op.needle))
        else:
            for op in step.ops:
                loops.pop((op.bed, op.needle), None)
    assert not live, f"carriers left in: {live}"
    assert not any(loops.values()), "loops left on the needles"
    return made


@settings(max_examples=40, deadline=None)
@given(single_view())
def test_schedule_makes_every_stitch_once_on_the_right_bed_with_its_carrier(p):
    s = lower_to_stitches(p)
    sch = schedule_courses(s)
    made = replay(sch)
    c_n, w_n = s.shape
    assert len(made) == c_n * w_n
    for (c, n), (bed, carriers) in made.items():
        w = n - sch.left
        assert bed == ("b" if s.kind[c, w] else "f")
        assert carriers == sch.carrier_of_yarn[int(s.yarn[c, w])]


@settings(max_examples=40, deadline=None)
@given(single_view())
def test_pass_count_meets_the_lower_bound_and_transfers_only_where_needed(p):
    s = lower_to_stitches(p)
    sch = schedule_courses(s)
    st_ = sch.stats
    assert st_.passes == st_.lower_bound and st_.ratio == 1.0
    assert st_.kickbacks == 0
    changes = (np.diff(np.vstack([np.zeros((1, s.wales), np.uint8), s.kind]), axis=0) != 0).any(
        axis=1
    )
    assert st_.body_lower_bound == s.courses + int(changes.sum())
    body_xfers = [q for q in sch.passes if q.role == "transfer"]
    assert sorted(q.course for q in body_xfers) == np.flatnonzero(changes).tolist()
    # transfers move exactly the loops that change bed
    for q in body_xfers:
        prev = s.kind[q.course - 1] if q.course else np.zeros(s.wales, np.uint8)
        moved = sorted(o.needle - sch.left for o in q.ops)
        assert moved == np.flatnonzero(prev != s.kind[q.course]).tolist()


def test_purls_share_the_pass_of_their_front_neighbours():
    p = LogicalPattern(np.zeros((1, 3), int), np.array([[False, True, False]]), YARNS[:1])
    sch = schedule_courses(lower_to_stitches(p))
    (purl_pass,) = [q for q in sch.passes if q.role == "body" and q.course == 1]
    beds = [o.bed for o in purl_pass.ops if o.op == "knit"]
    assert sorted(beds) == ["b", "b", "f", "f", "f", "f"]


def test_each_course_is_knit_by_one_carrier_and_stripes_use_two():
    yarn = np.repeat((np.arange(6) % 2)[:, None], 4, axis=1)
    p = LogicalPattern(yarn, np.eye(6, 4, dtype=bool), YARNS[:2])
    sch = schedule_courses(lower_to_stitches(p))
    assert set(sch.carrier_of_yarn.values()) == {("1",), ("2",)}
    assert all(len(q.carriers) == 1 for q in sch.passes if q.kind == "knit")
    assert [a.action for a in sch.steps if isinstance(a, CarrierAction)].count("outhook") == 2


def test_mixed_color_course_needs_the_mixed_scheduler():
    p = LogicalPattern(np.array([[0, 0], [0, 1]]), np.zeros((2, 2), bool), YARNS[:2])
    with pytest.raises(MixedColorworkError, match="mixed-colourwork scheduler"):
        schedule_courses(lower_to_stitches(p))


def test_more_yarns_than_carriers_is_refused():
    n = 11
    p = LogicalPattern(
        np.repeat(np.arange(n)[:, None], 2, axis=1), np.zeros((n, 2), bool), YARNS[:n]
    )
    with pytest.raises(
        SchedulingError,
        match=r"11 yarns but the generic 540-needle V-bed \(SWG091N2 rules\) has 10 carriers",
    ):
        schedule_courses(lower_to_stitches(p))
    # a machine with more carriers takes it
    m = MachineSpec(carriers=tuple(str(i) for i in range(1, 13)))
    assert len(schedule_courses(lower_to_stitches(p, machine=m), machine=m).carrier_of_yarn) == 11


def test_wider_than_the_bed_is_refused_by_the_scheduler_too():
    p = LogicalPattern(np.zeros((2, 10), int), np.zeros((2, 10), bool), YARNS[:1])
    s = lower_to_stitches(p)
    with pytest.raises(SchedulingError, match="generic 20-needle V-bed"):
        schedule_courses(s, machine=MachineSpec(needles=20))


def test_ir_validation():
    with pytest.raises(SchedulingError, match="direction"):
        Pass("knit", (Op("knit", "f", 1),), None, ("1",))
    with pytest.raises(SchedulingError, match="advance"):
        Pass("knit", (Op("knit", "f", 1), Op("knit", "f", 2)), "-", ("1",))
    with pytest.raises(MachineRuleError, match="racking"):
        Pass("xfer", (Op("xfer", "f", 1, "b", 1),), racking=0.5)
    p = LogicalPattern(np.zeros((1, 1), int), np.zeros((1, 1), bool), YARNS[:1])
    sch = schedule_courses(lower_to_stitches(p))
    bad = Pass("xfer", (Op("xfer", "f", 3, "b", 3),), racking=1.0)
    with pytest.raises(MachineRuleError, match="not aligned") as err:
        Schedule(**{**sch.__dict__, "steps": (*sch.steps[:-1], bad, sch.steps[-1])})
    assert (err.value.needle, err.value.racking) == ("f3", 1.0)
    far = Pass("xfer", (Op("xfer", "f", 9, "b", 4),), racking=5.0)
    with pytest.raises(MachineRuleError, match=r"racking 5\.0 exceeds") as err:
        Schedule(**{**sch.__dict__, "steps": (*sch.steps, far)})
    assert err.value.racking == 5.0


def test_time_model_is_passes_times_span_plus_turns():
    p = LogicalPattern(np.zeros((2, 3), int), np.zeros((2, 3), bool), YARNS[:1])
    sch = schedule_courses(lower_to_stitches(p))
    t = estimate_knit_time(sch, seconds_per_needle=1.0, seconds_per_turn=0.0)
    spans = sum(q.needle_span[1] - q.needle_span[0] + 1 for q in sch.passes)
    assert t.seconds == spans == t.needles_crossed
    t2 = estimate_knit_time(sch, seconds_per_needle=0.0, seconds_per_turn=2.0)
    assert t2.seconds == 2.0 * (len(sch.passes) + sch.stats.hook_passes)
    # body course pass: 6 wales + 2 parking needles beyond the edge
    body = [q for q in sch.passes if q.role == "body"]
    assert all(q.needle_span[1] - q.needle_span[0] + 1 == 6 + 2 for q in body)
    with pytest.raises(OptionError):
        estimate_knit_time(sch, seconds_per_turn=-1)


def test_kickbacks_count_same_direction_passes_per_carrier():
    p = LogicalPattern(np.zeros((1, 1), int), np.zeros((1, 1), bool), YARNS[:1])
    sch = schedule_courses(lower_to_stitches(p))
    again = Pass("knit", (Op("knit", "f", 3),), sch.passes[-3].direction, ("1",))
    steps = list(sch.steps)
    steps.insert(-3, again)  # repeat the direction of the pass before it
    assert Schedule(**{**sch.__dict__, "steps": tuple(steps)}).stats.kickbacks == 1
