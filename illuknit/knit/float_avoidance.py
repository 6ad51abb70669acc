"""Float avoidance (paper Algorithm 1): no yarn floating across the face of the purls.

Carriers run in the gap between the beds. When a carrier moves without knitting -- across the
other colours' runs in stranded colourwork, from its anchor to the start of its work, between
plated stitches -- its yarn passes behind loops held on the front bed (the technical back, where
floats belong) but *in front of* loops held on the back bed, i.e. across the face of the purls
(Fig. 14). Algorithm 1 moves those back-bed loops to the front before the carrier passes and back
afterwards, and only where a float actually crosses them, since each such move costs transfer
passes.

This module computes, for the planned passes of one course, which needles each pass's floats
cross (:func:`float_crossings`: from each carrier's last loop to its first stitch, and between
consecutive stitches), and decides the transfers to make before a pass
(:func:`transfers_before`). Transfers are *batched and lazy*: a loop moved to the front for a
float stays there until some pass has to stitch it as a purl, and then goes back together with
every other move that pass needs; at the same time every pending bed change of the course that
is safe (knits always; purls no float will cross before they are knit) rides along, so that a
course usually needs one transfer pass, plus one per carrier whose floats cross purls knit by
another carrier in the same course. Both directions share a pass (racking 0, every slot once).
With float avoidance off (the ablation of Fig. 20, left) the course's bed changes are made in one
pass before it and floats are ignored, as a naive program does.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from illuknit.knit.path_planning import CarrierState, PlannedPass

__all__ = ["float_crossings", "transfers_before"]


def float_crossings(
    passes: Sequence[PlannedPass],
    states: Mapping[str, CarrierState],
    *,
    needles: range,
    entry: int | None = None,
) -> list[frozenset[int]]:
    """Needles (within ``needles``) crossed by floats of each planned pass.

    Parameters
    ----------
    passes : sequence of PlannedPass
        One course's passes in execution order (``move`` passes cross nothing: no loop is made).
    states : mapping of str to CarrierState
        Carrier states before the first pass (their ``last_loop`` starts the first floats).
    needles : range
        The body's needles; crossings outside it are dropped.
    entry : int, optional
        Where a carrier's yarn hangs before its first stitch on a machine without an inserting
        hook (it comes in from the waste section, beyond an edge): its first float starts
        there. None (a hook holds the yarn end at the first stitch): no first float.

    Returns
    -------
    list of frozenset of int
        One set per pass.
    """
    last = {c: s.last_loop for c, s in states.items()}
    lo_b, hi_b = needles.start, needles.stop - 1
    out: list[frozenset[int]] = []
    for p in passes:
        if p.kind == "move":
            out.append(frozenset())
            continue
        # Floats between the pass's own stitches (the same for all its carriers); most
        # neighbouring stitches are adjacent, so only the few real gaps are expanded.
        seq = np.fromiter((n for n, _ in p.stitches), dtype=np.intp, count=len(p.stitches))
        a, b = seq[:-1], seq[1:]
        lo = np.maximum(np.minimum(a, b) + 1, lo_b)
        hi = np.minimum(np.maximum(a, b), hi_b + 1)
        crossed: set[int] = set()
        for i in np.flatnonzero(hi > lo):
            crossed.update(range(int(lo[i]), int(hi[i])))
        first, end = int(seq[0]), int(seq[-1])
        for car in p.carriers:
            prev = last.get(car)
            if prev is None and car not in last:
                prev = entry
            if prev is not None:
                crossed.update(
                    range(max(min(prev, first) + 1, lo_b), min(max(prev, first), hi_b + 1))
                )
            last[car] = end
        out.append(frozenset(crossed))
    return out


def transfers_before(
    k: int,
    passes: Sequence[PlannedPass],
    crossings: Sequence[frozenset[int]],
    *,
    bed: Mapping[int, str],
    required: Mapping[int, str],
    stitch_pass: Mapping[int, int],
) -> tuple[dict[int, str], bool]:
    """Loops to move before pass ``k`` of a course: needle -> target bed.

    Parameters
    ----------
    k : int
        Index of the pass about to be emitted.
    passes, crossings : sequences
        The course's planned passes and :func:`float_crossings` of them.
    bed : mapping of int to str
        Current bed (``"f"``/``"b"``) of the loop on each body needle.
    required : mapping of int to str
        Bed each needle's stitch of this course is made on.
    stitch_pass : mapping of int to int
        Index of the pass that stitches each needle in this course.

    Returns
    -------
    moves : dict of int to str
        Target bed per needle to move (empty when pass ``k`` needs nothing).
    for_floats : bool
        True when some move is there only because a float crosses the needle.
    """
    p = passes[k]
    moves: dict[int, str] = {}
    for_floats = False
    if p.kind != "move":
        for n in crossings[k]:
            if bed.get(n) == "b":
                moves[n] = "f"
                for_floats = True
        for n, b in p.stitches:
            if bed.get(n) != b:
                moves[n] = b
    if not moves:
        return moves, False
    # Everything else of the course that can safely change bed now rides along.
    for n, j in stitch_pass.items():
        if j <= k or n in moves:
            continue
        want = required[n]
        if bed.get(n) == want:
            continue
        if want == "f" or not any(n in crossings[i] for i in range(k, j)):
            moves[n] = want
    return moves, for_floats
