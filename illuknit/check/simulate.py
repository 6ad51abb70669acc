"""illuknit's own simulation of a knitout program on a V-bed machine.

The second stage of the checker: :func:`simulate_program` runs a parsed :class:`KnitoutProgram`
operation by operation and records what a real machine would do, without judging severity
(``rules.py`` and ``fabric.py`` do that). The machine state it tracks:

* **needles**: which loops (integer ids) each needle of the four beds (f, b, fs, bs) holds;
* **racking** R: back needle ``b k`` faces front needle ``f (k+R)``; its *location* on the common
  axis is ``k + R`` and its *slot* ``k + floor(R)`` (front needles: location = slot = index);
* **carriers**: active or not, the set named on their ``in``/``inhook`` (awaiting first use),
  their logical position (location of their last op and its direction: just right of it after
  ``+``, just left after ``-``), and the last loop they made;
* **the yarn-inserting hook**: which carrier set it holds and, once the first stitch is made, its
  slot (one right of that stitch, as in the SWG091N2 model of ``virtual-knitting-machine``);
* **the loop graph**: every loop made is a node; *stitch edges* join a new loop to the loops it was
  pulled through, *yarn edges* join consecutive loops of one carrier. A union-find keeps its
  connected components: each component is one separate piece of fabric.

Besides machine-rule events it records raw fabric observations: every float (a carrier moving
across needle slots between two consecutive loops), every slot where such a move passed in front
of back-bed loops with no front loop to hide the yarn (Fig. 14 of the paper), and every stitch
made while the carrier sat ahead of the needle in the pass direction (Fig. 16). The state and the
records live in :mod:`illuknit.check.sim_state`; this module says what each operation does to them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from illuknit.check.sim_state import (
    MAX_EVENTS_PER_CODE,
    BumpYarnChange,
    CarrierEnd,
    Drop,
    Event,
    FaceFloat,
    KnitRun,
    MachineState,
    UnclearedTuck,
    WrongSide,
)
from illuknit.knitout.floats import Float
from illuknit.knitout.parse import CARRIER_OPS, STITCH_OPS, KnitoutProgram, Operation

__all__ = ["Simulation", "simulate_program"]


@dataclass(frozen=True)
class Simulation:
    """What happened when the program ran.

    Attributes
    ----------
    events : tuple of Event
        Machine-rule events in line order (capped at ``MAX_EVENTS_PER_CODE`` per code).
    suppressed : dict of str to int
        Events per code beyond the cap.
    floats : tuple of Float
        Every float of length >= 1.
    face_floats, wrong_sides : tuple
        Raw fabric observations, see the classes.
    loop_lines : tuple of int
        Line that made each loop, indexed by loop id.
    loop_carriers : tuple of str
        Carrier of each loop.
    components : tuple of int
        Component (piece) label of each loop, labels 0..pieces-1 in order of first loop.
    loops_left : tuple of (str, int)
        Needles still holding loops at the end and how many.
    carriers_left : tuple of CarrierEnd
        Carriers never taken out.
    hook_left : tuple of str
        Carrier set still on the inserting hook at the end (empty when released).
    last_line : int
        Line of the last operation (1 when there is none).
    drops : tuple of Drop
        Every release of live loops (``drop``, or knit without yarn).
    draw_threads : tuple of int
        First loop id of each draw thread: a carrier's last run of knits in one direction,
        each pulled through loops of yarns already taken out, after which (when it goes out)
        it holds every loop on the needles. Loops made before it are waste below it.
    loop_tails : tuple of int
        Per loop: how many knits in a row its yarn made on that needle before it (a tail
        knit on the last needle of a bind-off counts up).
    yarn_changes : tuple of BumpYarnChange
        Purls pulled through a front-bed loop of other carriers only (split bumps).
    uncleared_tucks : tuple of UnclearedTuck
        Tucks on a back needle holding a loop, moved or dropped before a knit cleared them.
    """

    events: tuple[Event, ...]
    suppressed: dict[str, int]
    floats: tuple[Float, ...]
    face_floats: tuple[FaceFloat, ...]
    wrong_sides: tuple[WrongSide, ...]
    loop_lines: tuple[int, ...]
    loop_carriers: tuple[str, ...]
    components: tuple[int, ...]
    loops_left: tuple[tuple[str, int], ...]
    carriers_left: tuple[CarrierEnd, ...]
    hook_left: tuple[str, ...]
    last_line: int
    drops: tuple[Drop, ...] = ()
    draw_threads: tuple[int, ...] = ()
    loop_tails: tuple[int, ...] = ()
    yarn_changes: tuple[BumpYarnChange, ...] = ()
    uncleared_tucks: tuple[UnclearedTuck, ...] = ()

    @property
    def pieces(self) -> int:
        """Number of connected components of the loop/yarn graph (0 when no loop was made)."""
        return max(self.components, default=-1) + 1


def _check_pair(state: MachineState, op: Operation) -> bool:
    """Machine rules of a needle-to-needle move (xfer, split); True when loops may move."""
    src, dst = op.needles
    if src.is_front == dst.is_front:
        state.event(op.line, "xfer-same-bed", f"{op.op} {src} {dst}: both needles on one bed")
        return False
    if src.is_slider and dst.is_slider:
        state.event(op.line, "xfer-slider-slider", f"{op.op} {src} {dst}: slider to slider")
        return False
    if op.op == "split" and src.is_slider:
        state.event(op.line, "stitch-on-slider", f"split from slider {src}")
    front, back = (src, dst) if src.is_front else (dst, src)
    r = state.rack
    if front.index != back.index + r:
        state.event(
            op.line,
            "xfer-misaligned",
            f"{op.op} {src} {dst} at racking {_fmt(r)}: {back} faces f{back.index + r:g}; "
            f"this move needs rack {front.index - back.index}",
        )
        return False
    return True


def _fmt(x: float) -> str:
    return f"{x:g}"


def _stitch(state: MachineState, op: Operation) -> None:
    """A knit, tuck, miss or split: the carriers' rules, fabric observations, new loops."""
    line = op.line
    needle = op.needle
    direction = op.direction
    assert direction is not None
    carriers = op.carriers
    state.note_needle(needle, line)
    if op.op == "split":
        state.note_needle(op.needles[1], line)
    if not carriers:
        if op.op == "miss":
            state.event(
                line, "miss-without-carriers", f"miss {direction} {needle} names no carrier"
            )
        elif op.op == "knit":  # knit without yarn = drop
            state.drop(needle, line)
        elif op.op == "split" and _check_pair(state, op):  # split without yarn = xfer
            state.put(op.needles[1], state.move_off(needle, line), line)
        return
    if len(set(carriers)) != len(carriers):
        state.event(
            line, "duplicate-carrier", f"carrier set {' '.join(carriers)} repeats a carrier"
        )
    makes_loops = op.op != "miss"
    if makes_loops and needle.is_slider:
        state.event(
            line,
            "stitch-on-slider",
            f"{op.op} on slider needle {needle}: sliders cannot form loops",
        )
    x = state.location(needle)
    slot = state.slot(needle)
    _use_carriers(state, op, slot, makes_loops=makes_loops)
    if makes_loops:
        _observe_fabric(state, op, x, slot)
    new = _make_loops(state, op) if makes_loops else []
    for k, name in enumerate(carriers):
        c = state.carriers[name]
        c.x = x
        c.dir = direction
        c.used = True
        c.last_line = line
        if makes_loops:
            lid = new[k]
            if c.last_loop is not None:
                state.union(lid, c.last_loop)
            c.last_loop = lid


