"""Short floats: tuck long floats onto free back-bed needles (a machine knitter's float catch).

A *float* is the yarn between two consecutive loops of one carrier. Stranded colourwork floats
across other colours' runs, and a carrier whose colour region moves between courses floats from
its last loop to its next one; anything longer than ``MachineSpec.float_limit`` snags. Machine
knitters cut such floats with *tucks on the back bed*: the floating yarn is tucked onto empty
back needles at intervals, which holds it against the fabric's technical back.

:func:`tuck_long_floats` does this on a finished step list (any scheduler's). For every float
longer than the limit it finds the carriage pass that lays the yarn across the gap -- the pass
that makes the far loop when the carrier travels towards it, or else the carrier's previous pass
on its way out to its parking needle -- and adds tucks on back needles inside the gap, at most
``limit`` needles apart, choosing needles whose back bed is empty at that moment and that the
pass does not otherwise use. Right after that pass one transfer pass moves those tuck loops onto
the front needles (``xfer b n f n``), where the next stitch on the needle knits through them: the
tuck is caught into the fabric and sits behind the face stitch, and no loop is left on the back
bed for another carrier's float to cross in front of. Each pass that tucks therefore costs one
transfer pass.

A float the pass that lays it cannot reach (a racked pass, no free needle in a stretch longer
than the limit) stays long; :func:`tuck_long_floats` reports it, and the caller decides whether
that is an error.
"""

from __future__ import annotations

from bisect import bisect_right
from collections.abc import Sequence
from dataclasses import dataclass, replace

from illuknit.knit.ir import ActionKind, Bed, CarrierAction, Op, OpKind, Pass, PassKind, Role, Step

__all__ = ["LongFloat", "tuck_long_floats"]


@dataclass(frozen=True)
class LongFloat:
    """A float that could not be tucked: ``carrier`` crosses ``length`` needles after ``step``."""

    step: int
    carrier: str
    from_needle: int
    to_needle: int
    course: int | None

    @property
    def length(self) -> int:
        return abs(self.to_needle - self.from_needle) - 1


_LOOPS = (OpKind.KNIT, OpKind.TUCK, OpKind.SPLIT)


def _tuck_needles(a: int, b: int, limit: int, free: set[int]) -> list[int] | None:
    """Needles strictly between ``a`` and ``b`` cutting the float into pieces of <= ``limit``.

    Greedy from ``a``: each tuck as far as allowed, stepping back to the nearest free needle.
    None when some stretch has no free needle.
    """
    lo, hi = sorted((a, b))
    picks: list[int] = []
    pos = lo
    while hi - pos - 1 > limit:
        t = pos + limit + 1
        while t > pos and t not in free:
            t -= 1
        if t <= pos:
            return None
        picks.append(t)
        pos = t
    return picks


def _back_after(step: Step, back: set[int]) -> None:
    """Update the set of needles holding loops on the back bed after ``step``."""
    if not isinstance(step, Pass):
        return
    for o in step.ops:
        if o.op in (OpKind.KNIT, OpKind.TUCK) and o.bed is Bed.BACK:
            back.add(o.needle)
        elif o.op in (OpKind.XFER, OpKind.SPLIT):
            if o.bed is Bed.BACK:
                back.discard(o.needle)
            if o.to_bed is Bed.BACK and o.to_needle is not None:
                back.add(o.to_needle)
        elif o.op is OpKind.DROP and o.bed is Bed.BACK:
            back.discard(o.needle)


def tuck_long_floats(
    steps: Sequence[Step], *, limit: int, left: int, right: int
) -> tuple[list[Step], list[LongFloat]]:
    """Cut every float longer than ``limit`` with back-bed tucks (see the module docstring).

    Parameters
    ----------
    steps : sequence of Pass or CarrierAction
        A complete schedule's steps.
    limit : int
        Longest allowed float, in needles crossed.
    left, right : int
        The fabric's needles; tucks go only there.

    Returns
    -------
    steps : list of Pass or CarrierAction
        With tucks added and one transfer pass after each pass that tucks.
    long : list of LongFloat
        Floats still longer than ``limit``.
    """
    passes = list(steps)
    backs: list[frozenset[int]] = []  # back-bed needles holding loops before each step
    back: set[int] = set()
    stitched: dict[int, list[int]] = {}  # needle -> indices of the passes that knit it
    for i, s in enumerate(passes):
        backs.append(frozenset(back))
        _back_after(s, back)
        if isinstance(s, Pass) and s.kind is PassKind.KNIT:
            for o in s.ops:
                if o.op is OpKind.KNIT:
                    stitched.setdefault(o.needle, []).append(i)
    # One tuck per needle between two stitches there: the needle then holds its loop and the
    # tucked loops of one pass (two yarns if plated), well within what a needle holds.
    taken: set[tuple[int, int]] = set()

    # carrier -> (needle of its last loop, index of the pass that made it, index of its last pass)
    last: dict[str, tuple[int, int, int]] = {}
    adds: dict[int, set[int]] = {}  # pass index -> back needles to tuck
    long: list[LongFloat] = []
    for i, s in enumerate(passes):
        if isinstance(s, CarrierAction):
            if s.action in ("out", "outhook"):
                for c in s.carriers:
                    last.pop(c, None)
            continue
        if s.kind is not PassKind.KNIT:
            continue
        for o in s.ops:
            if o.op not in _LOOPS:
                continue
            for c in s.carriers:
                got = last.get(c)
                if got is not None and abs(o.needle - got[0]) - 1 > limit:
                    found = _plan_tucks(
                        passes,
                        backs,
                        adds,
                        (stitched, taken),
                        {k: v[0] for k, v in last.items()},
                        i,
                        o.needle,
                        got,
                        limit,
                        left,
                        right,
                    )
                    if not found:
                        long.append(LongFloat(i, c, got[0], o.needle, s.course))
                last[c] = (o.needle, i, i)
        for c in s.carriers:
            prev = last.get(c)
            if prev is not None:
                last[c] = (prev[0], prev[1], i)
    return _apply(passes, adds), long


