"""Long floats are tucked onto free back needles and the tucks caught at once."""

from __future__ import annotations

from dataclasses import replace
from itertools import pairwise

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from illuknit.check import check_knitout
from illuknit.check.simulate import simulate_program
from illuknit.core.machine import MachineSpec
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.knit.float_tucks import tuck_long_floats
from illuknit.knit.ir import Bed, CarrierAction, Op, Opcode, Pass, PassKind
from illuknit.knitout.parse import parse_knitout
from illuknit.knitting import knit_pattern

YARNS = parse_yarns("#1b1b1b,#f4f0e8")


def knit(needles, d, car="1"):
    return Pass(PassKind.KNIT, tuple(Op(Opcode.KNIT, Bed.FRONT, n) for n in needles), d, (car,))


def test_a_gap_in_a_pass_gets_tucks_at_most_limit_apart_then_moved_front():
    steps = [
        CarrierAction("inhook", ("1",)),
        knit(range(30, 0, -1), "-"),
        CarrierAction("releasehook", ("1",)),
        knit([1, 2, 30], "+"),  # floats 27 needles from 2 to 30
    ]
    out, long = tuck_long_floats(steps, limit=10, left=1, right=30)
    assert not long
    p = out[-2]
    tucks = [o.needle for o in p.ops if o.op is Opcode.TUCK]
    loops = [o.needle for o in p.ops if o.op in (Opcode.KNIT, Opcode.TUCK)]
    assert tucks and all(o.bed is Bed.BACK for o in p.ops if o.op is Opcode.TUCK)
    assert all(b - a - 1 <= 10 for a, b in pairwise(loops))
    back = out[-1]
    assert back.kind is PassKind.XFER
    assert sorted((o.needle, o.to_bed) for o in back.ops) == [(t, Bed.FRONT) for t in sorted(tucks)]


def test_no_free_needle_leaves_the_float_reported():
    steps = [
        CarrierAction("inhook", ("1",)),
        knit(range(30, 0, -1), "-"),
        CarrierAction("releasehook", ("1",)),
        knit([1, 2, 30], "+"),
    ]
    out, long = tuck_long_floats(steps, limit=10, left=28, right=30)  # no room to tuck
    assert len(long) == 1 and long[0].length == 27 and out == steps


def test_stranded_pattern_keeps_floats_within_the_limit_and_knits_clean():
    # two colours in wide stripes: one carrier per yarn floats across the other's stripe
    yarn = np.zeros((6, 24), np.int16)
    yarn[:, 8:16] = 1
    pattern = LogicalPattern(yarn, np.zeros(yarn.shape, bool), YARNS)
    m = replace(MachineSpec(), float_limit=8)
    result = knit_pattern(pattern, machine=m)
    sim = simulate_program(parse_knitout(result.text))
    longest = max(f.length for f in sim.floats)
    assert longest <= m.float_limit or result.schedule.long_floats
    assert max((f.length for f in result.schedule.long_floats), default=0) == (
        longest if longest > m.float_limit else 0
    )
    report = check_knitout(result.text, machine=m)
    assert report.ok and report.pieces == 1


def test_a_plated_pass_whose_other_yarn_comes_from_elsewhere_gets_a_tuck_pass_of_its_own():
    # carrier 1 ends at 30 and carrier 2 at 5, both moving right; the plated leftward stitch at
    # 2 floats carrier 1 across the piece. Tucks in the plated pass would tuck carrier 2 too,
    # outside its own short float (5 -> 2), so carrier 1 tucks alone first.
    steps = [
        CarrierAction("inhook", ("1",)),
        knit(range(30, 0, -1), "-", "1"),
        CarrierAction("releasehook", ("1",)),
        CarrierAction("inhook", ("2",)),
        knit(range(6, 3, -1), "-", "2"),
        CarrierAction("releasehook", ("2",)),
        knit(range(1, 31), "+", "1"),  # carrier 1 ends at 30, parked right
        knit([5], "+", "2"),
        Pass(PassKind.KNIT, (Op(Opcode.KNIT, Bed.FRONT, 2),), "-", ("1", "2")),
    ]
    out, long = tuck_long_floats(steps, limit=10, left=1, right=30, alone=True)
    assert not long
    alone = [
        s
        for s in out
        if isinstance(s, Pass)
        and s.kind is PassKind.KNIT
        and all(o.op is Opcode.TUCK for o in s.ops)
    ]
    assert alone and all(len(s.carriers) == 1 for s in alone)
    # every tuck is moved to the front right after the plated pass
    plated = next(k for k, s in enumerate(out) if isinstance(s, Pass) and len(s.carriers) == 2)
    back = out[plated + 1]
    assert back.kind is PassKind.XFER
    tucked = {o.needle for s in out if isinstance(s, Pass) for o in s.ops if o.op is Opcode.TUCK}
    assert {o.needle for o in back.ops} == tucked


def _random_mixed(seed: int) -> tuple[LogicalPattern, int]:
    """A small mixed pattern: 2-3 yarns in random blocks, random purls; and a float limit."""
    rng = np.random.default_rng(seed)
    n_yarns, wales, rows = (
        int(rng.integers(2, 4)),
        int(rng.integers(12, 40)),
        int(rng.integers(2, 7)),
    )
    yarn = np.zeros((rows, wales), np.int16)
    for _ in range(int(rng.integers(1, 5))):
        r0 = int(rng.integers(0, rows))
        c0 = int(rng.integers(0, wales))
        yarn[r0 : int(rng.integers(r0, rows)) + 1, c0 : int(rng.integers(c0, wales)) + 1] = (
            rng.integers(0, n_yarns)
        )
    raised = rng.random(yarn.shape) < 0.2
    yarns = parse_yarns("#1b1b1b,#f4f0e8,#cc2222")[: max(n_yarns, 2)]
    return LogicalPattern(yarn, raised, yarns), int(rng.integers(4, 12))


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10_000))
def test_random_mixed_patterns_report_every_long_float_and_check_clean(seed):
    # The program's floats measured by the checker's simulator: every float over the limit is
    # one the scheduler lists (same length, same carrier), and tucking breaks nothing.
    pattern, limit = _random_mixed(seed)
    m = replace(MachineSpec(), float_limit=limit)
    result = knit_pattern(pattern, machine=m)
    sim = simulate_program(parse_knitout(result.text))
    over = sorted((f.length, f.carrier) for f in sim.floats if f.length > limit)
    listed = sorted((f.length, f.carrier) for f in result.schedule.long_floats)
    assert over == listed
    report = check_knitout(result.text, machine=m)
    assert not report.blocking, report.blocking[:3]


