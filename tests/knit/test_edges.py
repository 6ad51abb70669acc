"""The shared tuck cast-on: every needle tucked once, leftward pass first, the hook where asked."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from illuknit.knit.edges import cast_on_steps
from illuknit.knit.ir import ActionKind, CarrierAction, Opcode, Pass, PassKind, Role


@given(
    needles=st.lists(st.integers(0, 40), min_size=1, max_size=20, unique=True).map(sorted),
    hook=st.sampled_from(["between", "after", "held"]),
    right_end=st.one_of(st.none(), st.integers(41, 50)),
)
def test_cast_on_tucks_each_needle_once_and_places_the_hook_release(needles, hook, right_end):
    steps = cast_on_steps(
        "3", needles, left_end=-5, right_end=right_end, hook=hook, stitch_number=7
    )
    assert steps[0] == CarrierAction(ActionKind.INHOOK, ("3",))
    passes = [s for s in steps if isinstance(s, Pass)]
    assert len(passes) == (1 if len(needles) == 1 else 2)
    assert all(p.kind is PassKind.KNIT and p.role is Role.CAST_ON for p in passes)
    assert all(p.stitch_number == 7 and p.carriers == ("3",) for p in passes)
    tucks = [(p.direction, op.needle) for p in passes for op in p.ops if op.op is Opcode.TUCK]
    assert sorted(n for _, n in tucks) == needles  # every needle exactly once
    down = [n for d, n in tucks if d == "-"]
    up = [n for d, n in tucks if d == "+"]
    assert down == needles[::-1][0::2] and up == sorted(set(needles) - set(down))
    # the leftward pass leaves the carrier at left_end; the rightward at right_end (or last tuck)
    assert passes[0].direction == "-" and passes[0].ops[-1].op is Opcode.MISS
    assert passes[0].ops[-1].needle == -5
    if len(passes) == 2:
        last = passes[1].ops[-1]
        assert (last.op, last.needle) == (
            (Opcode.TUCK, up[-1]) if right_end is None else (Opcode.MISS, right_end)
        )
    releases = [i for i, s in enumerate(steps) if getattr(s, "action", None) == "releasehook"]
    where = {"held": [], "after": [len(steps) - 1], "between": [2]}[hook]
    assert releases == where


@pytest.mark.parametrize("hook", ["between", "after", "held"])
def test_a_lone_needle_is_one_leftward_pass(hook):
    steps = cast_on_steps("1", [4], left_end=1, right_end=9, hook=hook, stitch_number=None)
    assert [type(s) for s in steps].count(Pass) == 1
