"""The mixed-colourwork scheduler's stages and its programs, checked by replay and the checker."""

from __future__ import annotations

from collections import defaultdict

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from illuknit.check import check_knitout
from illuknit.core.errors import CarrierShortageError, OptionError, PatternValidationError
from illuknit.core.machine import MachineSpec
from illuknit.core.pattern import LogicalPattern, Yarn
from illuknit.knit import Pass, lower_to_stitches, write_knitout
from illuknit.knit.catching import plan_catches
from illuknit.knit.color_runs import color_runs, plan_color_runs
from illuknit.knit.float_avoidance import float_crossings
from illuknit.knit.mixed import schedule_mixed
from illuknit.knit.move_folding import fold_moves
from illuknit.knit.options import KnitOptions
from illuknit.knit.path_planning import (
    CarrierState,
    PlannedPass,
    WorkItem,
    advance,
    is_behind,
    plan_item,
)
from illuknit.knit.schedule import CarrierAction, Op, count_kickbacks

YARNS = tuple(Yarn(f"y{i}", (i * 20, 255 - i * 20, 7 * i)) for i in range(12))


@st.composite
def mixed_patterns(draw, max_rows=5, max_cols=7):
    """Any small pattern: random yarn per unit (1-3 yarns), random bumps."""
    n = draw(st.integers(1, max_rows))
    m = draw(st.integers(2, max_cols))
    k = draw(st.integers(2, 3))
    cells = draw(st.lists(st.integers(0, k - 1), min_size=n * m, max_size=n * m))
    raised = draw(st.lists(st.booleans(), min_size=n * m, max_size=n * m))
    yarn = np.array(cells).reshape(n, m)
    return LogicalPattern(yarn, np.array(raised).reshape(n, m), YARNS[:k])


def replay(schedule, stitches) -> None:
    """Every body stitch is made exactly once, on its bed, with its yarn's carrier first."""
    made: dict[tuple[int, int], list[tuple[str, tuple[str, ...]]]] = defaultdict(list)
    for p in schedule.passes:
        if p.kind != "knit" or p.course is None or p.role != "body":
            continue
        for o in p.ops:
            if o.op == "knit":
                made[(p.course, o.needle - schedule.left)].append((o.bed, p.carriers))
    owner = {c: y for y, cs in schedule.carrier_of_yarn.items() for c in cs}
    c_count, w_count = stitches.shape
    assert len(made) == c_count * w_count
    for (c, w), got in made.items():
        assert len(got) == 1, (c, w, got)
        bed, cars = got[0]
        assert bed == ("b" if stitches.kind[c, w] else "f")
        assert owner[cars[0]] == stitches.yarn[c, w]
        assert len(cars) <= 2


# -- colour runs ------------------------------------------------------------------------------


def test_color_runs_are_maximal():
    assert color_runs([1, 1, 0, 0, 0, 1]) == [(0, 1, 1), (2, 4, 0), (5, 5, 1)]
    with pytest.raises(PatternValidationError):
        color_runs([])


def test_runs_within_the_float_limit_share_a_carrier_and_long_gaps_split_them():
    row = np.array([[0, 1, 1, 0, 1, 1, 1, 1, 1, 0]])
    plan = plan_color_runs(row, carriers=("1", "2", "3"), float_limit=2)
    segs = {s.yarn: [] for s in plan.courses[0].segments}
    for s in plan.courses[0].segments:
        segs[s.yarn].append(s.runs)
    # yarn 0: gap 2 (stranded), then gap 5 > 2 (a second, intarsia carrier)
    assert segs[0] == [((0, 0), (3, 3)), ((9, 9),)]
    assert segs[1] == [((1, 2), (4, 8))]
    assert all(s.longest_float <= 2 for s in plan.courses[0].segments)
    assert len(plan.carriers) == 3


def test_intarsia_carriers_keep_their_region_across_courses():
    rows = np.array([[0, 0, 1, 1, 1, 1, 1, 1, 0, 0]] * 3)
    plan = plan_color_runs(rows, carriers=("1", "2", "3", "4"), float_limit=3)
    firsts = [{s.lo: s.carrier for s in cp.segments} for cp in plan.courses]
    assert firsts[0] == firsts[1] == firsts[2]


def test_too_many_runs_for_the_carriers_is_a_clear_error_naming_the_course():
    row = np.array([[0, 1] * 3 + [0] * 30 + [1, 0] * 3])
    rows = np.vstack([np.zeros_like(row), row])
    with pytest.raises(CarrierShortageError) as e:
        plan_color_runs(
            rows, carriers=("1", "2"), float_limit=2, strict=True, course_names=["a", "row 7"]
        )
    msg = str(e.value)
    assert msg.startswith("row 7 needs") and "fewer yarns" in msg and "float limit" in msg
    assert e.value.course == 1 and e.value.available == 2 and e.value.needed == 3
    # by default the shortest gaps are bridged instead
    plan = plan_color_runs(rows, carriers=("1", "2"), float_limit=2)
    assert len(plan.courses[1].segments) == 2