def test_without_tuck_passes_the_plated_float_stays_and_is_reported():
    steps = [
        CarrierAction("inhook", ("1",)),
        knit(range(30, 0, -1), "-", "1"),
        CarrierAction("releasehook", ("1",)),
        CarrierAction("inhook", ("2",)),
        knit(range(6, 3, -1), "-", "2"),
        CarrierAction("releasehook", ("2",)),
        knit(range(1, 31), "+", "1"),
        knit([5], "+", "2"),
        Pass(PassKind.KNIT, (Op(Opcode.KNIT, Bed.FRONT, 2),), "-", ("1", "2")),
    ]
    out, long = tuck_long_floats(steps, limit=10, left=1, right=30)
    assert out == steps
    assert [(f.carrier, f.from_needle, f.to_needle, f.length) for f in long] == [("1", 30, 2, 27)]


def _way_out_past_purls(purls: range, *, purls_back_first: bool = False) -> list:
    """Carrier 1 knits 1-30, moves ``purls`` to the back bed, knits 1-2 rightward and parks at
    40, then knits 30 leftward: its yarn is laid from 2 to 30 on the way out, past the purls.
    ``purls_back_first``: float avoidance has moved the purls to the front before that knit."""
    to_back = Pass(PassKind.XFER, tuple(Op(Opcode.XFER, Bed.FRONT, n, Bed.BACK, n) for n in purls))
    out_and_park = Pass(
        PassKind.KNIT,
        (Op(Opcode.KNIT, Bed.FRONT, 1), Op(Opcode.KNIT, Bed.FRONT, 2), Op(Opcode.MISS, "f", 40)),
        "+",
        ("1",),
    )
    back = Pass(PassKind.XFER, tuple(Op(Opcode.XFER, Bed.BACK, n, Bed.FRONT, n) for n in purls))
    return [
        CarrierAction("inhook", ("1",)),
        knit(range(30, 0, -1), "-"),
        CarrierAction("releasehook", ("1",)),
        to_back,
        out_and_park,
        *([back] if purls_back_first else []),
        knit([30], "-"),
    ]


def test_a_float_laid_on_the_way_out_past_purls_is_tucked_with_the_purls_moved_around_it():
    # carrier 1 knits 1-2 rightward and parks at 40; it next knits 30 leftward, so the yarn is
    # laid from 2 to 30 on the way out, past purls held on back needles 20-25.
    purls = range(20, 26)
    steps = _way_out_past_purls(purls)
    out, long = tuck_long_floats(steps, limit=10, left=1, right=30)
    assert not long
    k = next(i for i, s in enumerate(out) if isinstance(s, Pass) and s.direction == "+")
    before, tucking, after = out[k - 1], out[k], out[k + 1]
    assert before.kind is PassKind.XFER
    assert {(o.needle, o.to_bed) for o in before.ops} == {(n, Bed.FRONT) for n in purls}
    tucks = {o.needle for o in tucking.ops if o.op is Opcode.TUCK}
    assert tucks and not tucks & set(purls)
    assert {(o.needle, o.to_bed) for o in after.ops} == {
        *((t, Bed.FRONT) for t in tucks),
        *((n, Bed.BACK) for n in purls),
    }


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10_000), wide=st.booleans())
def test_every_generated_mixed_program_keeps_its_floats_within_the_limit(seed, wide):
    pattern, limit = _random_mixed(seed)
    m = replace(MachineSpec(), float_limit=20 if wide else limit)
    result = knit_pattern(pattern, machine=m)
    sim = simulate_program(parse_knitout(result.text))
    assert max((f.length for f in sim.floats), default=0) <= m.float_limit
    assert not result.schedule.long_floats


def test_a_way_out_blocked_by_purls_comes_back_and_tucks_alone_before_the_far_stitch():
    # carrier 1 knits 1-2 rightward and parks at 40; every needle it passes on the way out holds
    # a purl on the back bed, so nothing can be tucked there. Float avoidance moves those purls
    # to the front before the pass knitting 30: the carrier then comes back beside its last loop
    # and tucks alone on its way to 30.
    purls = range(3, 30)
    steps = _way_out_past_purls(purls, purls_back_first=True)
    out, long = tuck_long_floats(steps, limit=10, left=1, right=30)
    assert not long
    move, tucking, far, back = out[-4:]
    assert move.is_move and move.direction == "-" and move.ops[0].needle == 3
    assert tucking.direction == "+" and tucking.ops[-1].op is Opcode.MISS
    tucks = [o.needle for o in tucking.ops if o.op is Opcode.TUCK]
    assert tucks and all(o.bed is Bed.BACK for o in tucking.ops if o.op is Opcode.TUCK)
    assert all(b - a - 1 <= 10 for a, b in pairwise([2, *tucks, 30]))
    assert far == steps[-1] and back.kind is PassKind.XFER
    assert {o.needle for o in back.ops} == set(tucks)
