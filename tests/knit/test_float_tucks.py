"""Long floats are tucked onto free back needles and the tucks caught at once."""

from __future__ import annotations

from dataclasses import replace
from itertools import pairwise

import numpy as np

from illuknit.check import check_knitout
from illuknit.check.parse import parse_knitout
from illuknit.check.simulate import simulate_program
from illuknit.knit import MachineSpec, knit_pattern
from illuknit.knit.float_tucks import tuck_long_floats
from illuknit.knit.ir import Bed, CarrierAction, Op, OpKind, Pass, PassKind
from illuknit.pattern import LogicalPattern, parse_yarns

YARNS = parse_yarns("#1b1b1b,#f4f0e8")


def knit(needles, d, car="1"):
    return Pass(PassKind.KNIT, tuple(Op(OpKind.KNIT, Bed.FRONT, n) for n in needles), d, (car,))


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
    tucks = [o.needle for o in p.ops if o.op is OpKind.TUCK]
    loops = [o.needle for o in p.ops if o.op in (OpKind.KNIT, OpKind.TUCK)]
    assert tucks and all(o.bed is Bed.BACK for o in p.ops if o.op is OpKind.TUCK)
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
