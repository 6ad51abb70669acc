"""Tuck joins: colour regions join by a tuck that always ends up behind a face stitch."""

from __future__ import annotations

from dataclasses import replace
from itertools import pairwise

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from illuknit.check import check_knitout
from illuknit.core.machine import MachineSpec
from illuknit.knit.catching import JoinTuck, _boundaries, plan_catches, plan_joins
from illuknit.knit.color_runs import CoursePlan, Segment
from illuknit.knit.course_order import course_items, order_and_plan
from illuknit.knit.ir import Bed, CarrierAction, Opcode, Pass, PassKind, Role
from illuknit.knit.path_planning import CarrierState
from illuknit.knitting import knit_pattern
from tests.knit.test_float_tucks import _random_mixed


def _join_tuck_fates(steps) -> list[tuple[Bed, Bed | None]]:
    """For every body tuck on the front bed (a tuck join): the bed it was made on and the bed of
    the stitch that pulled it through (None if nothing did), tracking loops through transfers."""
    held: dict[tuple[Bed, int], list[int]] = {}
    fate: dict[int, Bed | None] = {}
    rack = 0.0
    ids = 0
    for s in steps:
        if isinstance(s, CarrierAction):
            continue
        rack = s.racking
        for o in s.ops:
            key = (o.bed, o.needle)
            if o.op in (Opcode.XFER, Opcode.SPLIT) and s.kind is PassKind.XFER:
                assert o.to_bed is not None and o.to_needle is not None
                held.setdefault((o.to_bed, o.to_needle), []).extend(held.pop(key, []))
            elif o.op is Opcode.KNIT:
                for loop in held.pop(key, []):
                    if loop in fate and fate[loop] is None:
                        fate[loop] = o.bed
                ids += 1
                held[key] = [ids]
            elif o.op is Opcode.TUCK:
                ids += 1
                held.setdefault(key, []).append(ids)
                if s.role is Role.BODY and o.bed is Bed.FRONT:
                    fate[ids] = None
                    assert rack == 0
            elif o.op is Opcode.DROP:
                held.pop(key, None)
    return [(Bed.FRONT, b) for b in fate.values()]


def _plan(runs: list[tuple[str, list[tuple[int, int]]]]) -> CoursePlan:
    segs = [Segment(c, i, tuple(r)) for i, (c, r) in enumerate(runs)]
    return CoursePlan(0, tuple(sorted(segs, key=lambda s: s.lo)))


def test_two_intarsia_regions_join_by_one_tuck_of_the_left_carrier():
    cp = _plan([("1", [(0, 3)]), ("2", [(4, 7)])])
    tucks, plated = plan_joins(cp, knit_now=[True] * 8, knit_next=[True] * 8)
    assert tucks == [JoinTuck(4, "1")] and plated == []


def test_a_purl_next_course_moves_the_tuck_to_the_other_edge_or_falls_back_to_plating():
    cp = _plan([("1", [(0, 3)]), ("2", [(4, 7)])])
    nxt = [True] * 8
    nxt[4] = False  # wale 4 is purled next course: a tuck there would show in the bump
    tucks, plated = plan_joins(cp, knit_now=[True] * 8, knit_next=nxt)
    assert tucks == [JoinTuck(3, "2")] and plated == []
    nxt[3] = False  # both edge needles purl next: with no ordered tuck, plate (Algorithm 2)
    tucks, plated = plan_joins(cp, knit_now=[True] * 8, knit_next=nxt, ordered=False)
    assert tucks == [] and plated == plan_catches(cp)


@st.composite
def _random_courses(draw) -> tuple[CoursePlan, list[bool], list[bool]]:
    """A 12-wale course cut into runs of up to three carriers (touching runs of one carrier
    merged), and which wales knit this course and the next."""
    cuts = draw(st.lists(st.integers(1, 11), min_size=1, max_size=4, unique=True))
    owners = draw(st.lists(st.sampled_from("123"), min_size=5, max_size=5))
    runs: dict[str, list[tuple[int, int]]] = {}
    for k, (a, b) in enumerate(pairwise([0, *sorted(cuts), 12])):
        runs.setdefault(owners[k], []).append((a, b - 1))
    cp = _plan([(c, _merge(r)) for c, r in runs.items()])
    now = draw(st.lists(st.booleans(), min_size=12, max_size=12))
    nxt = draw(st.lists(st.booleans(), min_size=12, max_size=12))
    return cp, now, nxt


