"""The piece's two edges, shared by both schedulers: the tuck cast-on and the chain bind-off.

:func:`schedule_courses <illuknit.knit.schedule.schedule_courses>` casts on one carrier over
the whole width and :func:`cast_on <illuknit.knit.mixed_edges.cast_on>` casts on each carrier
of the first mixed course over its own wales; both lay the same two tuck passes
(:func:`cast_on_steps`) and differ only in where the passes end and when the inserting hook lets
go of the yarn end. Both bind off with :func:`bind_off_steps` when one yarn finishes the piece.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal

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
)

__all__ = ["HookRelease", "bind_off_steps", "cast_on_steps"]

#: When the cast-on lets the inserting hook release the yarn end: ``"between"`` the two tuck
#: passes (so the second may run on past the hook), ``"after"`` them, or ``"held"`` (the caller
#: releases it later, e.g. after the first plain course).
HookRelease = Literal["between", "after", "held"]


def cast_on_steps(
    carrier: str,
    needles: Sequence[int],
    *,
    left_end: int,
    right_end: int | None,
    hook: HookRelease,
    stitch_number: int | None,
) -> list[Step]:
    """``inhook`` and the alternating-tuck cast-on of ``carrier`` on ``needles``.

    The first pass tucks every other needle leftward from the rightmost one and ends with a
    ``miss`` on ``left_end`` (where the carrier waits, behind the carriage, for the second
    pass); the second tucks the other needles rightward and, unless ``right_end`` is None, ends
    with a ``miss`` on ``right_end``. A single needle takes one pass. ``hook`` says where the
    ``releasehook`` goes.

    Parameters
    ----------
    carrier : str
    needles : sequence of int
        The needles to cast on, ascending (need not be adjacent).
    left_end, right_end : int, int or None
        Where the leftward and the rightward pass leave the carrier.
    hook : {"between", "after", "held"}
    stitch_number : int or None
        ``x-stitch-number`` of both passes.

    Returns
    -------
    list of Step
    """
    down = list(needles)[::-1][0::2]
    up = sorted(set(needles) - set(down))
    tucks1 = (*(Op(Opcode.TUCK, Bed.FRONT, n) for n in down), Op(Opcode.MISS, Bed.FRONT, left_end))
    steps: list[Step] = [
        CarrierAction(ActionKind.INHOOK, (carrier,)),
        Pass(
            PassKind.KNIT, tucks1, "-", (carrier,), role=Role.CAST_ON, stitch_number=stitch_number
        ),
    ]
    release = CarrierAction(ActionKind.RELEASEHOOK, (carrier,))
    if hook == "between":
        steps.append(release)
    if up:
        tucks2 = tuple(Op(Opcode.TUCK, Bed.FRONT, n) for n in up)
        if right_end is not None:
            tucks2 += (Op(Opcode.MISS, Bed.FRONT, right_end),)
        steps.append(
            Pass(
                PassKind.KNIT,
                tucks2,
                "+",
                (carrier,),
                role=Role.CAST_ON,
                stitch_number=stitch_number,
            )
        )
    if hook == "after":
        steps.append(release)
    return steps


def bind_off_steps(
    carrier: str,
    direction: Direction,
    left: int,
    right: int,
    *,
    stitch_number: int | None,
    tail_stitches: int = 4,
) -> list[Step]:
    """Chain bind-off of front loops on needles left..right, then a tail, ``outhook`` and a drop.

    ``carrier`` must sit beyond the edge it starts from: right of ``right`` for ``direction``
    ``"-"``, left of ``left`` for ``"+"``. Each step knits a needle and moves its loop onto the
    next needle (front -> back at racking 0, back -> front at racking +/-1). Directions alternate;
    on every other step a miss carries the yarn one needle past the next stitch, so every stitch
    is made with the carrier behind the carriage and no kickback is needed.
    """
    order = list(range(left, right + 1)) if direction == "+" else list(range(right, left - 1, -1))
    shift = 1 if direction == "+" else -1
    steps: list[Step] = []
    d: Direction = direction
    for n in order[:-1]:
        chain = [Op(Opcode.KNIT, Bed.FRONT, n)]
        if d == direction:
            chain.append(Op(Opcode.MISS, Bed.FRONT, n + 2 * shift))
        steps.append(
            Pass(
                PassKind.KNIT, tuple(chain), d, (carrier,), 0.0, Role.BIND_OFF, None, stitch_number
            )
        )
        steps.append(
            Pass(
                PassKind.XFER,
                (Op(Opcode.XFER, Bed.FRONT, n, Bed.BACK, n),),
                None,
                (),
                0.0,
                Role.BIND_OFF,
            )
        )
        move = (Op(Opcode.XFER, Bed.BACK, n, Bed.FRONT, n + shift),)
        steps.append(Pass(PassKind.XFER, move, None, (), float(shift), Role.BIND_OFF))
        d = "-" if d == "+" else "+"
    last = order[-1]
    for _ in range(1 + tail_stitches):
        steps.append(
            Pass(
                PassKind.KNIT,
                (Op(Opcode.KNIT, Bed.FRONT, last),),
                d,
                (carrier,),
                0.0,
                Role.TAIL,
                None,
                stitch_number,
            )
        )
        d = "-" if d == "+" else "+"
    steps.append(CarrierAction(ActionKind.OUTHOOK, (carrier,)))
    steps.append(Pass(PassKind.DROP, (Op(Opcode.DROP, Bed.FRONT, last),), None, (), 0.0, Role.TAIL))
    return steps
