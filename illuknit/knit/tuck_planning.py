"""Where to tuck a long float: the planning half of :mod:`illuknit.knit.float_tucks`.

:class:`TuckPlan` scans nothing itself: :func:`~illuknit.knit.float_tucks.tuck_long_floats`
walks the step list, and for each float longer than the limit asks :meth:`TuckPlan.plan` to
find the pass that lays the yarn across the gap and back-bed needles inside the gap to tuck on.
A plan records, per pass index,

* ``adds``: back needles the pass itself tucks (every yarn of the pass tucks there);
* ``solo``: tucks of one carrier in a pass of its own right before the pass (optionally coming
  back beside its last loop first);
* ``clear``: back-bed loops (purls) moved to the front around the pass so that the tucked yarn
  does not cross in front of their faces.

It also remembers which needle has taken a tuck since its last stitch (one tuck per needle
between two stitches there). :func:`~illuknit.knit.float_tucks.tuck_long_floats` then applies
the plan to the steps.
"""

from __future__ import annotations

from bisect import bisect_right
from dataclasses import dataclass, field
from itertools import pairwise
from typing import Any

from illuknit.knit.ir import Bed, CarrierAction, Opcode, Pass, PassKind, Step

__all__ = ["LOOP_OPS", "MAX_TUCKS", "TuckPlan", "knit_pass"]

#: Tucks a needle may already take between two of its stitches and still take a float tuck:
#: with the loop it holds (and, on a machine without an inserting hook, the draw thread's loop
#: under the cast-on) that stays within what a needle holds (the PyPI simulator allows 3).
MAX_TUCKS = 2

#: Operations that leave a loop of the carriers' yarn on a needle.
LOOP_OPS = (Opcode.KNIT, Opcode.TUCK, Opcode.SPLIT)


def knit_pass(
    step: Step, last: dict[str, Any], *, forget: tuple[str, ...] = ("out", "outhook")
) -> Pass | None:
    """``step`` if it is a knit pass, else None.

    The walk of a carrier's loops, step by step: a carrier action in ``forget`` (going out, or
    coming in when walking backwards) drops its carriers from ``last``, so their next loop starts
    afresh.
    """
    if isinstance(step, CarrierAction):
        if step.action in forget:
            for c in step.carriers:
                last.pop(c, None)
        return None
    return step if step.kind is PassKind.KNIT else None


#: ``(carrier, back needles, needle it comes back beside first or None)`` per solo tuck pass.
Solo = tuple[str, set[int], int | None]


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
        if o.op in (Opcode.KNIT, Opcode.TUCK) and o.bed is Bed.BACK:
            back.add(o.needle)
        elif o.op in (Opcode.XFER, Opcode.SPLIT):
            if o.bed is Bed.BACK:
                back.discard(o.needle)
            if o.to_bed is Bed.BACK and o.to_needle is not None:
                back.add(o.to_needle)
        elif o.op is Opcode.DROP and o.bed is Bed.BACK:
            back.discard(o.needle)


def _neighbour_loops(
    passes: list[Step], entries: dict[str, int]
) -> list[dict[str, tuple[int | None, int | None]]]:
    """Per step: each of its carriers' last loop before it and first loop after it (or None);
    ``entries``: loops the carriers' yarns hang from before the first step."""
    out: list[dict[str, tuple[int | None, int | None]]] = [{} for _ in passes]
    prev: dict[str, int] = dict(entries)
    for i, step in enumerate(passes):
        if (s := knit_pass(step, prev)) is None:
            continue
        out[i] = {c: (prev.get(c), None) for c in s.carriers}
        loops = [o.needle for o in s.ops if o.op in LOOP_OPS]
        if loops:
            for c in s.carriers:
                prev[c] = loops[-1]
    nxt: dict[str, int] = {}
    for i in range(len(passes) - 1, -1, -1):
        if (s := knit_pass(passes[i], nxt, forget=("in", "inhook"))) is None:
            continue
        out[i] = {c: (b, nxt.get(c)) for c, (b, _) in out[i].items()}
        loops = [o.needle for o in s.ops if o.op in LOOP_OPS]
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
    own = [(o.needle, False) for o in p.ops if o.op in LOOP_OPS]
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


def _starts_beyond(q: Step, a: int, direction: str | None) -> bool:
    """True when the carrier, last moved by ``q``, enters its next pass from beyond ``a``.

    The carrier stops on the far side of ``q``'s last needle, half a needle on: a ``-`` move
    to ``a + 1`` (or a ``+`` move to ``a - 1``) leaves it right beside ``a``, between ``a`` and
    that needle -- where a parked carrier comes back to before a pass that starts away from its
    last loop -- so the next pass from there lays the whole float from ``a``."""
    if not isinstance(q, Pass):
        return False
    end = q.ops[-1].needle
    if direction == "-":
        return end >= a - (q.direction == "+")
    return end <= a + (q.direction == "-")


