"""The mixed-colourwork bind-off: a chain across both beds, two passes a needle."""

from __future__ import annotations

from itertools import pairwise

import numpy as np
import pytest

from illuknit.check import check_knitout
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.knit.ir import Bed, Opcode, Pass, PassKind, Role
from illuknit.knit.mixed_edges import zigzag_beds, zigzag_bind_off_steps
from illuknit.knitting import knit_pattern


@pytest.mark.parametrize("direction", ["+", "-"])
def test_each_loop_moves_onto_the_next_needle_on_the_other_bed_in_one_transfer(direction):
    steps = zigzag_bind_off_steps("3", direction, 5, 14, stitch_number=None, tail_stitches=2)
    passes = [s for s in steps if isinstance(s, Pass)]
    chain = [s for s in passes if s.role is Role.BIND_OFF]
    knits = [s for s in chain if s.kind is PassKind.KNIT]
    xfers = [s for s in chain if s.kind is PassKind.XFER]
    assert len(knits) == len(xfers) == 9  # two passes for each needle but the last
    order = list(range(5, 15)) if direction == "+" else list(range(14, 4, -1))
    beds = zigzag_beds(direction, 5, 14)
    assert [beds[n] for n in order] == [Bed.FRONT, Bed.BACK] * 5
    for k, x in zip(knits, xfers, strict=True):
        stitch = k.ops[0]
        move = x.ops[0]
        assert stitch.op is Opcode.KNIT and (stitch.bed, stitch.needle) == (move.bed, move.needle)
        assert move.to_bed is not stitch.bed
        assert move.to_needle == order[order.index(stitch.needle) + 1]
        # aligned at the pass's racking: back needle b k faces front needle f (k + racking)
        back, front = (
            (move.to_needle, move.needle)
            if move.bed is Bed.FRONT
            else (move.needle, move.to_needle)
        )
        assert back + x.racking == front
    # directions alternate, so the carrier never needs a kickback
    assert all(a.direction != b.direction for a, b in pairwise(knits))


def test_a_mixed_piece_binds_off_in_two_passes_a_wale_and_holds_together():
    yarn = np.zeros((4, 12), np.int16)
    yarn[:, 6:] = 1
    raised = np.zeros(yarn.shape, bool)
    raised[0, ::3] = True
    pattern = LogicalPattern(yarn, raised, parse_yarns("#1b1b1b,#f4f0e8"))
    result = knit_pattern(pattern)
    wales = result.stitches.shape[1]
    chain = [
        s
        for s in result.schedule.steps
        if isinstance(s, Pass) and s.role is Role.BIND_OFF and not s.is_move
    ]
    assert len(chain) <= 2 * wales + 1  # one transfer pass sets the beds up
    report = check_knitout(result.text)
    assert report.ok and report.pieces == 1