def _use_carriers(state: MachineState, op: Operation, slot: int, *, makes_loops: bool) -> None:
    """Rules of the carriers a stitch uses: brought in, first use as brought in, the hook."""
    line, needle, direction, carriers = op.line, op.needle, op.direction, op.carriers
    hook_first = False
    for name in carriers:
        c = state.carrier(name, line)
        if not c.active:
            state.event(
                line,
                "carrier-not-in",
                f"carrier {name} is used but was never brought in (in/inhook)"
                if not c.in_line
                else f"carrier {name} is used after it was taken out",
            )
            c.active = True
            c.in_line = c.in_line or line
        if c.pending is not None:
            if c.pending != carriers:
                state.event(
                    line,
                    "first-use-mismatch",
                    f"first use of carrier {name} is with set '{' '.join(carriers)}' but it was "
                    f"brought in as '{' '.join(c.pending)}' (same carriers, same order)",
                )
            c.pending = None
        if state.hook_set is not None and name in state.hook_set and state.hook_slot is None:
            hook_first = True
    if hook_first and makes_loops:
        if direction == "+":
            state.event(
                line,
                "hook-rightward",
                f"first stitch of hooked carrier(s) {' '.join(state.hook_set or ())} goes '+'; "
                "the inserting hook needs the first stitches to go '-' from the right edge",
            )
        state.hook_slot = slot + 1
    elif state.hook_set is not None and state.hook_slot is not None and slot >= state.hook_slot:
        state.event(
            line,
            "hook-blocked",
            f"{op.op} at {needle} is at or right of the inserting hook (slot {state.hook_slot}) "
            f"that still holds carrier(s) {' '.join(state.hook_set)}; releasehook first",
        )