def test_more_yarns_in_a_course_than_carriers_always_fails():
    with pytest.raises(CarrierShortageError, match="needs 4 carriers at once"):
        plan_color_runs(np.array([[0, 1, 2, 3]]), carriers=("1", "2", "3"), float_limit=20)


def test_a_yarn_arriving_when_every_carrier_is_threaded_is_named():
    rows = np.array([[0, 1, 2], [3, 3, 3]])
    with pytest.raises(CarrierShortageError, match="course 1 brings in yarn 3") as e:
        plan_color_runs(rows, carriers=("1", "2", "3"), float_limit=20)
    assert "uses 4 yarns but the machine has 3 carriers" in str(e.value)
    assert "--colors" in str(e.value) and "float_limit" not in str(e.value)


@pytest.mark.parametrize("limit", [0, -1, 1.5, True])
def test_float_limit_below_one_is_rejected(limit):
    with pytest.raises(OptionError, match="float_limit"):
        plan_color_runs(np.zeros((1, 3), int), carriers=("1",), float_limit=limit)
    with pytest.raises(OptionError, match="float_limit"):
        MachineSpec(float_limit=limit)


def test_machine_float_limit_of_zero_is_rejected():
    with pytest.raises(OptionError, match="float_limit"):
        MachineSpec(float_limit=0)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"path_planning": "zigzag"},
        {"catching": "no"},
        {"float_avoidance": None},
        {"catch_every": 0},
    ],
)
def test_bad_switches_are_rejected(kwargs):
    with pytest.raises(OptionError):
        KnitOptions(**kwargs)


def test_the_options_must_be_knit_options():
    s = lower_to_stitches(LogicalPattern(np.array([[0, 1]]), np.zeros((1, 2), bool), YARNS[:2]))
    with pytest.raises(OptionError, match="`options` must be a KnitOptions"):
        schedule_mixed(s, options={"catching": "plate"})  # type: ignore[arg-type]


# -- catching ---------------------------------------------------------------------------------


def test_catches_plate_the_intarsia_side_with_the_primary_first():
    rows = np.array([[0, 0, 0, 1, 1, 0, 0, 0]])
    plan = plan_color_runs(rows, carriers=("1", "2"), float_limit=5)
    cp = plan.courses[0]
    stranded = {s.yarn: s.carrier for s in cp.segments}
    got = plan_catches(cp)
    # both edges of the intarsia bar: its own carrier first, the stranded one second
    assert [p.wale for p in got] == [3, 4]
    assert all(p.carriers == (stranded[1], stranded[0]) for p in got)


def test_two_stranded_carriers_crossing_each_other_need_no_catch_between_them():
    rows = np.array([[0, 1, 0, 1, 0, 1]])
    cp = plan_color_runs(rows, carriers=("1", "2"), float_limit=3).courses[0]
    walls = [p.wale for p in plan_catches(cp)]
    assert 2 not in walls and 3 not in walls


# -- path planning ----------------------------------------------------------------------------


def test_position_rules_match_knitout():
    right_of_5 = CarrierState(5, "+", 5)
    assert is_behind(right_of_5, "+", 6) and not is_behind(right_of_5, "+", 5)
    assert is_behind(right_of_5, "-", 5) and not is_behind(right_of_5, "-", 6)


@pytest.mark.parametrize("strategy", ["anchor", "split"])
@pytest.mark.parametrize("anchor", range(0, 12))
@pytest.mark.parametrize("last", ["+", "-"])
def test_every_planned_stitch_finds_its_carrier_behind_and_alternating(strategy, anchor, last):
    item = WorkItem(("1",), tuple((n, "f") for n in range(2, 10)))
    states = {"1": CarrierState(anchor, last, anchor)}
    passes = plan_item(item, states, strategy=strategy, parity="+")
    knitted = []
    st_ = dict(states)
    for p in passes:
        s = st_["1"]
        assert p.direction != s.direction  # never twice the same way (no backend kickback)
        if p.kind == "knit":
            assert is_behind(s, p.direction, p.stitches[0][0])
            knitted += [n for n, _ in p.stitches]
        st_ = advance(st_, p)
    assert sorted(knitted) == list(range(2, 10))
    assert len(passes) <= 2


def test_plated_carriers_on_opposite_sides_get_an_anchoring_move():
    item = WorkItem(("1", "2"), ((5, "f"),), plated=True)
    states = {"1": CarrierState(2, "-", 2), "2": CarrierState(9, "+", 9)}
    passes = plan_item(item, states, strategy="anchor", parity="+")
    assert [p.kind for p in passes].count("move") == 1
    st_ = states
    for p in passes[:-1]:
        st_ = advance(st_, p)
    last = passes[-1]
    assert all(is_behind(st_[c], last.direction, 5) for c in ("1", "2"))


