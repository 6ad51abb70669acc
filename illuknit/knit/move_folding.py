"""Fold carrier moves into passes: the last stage of the mixed-colourwork scheduler.

The scheduler places carriers with passes of ``miss`` operations (a carrier parked beyond an
edge, or brought back beside its last loop). Many of them only continue, in the same direction,
the pass the carrier last made: :func:`fold_moves` appends such a move to that pass instead,
and the extra carriage pass disappears.
"""

from __future__ import annotations

from collections.abc import Sequence

from illuknit.knit.ir import Bed, CarrierAction, Op, Opcode, Pass, Step

__all__ = ["fold_moves"]


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
                    (*ops, Op(Opcode.MISS, Bed.FRONT, target)),
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