def _observe_fabric(state: MachineState, op: Operation, x: float, slot: int) -> None:
    """Per carrier, before the needle changes: a stitch made from the wrong side, a float."""
    line, needle, direction = op.line, op.needle, op.direction
    assert direction is not None
    for name in op.carriers:
        c = state.carriers[name]
        if c.x is not None and c.dir is not None:
            behind = (
                (c.x < x if c.dir == "+" else c.x <= x)
                if direction == "+"
                else (c.x > x if c.dir == "-" else c.x >= x)
            )
            if not behind:
                state.wrong_sides.append(WrongSide(line, name, str(needle), direction, c.x, c.dir))
        fl = state.floats.loop(line, name, slot)
        if fl is not None:
            lo, hi = sorted((fl.from_slot, fl.to_slot))
            _face_float(state, line, name, lo, hi)


def _make_loops(state: MachineState, op: Operation) -> list[int]:
    """The new loops of a knit, tuck or split, one per carrier, joined to the loops they hold.

    Knit and split pull the new loops through the needle's old ones (split leaves the old loops
    on the other needle), tuck adds them beside the old ones.
    """
    line, needle = op.line, op.needle
    parents: list[int] = []
    if op.op == "knit":
        parents = state.take(needle)
        # A needle that never held a loop starts its wale here: casting on (e.g. a waste
        # yarn's knits on alternate beds). One that held loops and lost them is a fault.
        if not parents and (needle.bed, needle.index) in state.held_ever:
            state.event(
                line,
                "knit-empty",
                f"knit on empty needle {needle}: it held loops before, and they were dropped "
                "or moved away (no loop to pull through)",
            )
    elif op.op == "split":
        parents = state.move_off(needle, line)
        if _check_pair(state, op):
            state.put(op.needles[1], parents, line)
        else:  # nothing moved; the old loops stay (and get caught)
            state.put(needle, parents, line)
    new = [state.new_loop(line, name) for name in op.carriers]
    for child in new:
        for p in parents:
            state.union(child, p)
    _note_bump(state, op, new, parents)
    state.put(needle, new, line)
    _note_structure(state, op, new, parents)
    return new


def _note_bump(state: MachineState, op: Operation, new: list[int], parents: list[int]) -> None:
    """Record what the bump rules need: loops made on the front bed, a purl pulled through a
    front-bed loop of other carriers only (a yarn change inside a bump), tucks on a back needle
    that holds a loop (a tall bump's tuck) until a knit there clears them."""
    needle = op.needle
    if needle.bed == "f":
        state.front_loops.update(new)
        return
    if needle.bed != "b":
        return
    if op.op == "tuck":
        if state.held(needle):
            state.bump_tucks.update((lid, op.line) for lid in new)
        return
    for p in parents:
        state.bump_tucks.pop(p, None)
    if op.op != "knit":
        return
    below = {state.loop_carriers[p] for p in parents if p in state.front_loops}
    if below and not below.intersection(op.carriers):
        state.yarn_changes.append(
            BumpYarnChange(op.line, str(needle), tuple(op.carriers), tuple(sorted(below)))
        )


def _note_structure(state: MachineState, op: Operation, new: list[int], parents: list[int]) -> None:
    """Record what the release checks need of the new loops: how many knits in a row their
    yarn made on this needle (a tail), and each carrier's run of knits over yarns already taken
    out (a draw thread candidate)."""
    over_done = bool(parents) and all(
        not state.carriers[state.loop_carriers[p]].active for p in parents
    )
    for lid, name in zip(new, op.carriers, strict=True):
        prev = state.carriers[name].last_loop
        on_own = op.op == "knit" and prev is not None and prev in parents
        state.loop_tails.append(state.loop_tails[prev] + 1 if on_own and prev is not None else 0)
        run = state.runs.get(name)
        if op.op != "knit" or len(op.carriers) > 1 or not over_done:
            state.runs.pop(name, None)
        elif (
            run is not None
            and run.direction == op.direction
            and (run.op_index == state.op_index - 1)
        ):
            run.last, run.op_index = lid, state.op_index
        else:
            assert op.direction is not None
            state.runs[name] = KnitRun(lid, lid, op.direction, state.op_index)


