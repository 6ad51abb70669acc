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

import math
from bisect import bisect_right
from collections.abc import Sequence
from dataclasses import dataclass, replace
from itertools import pairwise

from illuknit.knit.ir import (
    ActionKind,
    Bed,
    CarrierAction,
    Op,
    OpKind,
    Pass,
    PassKind,
    Role,
    Step,
    flip,
)

__all__ = ["LongFloat", "measure_long_floats", "tuck_long_floats"]


@dataclass(frozen=True)
class LongFloat:
    """A float still too long: ``carrier`` crosses ``length`` needle slots before ``step``.

    ``step`` indexes the steps the float was measured on (the tucked program's)."""

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
    steps: Sequence[Step], *, limit: int, left: int, right: int, alone: bool = False
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
    alone : bool
        Where a plated pass cannot tuck a float, let the floating yarn tuck alone in a pass of
        its own right before (a knit pass and a transfer pass more); False keeps those floats.

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
    around = _neighbour_loops(passes)

    # carrier -> (needle of its last loop, index of the pass that made it, index of its last pass)
    last: dict[str, tuple[int, int, int]] = {}
    adds: dict[int, set[int]] = {}  # pass index -> back needles to tuck
    solo: dict[
        int, list[tuple[str, set[int], int | None]]
    ] = {}  # pass index -> (carrier, tucks) before it
    clear: dict[int, set[int]] = {}  # pass index -> back loops moved front around it
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
                    _plan_tucks(
                        passes,
                        backs,
                        adds,
                        (stitched, taken),
                        around,
                        solo,
                        c,
                        alone,
                        i,
                        o.needle,
                        got,
                        limit,
                        left,
                        right,
                        clear,
                    )
                last[c] = (o.needle, i, i)
        for c in s.carriers:
            prev = last.get(c)
            if prev is not None:
                last[c] = (prev[0], prev[1], i)
    out = _apply(passes, adds, solo, clear)
    # One yarn's tucks may cut another's float too (a plated pass tucks every yarn): what stays
    # long is measured on the result, loop to loop, as the checker's simulator measures it.
    return out, measure_long_floats(out, limit=limit)


def measure_long_floats(steps: Sequence[Step], *, limit: int) -> list[LongFloat]:
    """Every float longer than ``limit`` in ``steps``: from a carrier's loop to its next one.

    Needle slots as the machine sees them (a back needle at racking ``r`` sits at slot
    ``needle + floor(r)``); a carrier taken out (``out``/``outhook``) starts afresh.
    """
    long: list[LongFloat] = []
    last: dict[str, int] = {}
    for i, s in enumerate(steps):
        if isinstance(s, CarrierAction):
            if s.action in ("out", "outhook"):
                for c in s.carriers:
                    last.pop(c, None)
            continue
        if s.kind is not PassKind.KNIT:
            continue
        shift = math.floor(s.racking)
        for o in s.ops:
            if o.op not in _LOOPS:
                continue
            slot = o.needle + (shift if o.bed is Bed.BACK else 0)
            for c in s.carriers:
                got = last.get(c)
                if got is not None and abs(slot - got) - 1 > limit:
                    long.append(LongFloat(i, c, got, slot, s.course))
                last[c] = slot
    return long


def _neighbour_loops(passes: list[Step]) -> list[dict[str, tuple[int | None, int | None]]]:
    """Per step: each of its carriers' last loop before it and first loop after it (or None)."""
    out: list[dict[str, tuple[int | None, int | None]]] = [{} for _ in passes]
    prev: dict[str, int] = {}
    for i, s in enumerate(passes):
        if isinstance(s, CarrierAction):
            if s.action in ("out", "outhook"):
                for c in s.carriers:
                    prev.pop(c, None)
            continue
        if s.kind is not PassKind.KNIT:
            continue
        out[i] = {c: (prev.get(c), None) for c in s.carriers}
        loops = [o.needle for o in s.ops if o.op in _LOOPS]
        if loops:
            for c in s.carriers:
                prev[c] = loops[-1]
    nxt: dict[str, int] = {}
    for i in range(len(passes) - 1, -1, -1):
        s = passes[i]
        if isinstance(s, CarrierAction):
            if s.action in ("in", "inhook"):
                for c in s.carriers:
                    nxt.pop(c, None)
            continue
        if s.kind is not PassKind.KNIT:
            continue
        out[i] = {c: (b, nxt.get(c)) for c, (b, _) in out[i].items()}
        loops = [o.needle for o in s.ops if o.op in _LOOPS]
        if loops:
            for c in s.carriers:
                nxt[c] = loops[0]
    return out


