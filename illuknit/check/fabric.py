"""illuknit's own fabric checks: failures a machine accepts but a knitter would not.

Neither the SWG converter nor the PyPI simulator reports these (paper section 7, Figs. 14-16,
20, 21); :func:`fabric_findings` derives them from a :class:`Simulation`:

``face-float`` (error)
    A carrier moved across needle slots whose loops sit on the back bed (purls) without stitching
    there and with no front loop in that slot to hide it: the yarn lies between the beds, so on the
    technical face it floats over the purls (Fig. 14). Fix: knit the purls in the same pass, or
    transfer them to the front before the move and back after (Algorithm 1).
``wrong-side-carrier`` (error)
    A stitch made while its carrier's logical position was ahead of the needle in the pass
    direction (a ``+`` stitch at needle n with the carrier parked right of n, or a ``-`` stitch
    with it left of n). The carriage meets the needle before the yarn does, so no yarn is laid and
    the stitch is not formed (Fig. 16, 21); converters that insert a kickback instead leave a loop
    of yarn across the fabric. Fix: alternate directions, or park the carrier with ``miss``.
``pieces`` (error)
    The loop/yarn graph has more than one connected component: the program knits separate pieces
    (for example intarsia blocks whose yarns never share a loop, Fig. 15, 20 right).
``long-float`` (warning)
    Yarn carried across more needle slots than the float limit between two consecutive loops.
``loops-left`` (error)
    Loops still on needles when the program ends; end with a bind-off, or knit waste and ``drop``
    deliberately.
``dropped-stitch`` (error)
    A ``drop`` (or a knit without yarn) released live loops that are still part of the fabric:
    the wale ladders down from there. Not reported: the release of waste yarn (loops made
    before a draw thread, the separating course a yarn knits through every loop on the needles
    before it goes out), the final release (no loop is made after the drop), and the end of a
    tail (a loop knit at least :data:`TAIL_KNITS` times in a row on its needle by its own yarn,
    as a bind-off chain ends).
``carrier-left-in`` / ``hook-left`` (error)
    A carrier never taken out (``outhook``/``out``), or the inserting hook still holding a yarn.
``bump-yarn-change`` (error, unless the program is checked as one with split bumps)
    A purl (a knit on the back bed) pulled through a loop knit on the front bed -- a bump -- by
    carriers none of which made that loop: the yarn changes inside the bump. That is exactly a
    split bump (``docs/split-bumps.md``), which a pattern must ask for; anywhere else it is a
    colour in the wrong course. A program that declares its split bumps
    (:mod:`illuknit.knitout.bumps`) or ``check_knitout(..., split_bumps=True)`` (``illuknit check
    --split-bumps``) accepts it.
``tuck-not-cleared`` (warning)
    A tuck on a back needle that holds a loop (a tall bump's tuck) whose loops were transferred
    or dropped before a knit on that needle pulled through them: the tuck's yarn leaves the
    bump (it ends behind a face stitch instead) and the bump is no taller.
"""

from __future__ import annotations

from illuknit.check.report import Finding
from illuknit.check.sim_state import MAX_EVENTS_PER_CODE, Drop
from illuknit.check.simulate import Simulation
from illuknit.knitout.floats import is_long_float

__all__ = ["FABRIC_RULES", "TAIL_KNITS", "dropped_stitches", "fabric_findings"]

#: code -> (severity, what it means)
FABRIC_RULES: dict[str, tuple[str, str]] = {
    "face-float": ("error", "yarn floats in front of back-bed (purl) loops"),
    "wrong-side-carrier": ("error", "stitch made with the carrier ahead of the carriage"),
    "pieces": ("error", "the fabric falls apart into separate pieces"),
    "long-float": ("warning", "float longer than the float limit"),
    "loops-left": ("error", "loops left on needles at the end"),
    "dropped-stitch": ("error", "a live loop of the fabric is dropped (the wale ladders down)"),
    "carrier-left-in": ("error", "carrier never taken out"),
    "hook-left": ("error", "inserting hook still holds a yarn at the end"),
    "bump-yarn-change": ("error", "the yarn changes inside a bump that is not a split bump"),
    "tuck-not-cleared": ("warning", "a bump's tuck is moved or dropped before a knit clears it"),
}


#: Knits in a row on one needle by one yarn that make a tail (its last loop may be dropped).
TAIL_KNITS = 2


def dropped_stitches(sim: Simulation) -> list[Drop]:
    """The drops of ``sim`` that release loops still part of the fabric (see ``dropped-stitch``
    in the module docstring)."""
    made = len(sim.loop_lines)
    first_draw = max(sim.draw_threads, default=-1)
    out = []
    for d in sim.drops:
        if d.made == made:
            continue  # the final release: nothing is knit after it
        if all(lid < first_draw for lid in d.loops):
            continue  # waste yarn below a draw thread
        if all(sim.loop_tails[lid] >= TAIL_KNITS for lid in d.loops):
            continue  # the end of a tail
        out.append(d)
    return out


def _finding(line: int, code: str, message: str) -> Finding:
    return Finding(line, code, FABRIC_RULES[code][0], message)


def _side(x: float, d: str) -> str:
    return f"{x:g}{d}"