def test_float_crossings_cover_the_gap_from_the_last_loop():
    p = PlannedPass(("1",), "+", ((5, "f"), (9, "b")))
    got = float_crossings([p], {"1": CarrierState(1, "-", 1)}, needles=range(0, 20))
    assert got == [frozenset({2, 3, 4, 6, 7, 8})]


def test_moves_fold_into_the_previous_pass_of_their_carrier():
    steps = [
        CarrierAction("inhook", ("1",)),
        Pass("knit", (Op("knit", "f", 5), Op("knit", "f", 4)), "-", ("1",)),
        CarrierAction("releasehook", ("1",)),
        Pass("knit", (Op("knit", "f", 4), Op("knit", "f", 5)), "+", ("1",)),
        Pass("xfer", (Op("xfer", "f", 5, "b", 5),), None, ()),
        Pass("knit", (Op("miss", "f", 8),), "+", ("1",), role="anchor"),
    ]
    out = fold_moves(steps)
    assert len(out) == len(steps) - 1
    assert out[3].ops[-1] == Op("miss", "f", 8)
    assert count_kickbacks(out) == 0


# -- whole programs ---------------------------------------------------------------------------


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mixed_patterns())
def test_every_program_knits_every_stitch_once_and_passes_the_checker(pattern):
    stitches = lower_to_stitches(pattern)
    sch = schedule_mixed(stitches)
    replay(sch, stitches)
    stats = sch.stats
    assert stats.body_lower_bound <= stats.body_passes
    assert stats.lower_bound <= stats.passes
    report = check_knitout(write_knitout(sch), float_limit=500)
    assert report.ok, [f.to_dict() for f in report.blocking][:3]
    assert report.pieces == 1


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    mixed_patterns(max_rows=3, max_cols=5),
    st.sampled_from(["anchor", "split"]),
    st.integers(1, 3),
)
def test_both_path_strategies_and_any_catch_spacing_make_clean_programs(pattern, strategy, every):
    sch = schedule_mixed(
        lower_to_stitches(pattern),
        options=KnitOptions(path_planning=strategy, catch_every=every),
    )
    report = check_knitout(write_knitout(sch), float_limit=500)
    assert report.ok and report.pieces == 1


def test_catching_every_course_plates_twice_as_often():
    p = LogicalPattern(np.array([[0, 1, 1, 0]] * 3), np.zeros((3, 4), bool), YARNS[:2])
    s = lower_to_stitches(p)
    every = schedule_mixed(
        s, options=KnitOptions(catch_every=1, catching="plate")
    ).mixed.plated_stitches
    alternate = schedule_mixed(
        s, options=KnitOptions(catch_every=2, catching="plate")
    ).mixed.plated_stitches
    assert every == 2 * alternate > 0


def test_catching_every_course_tuck_joins_twice_as_often_and_never_plates_flat_fabric():
    p = LogicalPattern(np.array([[0, 1, 1, 0]] * 3), np.zeros((3, 4), bool), YARNS[:2])
    s = lower_to_stitches(p)
    every = schedule_mixed(s, options=KnitOptions(catch_every=1)).mixed
    alternate = schedule_mixed(s, options=KnitOptions(catch_every=2)).mixed
    assert every.tuck_joins == 2 * alternate.tuck_joins > 0
    assert every.plated_stitches == alternate.plated_stitches == 0


def test_carriers_enter_with_exactly_the_set_they_first_use():
    p = LogicalPattern(
        np.array([[0, 1, 1, 0], [0, 0, 0, 0], [1, 1, 0, 0]]), np.zeros((3, 4), bool), YARNS[:2]
    )
    sch = schedule_mixed(lower_to_stitches(p))
    first_use: dict[str, tuple[str, ...]] = {}
    hooked: dict[str, tuple[str, ...]] = {}
    for s in sch.steps:
        if isinstance(s, CarrierAction) and s.action == "inhook":
            for c in s.carriers:
                hooked[c] = s.carriers
        elif isinstance(s, Pass) and s.kind == "knit":
            for c in s.carriers:
                first_use.setdefault(c, s.carriers)
    assert first_use == hooked


@settings(max_examples=5, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mixed_patterns(max_rows=3, max_cols=5))
def test_random_programs_run_in_the_pypi_simulator(pattern):
    report = check_knitout(
        write_knitout(schedule_mixed(lower_to_stitches(pattern))), float_limit=500, simulate=True
    )
    assert report.ok and report.vm is not None and report.vm["ran"]
    assert report.vm["pieces"] == 1
    assert not [f for f in report.findings if f.source == "vm" and f.blocking]