def _tucks_fit(
    p: Pass, tucks: set[int], around: dict[str, tuple[int | None, int | None]], limit: int
) -> bool:
    """True when ``tucks`` only cut floats of the yarns of ``p``, into pieces of <= ``limit``.

    Each yarn of the pass loops at its stitches and at every tuck, in pass order, between its
    last loop before the pass and its first after it. A tuck must lie inside the float it
    interrupts (between the yarn's neighbouring own loops): then every new float is part of one
    the schedule already laid, whose crossings of purls float avoidance has cleared; and every
    float ending at a tuck must be short.
    """
    sign = 1 if p.direction == "+" else -1
    own = [(o.needle, False) for o in p.ops if o.op in _LOOPS]
    seq = sorted([*own, *((t, True) for t in tucks)], key=lambda x: sign * x[0])
    for c in p.carriers:
        before, after = around.get(c, (None, None))
        full = ([(before, False)] if before is not None else []) + seq
        full += [(after, False)] if after is not None else []
        for (x, tx), (y, ty) in pairwise(full):
            if (tx or ty) and abs(x - y) - 1 > limit:
                return False
        loops = [k for k, (_, t) in enumerate(full) if not t]
        for k, (x, t) in enumerate(full):
            if not t:
                continue
            lo = max((j for j in loops if j < k), default=None)
            hi = min((j for j in loops if j > k), default=None)
            if lo is None or hi is None:
                continue  # the yarn's first loop or its last: nothing before or after to cross
            u, v = sorted((full[lo][0], full[hi][0]))
            if not u < x < v:
                return False
    return True


def _plan_tucks(
    passes: list[Step],
    backs: list[frozenset[int]],
    adds: dict[int, set[int]],
    once: tuple[dict[int, list[int]], set[tuple[int, int]]],
    around: list[dict[str, tuple[int | None, int | None]]],
    solo: dict[int, list[tuple[str, set[int], int | None]]],
    carrier: str,
    alone: bool,
    i: int,
    n: int,
    got: tuple[int, int, int],
    limit: int,
    left: int,
    right: int,
    clear: dict[int, set[int]],
) -> bool:
    """Tuck the float ``got[0]`` -> ``n`` in the pass that lays it; False if there is none.

    In a plated pass every yarn tucks: the tucks must leave each of them short floats
    (:func:`_tucks_fit`), and no purl face may lie where any of their paths changes. Where the
    pass that lays the float cannot tuck it (a plated catching pass whose other yarn comes from
    elsewhere), the carrier tucks alone in a pass of its own right before, on its way to ``n``.
    """
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
    if where == i and p.racking == 0 and len(p.carriers) > 1:
        # (Not once a yarn of the pass tucks alone before it: the tucks here were not planned
        # from where that yarn then is.)
        if i not in solo and _tuck_in(
            p,
            where,
            a,
            n,
            backs,
            adds,
            once,
            around,
            limit,
            left,
            right,
            outward=False,
            clear=clear,
        ):
            return True
        if made_in == i or not alone:  # (between two loops of this pass, nothing fits before)
            return False
        return _tuck_alone(i, carrier, a, n, backs, (adds, solo), once, limit, left, right)
    if _tuck_in(
        p,
        where,
        a,
        n,
        backs,
        adds,
        once,
        around,
        limit,
        left,
        right,
        outward=where != i,
        clear=clear,
    ):
        return True
    if where == i or len(s.carriers) > 1 or s.racking != 0 or i in solo:
        return False
    # The way out is blocked (no free back needle among purls there): the carrier comes back
    # beside its last loop and tucks alone on its way to ``n``, right before pass ``i``, when
    # float avoidance has already moved the purls the float crosses to the front.
    busy = set(adds.get(i, set()))
    picks = _tuck_needles(a, n, limit, _free_needles(i, a, n, backs, busy, once, left, right))
    if not picks:
        return False
    solo.setdefault(i, []).append((carrier, set(picks), a))
    stitched, taken = once
    taken.update((t, bisect_right(stitched.get(t, []), i)) for t in picks)
    return True