@settings(max_examples=60, deadline=None)
@given(course=_random_courses())
def test_tucks_only_on_safe_wales_and_plating_only_where_no_tuck_is_safe(course):
    cp, now, nxt = course
    tucks, plated = plan_joins(cp, knit_now=now, knit_next=nxt, ordered=False)
    assert len({t.wale for t in tucks}) == len(tucks)
    owner = {w: s.carrier for s in cp.segments for w in s.wales}
    for t in tucks:
        assert now[t.wale] and nxt[t.wale]  # knit now and next: the tuck hides behind a face stitch
        assert owner[t.wale] != t.carrier  # on the neighbour's needle
    # every boundary is joined by a tuck on one of its edge wales, or plated where neither
    # edge wale was safe (or it was taken by another boundary's tuck)
    assert len(plated) <= len(_boundaries(cp)) - len(tucks)
    at = {t.wale: t for t in tucks}
    for hi, lo, left, right, _, _ in _boundaries(cp):
        tucked = (lo in at and at[lo].carrier == left) or (hi in at and at[hi].carrier == right)
        if not tucked:
            assert not any(now[w] and nxt[w] and w not in at for w in (hi, lo))


def _merge(runs: list[tuple[int, int]]) -> list[tuple[int, int]]:
    out: list[tuple[int, int]] = []
    for lo, hi in sorted(runs):
        if out and lo == out[-1][1] + 1:
            out[-1] = (out[-1][0], hi)
        else:
            out.append((lo, hi))
    return out


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10_000))
def test_every_tuck_join_is_knit_through_by_a_face_stitch_and_the_piece_holds(seed):
    pattern, limit = _random_mixed(seed)
    m = replace(MachineSpec(), float_limit=limit)
    result = knit_pattern(pattern, machine=m)
    fates = _join_tuck_fates(result.schedule.steps)
    # never on a back needle, always pulled through by a front (face) stitch
    assert all(made is Bed.FRONT and through is Bed.FRONT for made, through in fates)
    report = check_knitout(result.text, machine=m)
    assert not report.blocking, report.blocking[:3]
    assert report.pieces == 1


def test_tuck_joins_replace_plated_passes_on_a_two_colour_block():
    yarn = np.zeros((6, 16), np.int16)
    yarn[:, 8:] = 1
    from illuknit.core.pattern import LogicalPattern, parse_yarns

    pattern = LogicalPattern(yarn, np.zeros(yarn.shape, bool), parse_yarns("#1b1b1b,#f4f0e8"))
    tuck = knit_pattern(pattern)
    plate = knit_pattern(pattern, catching="plate")
    assert tuck.schedule.mixed.tuck_joins > 0 and tuck.schedule.mixed.plated_stitches == 0
    assert plate.schedule.mixed.plated_stitches > 0
    assert tuck.stats.passes < plate.stats.passes
    assert tuck.stats.lower_bound < plate.stats.lower_bound
    assert not any(
        isinstance(s, Pass) and s.kind is PassKind.KNIT and len(s.carriers) > 1
        for s in tuck.schedule.steps
    )
    assert check_knitout(tuck.text).pieces == 1


def test_a_wale_purled_next_course_takes_a_tuck_made_before_its_knit():
    cp = _plan([("1", [(0, 3)]), ("2", [(4, 7)])])
    nxt = [True] * 8
    nxt[3] = nxt[4] = False  # both edge wales purl next course
    tucks, plated = plan_joins(cp, knit_now=[True] * 8, knit_next=nxt)
    assert tucks == [JoinTuck(4, "1", first=True)] and plated == []
    # the tuck's item comes before the item knitting wale 4
    items = course_items([("1", [0, 1, 2, 3]), ("2", [4, 5, 6, 7])], plated, ["f"] * 8, 10, tucks)
    assert [(it.carriers, it.follows) for it in items] == [
        (("1",), frozenset()),
        (("2",), frozenset({"1"})),
    ]
    order, _ = order_and_plan(items, {}, "anchor", "-")
    assert order[0].carriers == ("1",) and 14 in order[0].tucks


@settings(max_examples=60, deadline=None)
@given(course=_random_courses())
def test_ordered_tucks_never_plate_more_and_never_order_in_a_cycle(course):
    cp, now, nxt = course
    tucks, plated = plan_joins(cp, knit_now=now, knit_next=nxt)
    _, plated_unordered = plan_joins(cp, knit_now=now, knit_next=nxt, ordered=False)
    assert len(plated) <= len(plated_unordered)
    assert all(now[t.wale] and (t.first or nxt[t.wale]) for t in tucks)
    items = course_items([(s.carrier, s.wales) for s in cp.segments], plated, ["f"] * 12, 0, tucks)
    knitted = {c: CarrierState(30, "+", 11) for c in "123"}  # (plated pairs need both knit)
    order_and_plan(items, knitted, "anchor", "-")  # an order exists: the tucks' orders are acyclic