def _plan_tucks(
    passes: list[Step],
    backs: list[frozenset[int]],
    adds: dict[int, set[int]],
    once: tuple[dict[int, list[int]], set[tuple[int, int]]],
    loops: dict[str, int],
    i: int,
    n: int,
    got: tuple[int, int, int],
    limit: int,
    left: int,
    right: int,
) -> bool:
    """Tuck the float ``got[0]`` -> ``n`` in the pass that lays it; False if there is none."""
    a, made_in, last_pass = got
    s = passes[i]
    assert isinstance(s, Pass)
    toward = (s.direction == "-") == (a > n)
    # The yarn crosses the gap in this pass when it travels from beyond ``a`` towards ``n``;
    # otherwise on the way out of the pass that made ``a``, if that pass ran on past ``n``.
    where = i
    if not toward or (made_in != i and not _starts_beyond(passes[last_pass], a, s.direction)):
        q = passes[made_in]
        if made_in != last_pass or not isinstance(q, Pass):
            return False
        end = q.ops[-1].needle
        if q.direction != ("+" if n > a else "-") or (end < n if n > a else end > n):
            return False
        where = made_in
    p = passes[where]
    assert isinstance(p, Pass)
    lo, hi = sorted((a, n))
    if len(p.carriers) > 1:
        # A plated pass tucks all its yarns: only where every one of them comes from beyond the
        # tucks in this very pass, with no purl face in the way of the paths that changes.
        if where != i:
            return False
        ends = [loops[c] for c in p.carriers if c in loops] + [n]
        lo, hi = min(*ends, lo), max(*ends, hi)
        if any(lo < t < hi for t in backs[where]):
            return False
    if p.racking != 0 or (where != i and any(lo < t < hi for t in backs[where])):
        # A tuck on the way out would pull the float in front of those purls' faces: the yarn
        # that passed them as a miss becomes a float between two loops.
        return False
    stitched, taken = once
    busy = {o.needle for o in p.ops} | adds.get(where, set())
    free = {
        t
        for t in range(max(left, min(a, n) + 1), min(right, max(a, n) - 1) + 1)
        if t not in backs[where]
        and t not in busy
        and (t, bisect_right(stitched.get(t, []), where)) not in taken
    }
    picks = _tuck_needles(a, n, limit, free)
    if picks is None:
        return False
    if len(p.carriers) > 1:
        # Every yarn of the plated pass must reach the tucks from beyond them.
        far = max(picks) if a > n else min(picks)
        if any(
            (loops.get(c, far) < far) if a > n else (loops.get(c, far) > far) for c in p.carriers
        ):
            return False
    adds.setdefault(where, set()).update(picks)
    taken.update((t, bisect_right(stitched.get(t, []), where)) for t in picks)
    return True


def _starts_beyond(q: Step, a: int, direction: str | None) -> bool:
    """True when the carrier, last moved by ``q``, enters its next pass from beyond ``a``."""
    if not isinstance(q, Pass):
        return False
    end = q.ops[-1].needle
    return end >= a if direction == "-" else end <= a


def _apply(passes: list[Step], adds: dict[int, set[int]]) -> list[Step]:
    out: list[Step] = []
    pending: Pass | None = None
    for i, s in enumerate(passes):
        release = isinstance(s, CarrierAction) and s.action is ActionKind.RELEASEHOOK
        if pending is not None and not release:
            # (After a hook release that follows the tucking pass: the machine releases the hook
            # on a pass running the hook's way, which a transfer in between would upset.)
            out.append(pending)
            pending = None
        tucks = adds.get(i)
        if not tucks or not isinstance(s, Pass):
            out.append(s)
            continue
        sign = 1 if s.direction == "+" else -1
        ops = [*s.ops, *(Op(OpKind.TUCK, Bed.BACK, t) for t in tucks)]
        # Back and front of one needle are one slot at racking 0: order by needle, and a tuck
        # lands between the pass's own operations (its needles were excluded when choosing).
        ops.sort(key=lambda o: sign * o.needle)
        out.append(replace(s, ops=tuple(ops)))
        pending = Pass(
            PassKind.XFER,
            tuple(Op(OpKind.XFER, Bed.BACK, t, Bed.FRONT, t) for t in sorted(tucks)),
            None,
            (),
            0.0,
            Role.FLOAT_AVOIDANCE,
            s.course,
        )
    if pending is not None:
        out.append(pending)
    return out