def _free_needles(
    where: int,
    a: int,
    n: int,
    backs: list[frozenset[int]],
    busy: set[int],
    once: tuple[dict[int, list[int]], set[tuple[int, int]]],
    left: int,
    right: int,
) -> set[int]:
    """Needles strictly between ``a`` and ``n`` whose back bed may take a tuck at pass ``where``."""
    stitched, taken = once
    return {
        t
        for t in range(max(left, min(a, n) + 1), min(right, max(a, n) - 1) + 1)
        if t not in backs[where]
        and t not in busy
        and (t, bisect_right(stitched.get(t, []), where)) not in taken
    }


def _tuck_alone(
    i: int,
    carrier: str,
    a: int,
    n: int,
    backs: list[frozenset[int]],
    plans: tuple[dict[int, set[int]], dict[int, list[tuple[str, set[int], int | None]]]],
    once: tuple[dict[int, list[int]], set[tuple[int, int]]],
    limit: int,
    left: int,
    right: int,
) -> bool:
    """Tuck the float ``a`` -> ``n`` with ``carrier`` alone in a pass of its own before ``i``."""
    adds, solo = plans
    busy = set(adds.get(i, set())).union(*(t for _, t, _ in solo.get(i, [])))
    picks = _tuck_needles(a, n, limit, _free_needles(i, a, n, backs, busy, once, left, right))
    if not picks:
        return False
    # The pass's own tucks (for another yarn's float) must lie ahead of where this yarn stops.
    stop = max(picks) if n > a else min(picks)
    if any((t - stop) * (n - a) <= 0 for t in adds.get(i, set())):
        return False
    solo.setdefault(i, []).append((carrier, set(picks), None))
    stitched, taken = once
    taken.update((t, bisect_right(stitched.get(t, []), i)) for t in picks)
    return True


def _tuck_in(
    p: Pass,
    where: int,
    a: int,
    n: int,
    backs: list[frozenset[int]],
    adds: dict[int, set[int]],
    once: tuple[dict[int, list[int]], set[tuple[int, int]]],
    around: list[dict[str, tuple[int | None, int | None]]],
    limit: int,
    left: int,
    right: int,
    *,
    outward: bool,
    clear: dict[int, set[int]],
) -> bool:
    """Tuck the float ``a`` -> ``n`` in pass ``where`` (all its yarns tuck); ``outward``: on
    the way out of the pass that made ``a``. Back-bed loops the float then passes are added to
    ``clear[where]``: moved to the front before the pass and back right after it."""
    lo, hi = sorted((a, n))
    if len(p.carriers) > 1:
        ends = [e for c in p.carriers for e in around[where].get(c, (None, None)) if e is not None]
        lo, hi = min(*ends, lo), max(*ends, hi)
        if any(lo < t < hi for t in backs[where]):
            return False
    if p.racking != 0:
        return False
    purls = {t for t in backs[where] if lo < t < hi} if outward else set()
    if purls and len(p.carriers) > 1:
        # A tuck on the way out would pull the float in front of those purls' faces (the yarn
        # that passed them as a miss becomes a float between two loops); a single yarn's pass
        # has them moved to the front around it, a plated pass is left alone.
        return False
    stitched, taken = once
    busy = {o.needle for o in p.ops} | adds.get(where, set())
    free = _free_needles(where, a, n, backs, busy, once, left, right)
    picks = _tuck_needles(a, n, limit, free)
    if picks is None or not _tucks_fit(
        p, adds.get(where, set()) | set(picks), around[where], limit
    ):
        return False
    adds.setdefault(where, set()).update(picks)
    if purls:
        clear.setdefault(where, set()).update(purls)
    taken.update((t, bisect_right(stitched.get(t, []), where)) for t in picks)
    return True