def _note_draw_thread(state: MachineState, name: str) -> None:
    """``name`` goes out: its last run of knits is a draw thread if it now holds every loop on
    the needles (a separating course: pulled out later, it frees the piece above from the
    waste below)."""
    run = state.runs.pop(name, None)
    if run is None or run.last == run.first:
        return
    held = (lid for bed in state.beds.values() for loops in bed.values() for lid in loops)
    if all(run.first <= lid <= run.last for lid in held):
        state.draw_threads.append(run.first)


def _face_float(state: MachineState, line: int, carrier: str, lo: int, hi: int) -> None:
    """Record back-bed loops with no front loop at slots strictly between lo and hi."""
    shift = math.floor(state.rack)
    back, back_s = state.beds["b"], state.beds["bs"]
    front, front_s = state.beds["f"], state.beds["fs"]
    hits: list[str] = []
    if not back and not back_s:
        return
    if hi - lo - 1 <= len(back) + len(back_s):
        candidates: list[int] = list(range(lo + 1, hi))
    else:  # a long float over a sparse back bed: look only at occupied back needles
        candidates = sorted({k + shift for k in (*back, *back_s) if lo < k + shift < hi})
    for s in candidates:
        k = s - shift
        on_back = back.get(k) or back_s.get(k)
        if on_back and not (front.get(s) or front_s.get(s)):
            hits.append(f"b{k}" if back.get(k) else f"bs{k}")
    if hits:
        state.face_floats.append(FaceFloat(line, carrier, tuple(hits)))


def _carrier_op(state: MachineState, op: Operation) -> None:
    line = op.line
    cs = op.carriers
    if len(set(cs)) != len(cs):
        state.event(line, "duplicate-carrier", f"{op.op} {' '.join(cs)} repeats a carrier")
    if op.op in ("in", "inhook"):
        if op.op == "inhook" and state.hook_set is not None:
            state.event(
                line,
                "hook-busy",
                f"inhook {' '.join(cs)} while the hook still holds {' '.join(state.hook_set)}; "
                "releasehook first",
            )
        for name in cs:
            c = state.carrier(name, line)
            if c.active:
                state.event(
                    line, "in-active-carrier", f"{op.op} {name}: carrier {name} is already in"
                )
            c.active = True
            c.pending = cs
            state.runs.pop(name, None)
            c.used = False
            c.x = c.dir = None
            c.last_loop = None
            state.floats.cut(name)
            c.in_line = line
            c.last_line = line
        if op.op == "inhook":
            state.hook_set = cs
            state.hook_slot = None
    elif op.op == "releasehook":
        if state.hook_set is None:
            state.event(
                line, "release-empty", f"releasehook {' '.join(cs)} but the hook holds nothing"
            )
        else:
            if state.hook_set != cs:
                state.event(
                    line,
                    "release-wrong-set",
                    f"releasehook {' '.join(cs)} but the hook holds {' '.join(state.hook_set)}",
                )
            if state.hook_slot is None:
                state.event(
                    line,
                    "release-before-stitch",
                    f"releasehook {' '.join(cs)} before the hooked carrier made any stitch",
                )
        state.hook_set = None
        state.hook_slot = None
    else:  # out, outhook
        if op.op == "outhook" and state.hook_set is not None and not set(cs) <= set(state.hook_set):
            state.event(
                line,
                "outhook-hook-busy",
                f"outhook {' '.join(cs)} while the hook holds {' '.join(state.hook_set)}",
            )
        for name in cs:
            c = state.carrier(name, line)
            if state.hook_set is not None and name in state.hook_set:
                state.event(
                    line,
                    "out-hooked",
                    f"{op.op} {name} while carrier {name} is still on the inserting hook; "
                    "releasehook first",
                )
            if not c.active:
                state.event(line, "out-inactive", f"{op.op} {name}: carrier {name} is not in")
            elif not c.used:
                state.event(line, "out-unused", f"{op.op} {name}: carrier {name} never stitched")
            _note_draw_thread(state, name)
            c.active = False
            c.pending = None
            c.last_loop = None  # the yarn is cut (outhook) or parked (out)
            state.floats.cut(name)
            c.x = c.dir = None
        if state.hook_set is not None and set(state.hook_set) <= set(cs):
            state.hook_set = None
            state.hook_slot = None