def fabric_findings(
    sim: Simulation, *, float_limit: int, split_bumps: bool = False
) -> tuple[list[Finding], dict[str, int]]:
    """Fabric findings of a simulation.

    Parameters
    ----------
    sim : Simulation
    float_limit : int, keyword-only
        Longest allowed float, in needle slots crossed.
    split_bumps : bool, keyword-only
        The program knits split bumps: a yarn change inside a bump is meant.

    Returns
    -------
    findings : list of Finding
    suppressed : dict of str to int
        Findings per code beyond the listing cap.
    """
    out: list[Finding] = []
    counts: dict[str, int] = {}

    def add(line: int, code: str, message: str) -> None:
        n = counts.get(code, 0)
        counts[code] = n + 1
        if n < MAX_EVENTS_PER_CODE:
            out.append(_finding(line, code, message))

    for line, code, message in _bump_findings(sim, split_bumps=split_bumps):
        add(line, code, message)
    for ff in sim.face_floats:
        shown = ", ".join(ff.needles[:6]) + (" ..." if len(ff.needles) > 6 else "")
        add(
            ff.line,
            "face-float",
            f"carrier {ff.carrier} moves across {len(ff.needles)} back-bed loop(s) ({shown}) "
            "without stitching them: the yarn floats over the purls on the face; knit them in "
            "this pass or move them to the front first",
        )
    for ws in sim.wrong_sides:
        where = "right" if ws.direction == "+" else "left"
        add(
            ws.line,
            "wrong-side-carrier",
            f"{ws.direction} stitch at {ws.needle} but carrier {ws.carrier} sits at "
            f"{_side(ws.carrier_location, ws.carrier_direction)}, {where} of it (ahead of the "
            "carriage): the stitch will not form; alternate direction or park it with miss",
        )
    for fl in sim.floats:
        if is_long_float(fl.length, float_limit):
            add(
                fl.line,
                "long-float",
                f"carrier {fl.carrier} floats across {fl.length} needles "
                f"(slot {fl.from_slot} to {fl.to_slot}); limit {float_limit}",
            )
    for line, message in _separate_pieces(sim):
        add(line, "pieces", message)
    for d in dropped_stitches(sim):
        lid = d.loops[0]
        add(
            d.line,
            "dropped-stitch",
            f"drop of {d.needle} releases {len(d.loops)} live loop(s) of the fabric (carrier "
            f"{sim.loop_carriers[lid]}, made at line {sim.loop_lines[lid]}) while knitting goes "
            "on: the wale ladders down; knit or bind off that loop instead, or drop only after "
            "the last stitch",
        )
    if sim.loops_left:
        total = sum(n for _, n in sim.loops_left)
        shown = ", ".join(n for n, _ in sim.loops_left[:6]) + (
            " ..." if len(sim.loops_left) > 6 else ""
        )
        add(
            sim.last_line,
            "loops-left",
            f"{total} loop(s) left on {len(sim.loops_left)} needle(s) at the end ({shown}); "
            "bind off, or knit waste and drop them deliberately",
        )
    for ce in sim.carriers_left:
        add(
            ce.last_line,
            "carrier-left-in",
            f"carrier {ce.carrier} (brought in at line {ce.in_line}) is never taken out; "
            f"add 'outhook {ce.carrier}' after its last use",
        )
    if sim.hook_left:
        add(
            sim.last_line,
            "hook-left",
            f"the inserting hook still holds {' '.join(sim.hook_left)} at the end",
        )
    suppressed = {k: n - MAX_EVENTS_PER_CODE for k, n in counts.items() if n > MAX_EVENTS_PER_CODE}
    return out, suppressed


def _bump_findings(sim: Simulation, *, split_bumps: bool) -> list[tuple[int, str, str]]:
    """(line, code, message) of the bump rules: yarn changes inside bumps (unless split bumps
    are meant) and bump tucks moved or dropped before a knit cleared them."""
    out = []
    if not split_bumps:
        for yc in sim.yarn_changes:
            out.append(
                (
                    yc.line,
                    "bump-yarn-change",
                    f"purl at {yc.needle} in carrier {' '.join(yc.carriers)} is pulled through a "
                    f"knit loop of carrier {' '.join(yc.below)}: the yarn changes inside a bump. "
                    "Only a split bump does that, and this program does not declare split bumps "
                    "('; illuknit-bumps: split N'); check with --split-bumps if it has them",
                )
            )
    for ut in sim.uncleared_tucks:
        out.append(
            (
                ut.line,
                "tuck-not-cleared",
                f"the tuck on {ut.needle} (line {ut.tuck_line}) joined the loop it holds, but "
                "the loops are moved or dropped here before a knit on that needle pulled through "
                "them: the tuck's yarn leaves the bump; knit the needle first",
            )
        )
    return out


def _separate_pieces(sim: Simulation) -> list[tuple[int, str]]:
    """(line, message) where each piece after the first starts, when the fabric falls apart."""
    if sim.pieces <= 1:
        return []
    first: dict[int, int] = {}
    carriers: dict[int, set[str]] = {}
    for lid, comp in enumerate(sim.components):
        first.setdefault(comp, lid)
        carriers.setdefault(comp, set()).add(sim.loop_carriers[lid])
    return [
        (
            sim.loop_lines[first[comp]],
            f"piece {comp + 1} of {sim.pieces} starts here (carrier(s) "
            f"{' '.join(sorted(carriers[comp]))}) and never shares a loop or yarn with piece 1: "
            "the fabric falls apart; catch the yarns (e.g. a plated stitch at the colour change)",
        )
        for comp in range(1, sim.pieces)
    ]