def _starts_beyond(q: Step, a: int, direction: str | None) -> bool:
    """True when the carrier, last moved by ``q``, enters its next pass from beyond ``a``."""
    if not isinstance(q, Pass):
        return False
    end = q.ops[-1].needle
    return end >= a if direction == "-" else end <= a


def _apply(
    passes: list[Step],
    adds: dict[int, set[int]],
    solo: dict[int, list[tuple[str, set[int], int | None]]],
    clear: dict[int, set[int]],
) -> list[Step]:
    out: list[Step] = []
    pending: Pass | None = None
    for i, s in enumerate(passes):
        release = isinstance(s, CarrierAction) and s.action is ActionKind.RELEASEHOOK
        if pending is not None and not release:
            # (After a hook release that follows the tucking pass: the machine releases the hook
            # on a pass running the hook's way, which a transfer in between would upset.)
            out.append(pending)
            pending = None
        alone: set[int] = set()
        for carrier, picks, back_to in solo.get(i, []):
            assert isinstance(s, Pass) and s.direction is not None
            d = s.direction
            trail: tuple[Op, ...] = ()
            if back_to is not None:
                # Back beside the last loop, then tuck towards the pass's first needle and stop
                # just beyond it, behind the carriage for the pass.
                d = "+" if s.ops[0].needle > back_to else "-"
                step = 1 if d == "+" else -1
                out.append(
                    Pass(
                        PassKind.KNIT,
                        (Op(OpKind.MISS, Bed.FRONT, back_to + step),),
                        flip(d),
                        (carrier,),
                        0.0,
                        Role.ANCHOR,
                        s.course,
                    )
                )
                trail = (Op(OpKind.MISS, Bed.FRONT, s.ops[0].needle + step),)
            sign = 1 if d == "+" else -1
            tucks_op = tuple(Op(OpKind.TUCK, Bed.BACK, t) for t in sorted(picks, key=sign.__mul__))
            out.append(
                Pass(
                    PassKind.KNIT,
                    tucks_op + trail,
                    d,
                    (carrier,),
                    0.0,
                    Role.FLOAT_AVOIDANCE,
                    s.course,
                )
            )
            alone |= picks
        tucks = adds.get(i, set())
        if not isinstance(s, Pass) or not (tucks or alone):
            out.append(s)
            continue
        purls = sorted(clear.get(i, set()))
        if purls:
            out.append(_xfers([(t, Bed.BACK, Bed.FRONT) for t in purls], s.course))
        sign = 1 if s.direction == "+" else -1
        ops = [*s.ops, *(Op(OpKind.TUCK, Bed.BACK, t) for t in tucks)]
        # Back and front of one needle are one slot at racking 0: order by needle, and a tuck
        # lands between the pass's own operations (its needles were excluded when choosing).
        ops.sort(key=lambda o: sign * o.needle)
        out.append(replace(s, ops=tuple(ops)))
        pending = _xfers(
            sorted(
                [
                    *((t, Bed.BACK, Bed.FRONT) for t in tucks | alone),
                    *((t, Bed.FRONT, Bed.BACK) for t in purls),
                ]
            ),
            s.course,
        )
    if pending is not None:
        out.append(pending)
    return out


def _xfers(moves: list[tuple[int, Bed, Bed]], course: int | None) -> Pass:
    """One transfer pass at racking 0: ``(needle, from bed, to bed)`` each."""
    ops = tuple(Op(OpKind.XFER, frm, n, to, n) for n, frm, to in moves)
    return Pass(PassKind.XFER, ops, None, (), 0.0, Role.FLOAT_AVOIDANCE, course)