@dataclass(eq=False)
class TuckPlan:
    """The tucks planned so far on one step list (see the module docstring).

    Mutable on purpose: it is built up float by float while
    :func:`~illuknit.knit.float_tucks.tuck_long_floats` walks the steps, and never leaves it.

    Attributes
    ----------
    passes : list of Pass or CarrierAction
        The steps being tucked (not changed).
    backs : list of frozenset of int
        Back-bed needles holding loops before each step.
    stitched : dict
        Needle -> indices of the knit passes that knit it, in order.
    around : list of dict
        Per step: each of its carriers' last loop before it and first loop after it.
    limit, left, right, alone
        As for :func:`~illuknit.knit.float_tucks.tuck_long_floats`.
    adds, solo, clear : dict
        The plan, per pass index (see the module docstring).
    taken : set of (needle, stitch count)
        Needles that took a tuck, with how many stitches they had had by then.
    tucked : dict
        Needle -> indices of the knit passes that tuck on it (cast-on tucks, tuck joins), in
        order: a needle that already takes :data:`MAX_TUCKS` tucks between two of its stitches
        takes no float tuck there (it would hold too many loops).
    """

    passes: list[Step]
    backs: list[frozenset[int]]
    stitched: dict[int, list[int]]
    around: list[dict[str, tuple[int | None, int | None]]]
    limit: int
    left: int
    right: int
    alone: bool
    adds: dict[int, set[int]] = field(default_factory=dict)
    solo: dict[int, list[Solo]] = field(default_factory=dict)
    clear: dict[int, set[int]] = field(default_factory=dict)
    taken: set[tuple[int, int]] = field(default_factory=set)
    tucked: dict[int, list[int]] = field(default_factory=dict)

    @classmethod
    def for_steps(
        cls,
        passes: list[Step],
        *,
        limit: int,
        left: int,
        right: int,
        alone: bool,
        entries: dict[str, int] | None = None,
    ) -> TuckPlan:
        """An empty plan for ``passes``, with the back-bed loops and stitches read off them
        (``entries``: the loops carriers' yarns hang from before the first step)."""
        backs: list[frozenset[int]] = []
        back: set[int] = set()
        stitched: dict[int, list[int]] = {}
        tucked: dict[int, list[int]] = {}
        for i, s in enumerate(passes):
            backs.append(frozenset(back))
            _back_after(s, back)
            if isinstance(s, Pass) and s.kind is PassKind.KNIT:
                for o in s.ops:
                    if o.op is Opcode.KNIT:
                        stitched.setdefault(o.needle, []).append(i)
                    elif o.op is Opcode.TUCK:
                        tucked.setdefault(o.needle, []).append(i)
        # One tuck per needle between two stitches there: the needle then holds its loop and
        # the tucked loops of one pass (two yarns if plated), well within what a needle holds.
        around = _neighbour_loops(passes, dict(entries or {}))
        return cls(passes, backs, stitched, around, limit, left, right, alone, tucked=tucked)

    def plan(self, i: int, carrier: str, n: int, got: tuple[int, int, int]) -> bool:
        """Tuck the float ``got[0]`` -> ``n`` in the pass that lays it; False if there is none.

        ``got`` is the carrier's last loop: (needle, index of the pass that made it, index of
        the carrier's last pass), -1 for a loop made before the steps (the yarn's entry, with
        the carrier parked beyond it); pass ``i`` makes the loop on ``n``. In a plated pass every
        yarn tucks: the tucks must leave each of them short floats (:func:`_tucks_fit`), and no
        purl face may lie where any of their paths changes. Where the pass that lays the float
        cannot tuck it (a plated catching pass whose other yarn comes from elsewhere), the
        carrier tucks alone in a pass of its own right before, on its way to ``n``.
        """
        a, made_in, last_pass = got
        passes = self.passes
        s = passes[i]
        assert isinstance(s, Pass)
        toward = (s.direction == "-") == (a > n)
        # The yarn crosses the gap in this pass when it travels from beyond ``a`` towards
        # ``n``; otherwise on the way out of the pass that made ``a``, if that pass ran on past
        # ``n``.
        where = i
        if made_in < 0:
            # The yarn's entry: the carrier waits beyond ``a`` until its first pass (or a move
            # of its own) takes it in; only a pass travelling from there towards ``n`` lays it.
            behind = last_pass < 0 or _starts_beyond(passes[last_pass], a, s.direction)
            if not toward or not behind:
                return False
        elif not toward or (made_in != i and not _starts_beyond(passes[last_pass], a, s.direction)):
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
            # (Not once a yarn of the pass tucks alone before it: the tucks here were not
            # planned from where that yarn then is.)
            if i not in self.solo and self._tuck_in(p, where, a, n, outward=False):
                return True
            if made_in == i or not self.alone:  # (between two loops of this pass, nothing fits)
                return False
            return self._tuck_alone(i, carrier, a, n)
        if self._tuck_in(p, where, a, n, outward=where != i):
            return True
        if where == i or len(s.carriers) > 1 or s.racking != 0 or i in self.solo:
            return False
        # The way out is blocked (no free back needle among purls there): the carrier comes
        # back beside its last loop and tucks alone on its way to ``n``, right before pass
        # ``i``, when float avoidance has already moved the purls the float crosses to the front.
        busy = set(self.adds.get(i, set()))
        picks = _tuck_needles(a, n, self.limit, self._free_needles(i, a, n, busy))
        if not picks:
            return False
        self.solo.setdefault(i, []).append((carrier, set(picks), a))
        self._take(picks, i)
        return True

    def _take(self, picks: list[int], where: int) -> None:
        """Mark ``picks`` as tucked at pass ``where`` (until each needle's next stitch)."""
        self.taken.update((t, bisect_right(self.stitched.get(t, []), where)) for t in picks)

    def _free_needles(self, where: int, a: int, n: int, busy: set[int]) -> set[int]:
        """Needles strictly between ``a`` and ``n`` whose back bed may take a tuck at pass
        ``where``."""
        return {
            t
            for t in range(max(self.left, min(a, n) + 1), min(self.right, max(a, n) - 1) + 1)
            if t not in self.backs[where]
            and t not in busy
            and (t, bisect_right(self.stitched.get(t, []), where)) not in self.taken
            and self._tucks_between_stitches(t, where) < MAX_TUCKS
        }

    def _tucks_between_stitches(self, t: int, where: int) -> int:
        """Tucks the steps make on needle ``t`` between its last stitch before pass ``where``
        and its next one."""
        knits = self.stitched.get(t, [])
        k = bisect_right(knits, where)
        lo = knits[k - 1] if k else -1
        hi = knits[k] if k < len(knits) else len(self.passes)
        tucks = self.tucked.get(t, [])
        return bisect_right(tucks, hi) - bisect_right(tucks, lo)

    def _tuck_alone(self, i: int, carrier: str, a: int, n: int) -> bool:
        """Tuck the float ``a`` -> ``n`` with ``carrier`` alone in a pass of its own before
        ``i``."""
        busy = set(self.adds.get(i, set())).union(*(t for _, t, _ in self.solo.get(i, [])))
        picks = _tuck_needles(a, n, self.limit, self._free_needles(i, a, n, busy))
        if not picks:
            return False
        # The pass's own tucks (for another yarn's float) must lie ahead of where this yarn
        # stops.
        stop = max(picks) if n > a else min(picks)
        if any((t - stop) * (n - a) <= 0 for t in self.adds.get(i, set())):
            return False
        self.solo.setdefault(i, []).append((carrier, set(picks), None))
        self._take(picks, i)
        return True

    def _tuck_in(self, p: Pass, where: int, a: int, n: int, *, outward: bool) -> bool:
        """Tuck the float ``a`` -> ``n`` in pass ``where`` (all its yarns tuck); ``outward``:
        on the way out of the pass that made ``a``. Back-bed loops the float then passes are
        added to ``clear[where]``: moved to the front before the pass and back right after
        it."""
        lo, hi = sorted((a, n))
        backs = self.backs[where]
        if len(p.carriers) > 1:
            ends = [
                e
                for c in p.carriers
                for e in self.around[where].get(c, (None, None))
                if e is not None
            ]
            lo, hi = min(*ends, lo), max(*ends, hi)
            if any(lo < t < hi for t in backs):
                return False
        if p.racking != 0:
            return False
        purls = {t for t in backs if lo < t < hi} if outward else set()
        if purls and len(p.carriers) > 1:
            # A tuck on the way out would pull the float in front of those purls' faces (the
            # yarn that passed them as a miss becomes a float between two loops); a single
            # yarn's pass has them moved to the front around it, a plated pass is left alone.
            return False
        busy = {o.needle for o in p.ops} | self.adds.get(where, set())
        picks = _tuck_needles(a, n, self.limit, self._free_needles(where, a, n, busy))
        if picks is None or not _tucks_fit(
            p, self.adds.get(where, set()) | set(picks), self.around[where], self.limit
        ):
            return False
        self.adds.setdefault(where, set()).update(picks)
        if purls:
            self.clear.setdefault(where, set()).update(purls)
        self._take(picks, where)
        return True