def _rack(state: MachineState, op: Operation) -> None:
    r = op.value
    assert r is not None
    if abs(r) > state.max_racking:
        state.event(
            op.line, "rack-range", f"rack {_fmt(r)}: |racking| must be <= {_fmt(state.max_racking)}"
        )
    frac = r - math.floor(r)
    if frac not in (0.0, 0.25):
        state.event(
            op.line,
            "rack-fraction",
            f"rack {_fmt(r)}: racking must be an integer or integer + 0.25",
        )
    state.rack = r


def simulate_program(
    program: KnitoutProgram,
    *,
    max_racking: float = 4,
    max_loops: int = 4,
    bed_width: int | None = None,
) -> Simulation:
    """Run ``program`` on illuknit's machine model.

    Parameters
    ----------
    program : KnitoutProgram
        Parsed program.
    max_racking : float, keyword-only
        Largest allowed |racking| (4 for the SWG091N2 model).
    max_loops : int, keyword-only
        Most loops one needle may hold.
    bed_width : int or None, keyword-only
        Needles per bed; None takes the ``;;Width`` header, or skips the width check.

    Returns
    -------
    Simulation
    """
    hc = program.header("Carriers")
    header_carriers = frozenset(hc[0].split()) if hc is not None else None
    if bed_width is None:
        bed_width = program.width
    pos = program.header("Position")
    state = MachineState(
        header_carriers=header_carriers,
        max_racking=max_racking,
        max_loops=max_loops,
        bed_width=bed_width,
        keep_position=pos is not None and pos[0] == "Keep",
    )
    for i, op in enumerate(program.operations):
        state.op_index = i
        name = op.op
        if name in STITCH_OPS:
            _stitch(state, op)
        elif name == "xfer":
            for n in op.needles:
                state.note_needle(n, op.line)
            if _check_pair(state, op):
                src, dst = op.needles
                state.put(dst, state.move_off(src, op.line), op.line)
        elif name == "drop":
            state.note_needle(op.needle, op.line)
            state.drop(op.needle, op.line)
        elif name == "amiss":
            state.note_needle(op.needle, op.line)
        elif name == "rack":
            _rack(state, op)
        elif name in CARRIER_OPS:
            _carrier_op(state, op)
        # stitch, pause, x-*: no effect on the model
    return _result(state, program)


def _result(state: MachineState, program: KnitoutProgram) -> Simulation:
    """The frozen :class:`Simulation` of a finished run."""
    last_line = program.operations[-1].line if program.operations else 1
    roots = [state.find(i) for i in range(len(state.parent))]
    labels: dict[int, int] = {}
    components = tuple(labels.setdefault(r, len(labels)) for r in roots)
    loops_left = tuple(
        (f"{bed}{idx}", len(loops))
        for bed in ("f", "b", "fs", "bs")
        for idx, loops in sorted(state.beds[bed].items())
        if loops
    )
    carriers_left = tuple(
        CarrierEnd(c.name, c.in_line, c.last_line)
        for c in sorted(state.carriers.values(), key=lambda c: c.in_line)
        if c.active
    )
    suppressed = {
        k: n - MAX_EVENTS_PER_CODE for k, n in state.counts.items() if n > MAX_EVENTS_PER_CODE
    }
    return Simulation(
        events=tuple(state.events),
        suppressed=suppressed,
        floats=tuple(state.floats.floats),
        face_floats=tuple(state.face_floats),
        wrong_sides=tuple(state.wrong_sides),
        loop_lines=tuple(state.loop_lines),
        loop_carriers=tuple(state.loop_carriers),
        components=components,
        loops_left=loops_left,
        carriers_left=carriers_left,
        hook_left=tuple(state.hook_set or ()),
        last_line=last_line,
        drops=tuple(state.drops),
        draw_threads=tuple(state.draw_threads),
        loop_tails=tuple(state.loop_tails),
        yarn_changes=tuple(state.yarn_changes),
        uncleared_tucks=tuple(state.uncleared_tucks),
    )
