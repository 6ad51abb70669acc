"""Carriage passes of a Shima SWG machine for a knitout program.

The first stage of the ``.dat`` writer, and the pass model the schedulers count with. It follows the
rules of the CMU textiles-lab SWG backend (the reference converter, see
``docs/knitout-notes`` section 5), so the passes returned here are exactly the rows of the ``.dat``
that backend writes:

* operations join the open pass when its type, racking, stitch and speed numbers, direction and
  carrier list match, hook/gripper actions and presser modes are compatible, no ``pause`` is pending,
  and the needle's slot lies beyond the pass's furthest slot in the pass direction (transfers and
  drops are undirected: each slot once);
* before a pass that cannot join, each of its carriers that was left moving the same way, or parked
  beyond the pass's first slot, is kicked back by an extra carrier-move pass;
* before a stitch or transfer at a needle, every other live carrier whose yarn is attached on the
  other side of that needle is moved out of the way;
* ``releasehook`` is its own empty pass (plus an empty carriage move first when the previous pass ran
  the hook's way); ``out``/``outhook`` is a rightward pass at the carrier's last needle.

The stage is pure: :func:`plan_swg` reads a knitout program (text is parsed first) and returns an
:class:`~illuknit.formats.swg_ir.SwgPlan` whose :class:`~illuknit.formats.swg_ir.MachinePass`
records are frozen (their types live in :mod:`illuknit.formats.swg_ir`). The mutable bookkeeping
lives in a private builder (:mod:`illuknit.formats.swg_build`), each knitout operation's effect on
it in :mod:`illuknit.formats.swg_ops`.
"""

from __future__ import annotations

from illuknit.core.errors import MachineRuleError, UnsupportedKnitoutError
from illuknit.formats.swg_build import _Builder, freeze_passes, read_header
from illuknit.formats.swg_ir import MachinePass, SwgPlan
from illuknit.formats.swg_ops import apply_operation
from illuknit.knitout.parse import parse_knitout
from illuknit.knitout.program import KnitoutProgram

__all__ = ["machine_passes", "plan_swg"]


def plan_swg(program: KnitoutProgram | str) -> SwgPlan:
    """A knitout program (or its text, parsed first) -> the SWG machine's carriage passes and
    bed placement.

    Raises
    ------
    KnitoutParseError
        The text is not knitout.
    MachineRuleError
        The program breaks a rule the SWG backend enforces (carrier not brought in, misaligned
        transfer, bad racking, carriers left in, ...); the message names the line.
    UnsupportedKnitoutError
        Valid knitout this writer does not implement (split via sliders, unknown extensions,
        three or more carriers in one pass).
    """
    if isinstance(program, str):
        program = parse_knitout(program)
    width, position = read_header(program)
    b = _Builder()
    for op in program.operations:
        b.line = op.line
        if op.tabs:
            raise b.error("tokens must be separated by spaces (the SWG backend refuses tabs)")
        apply_operation(b, op)
    if b.carriers:
        raise MachineRuleError(
            "every carrier must be taken out (out/outhook) before the end; still in: "
            + " ".join(sorted(b.carriers, key=int))
        )
    if not b.passes:
        raise UnsupportedKnitoutError("the program makes no carriage pass; nothing to write")
    return SwgPlan(passes=tuple(freeze_passes(b.passes)), width=width, position=position)


def machine_passes(program: KnitoutProgram | str) -> list[MachinePass]:
    """The carriage passes the SWG machine runs for a knitout program (or its text).

    Their number equals the pass rows of the reference backend's ``.dat`` (raster height - 19).

    Examples
    --------
    >>> k = ";!knitout-2\\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\\ninhook 3\\n"
    >>> k += "knit - f2 3\\nknit - f1 3\\nreleasehook 3\\nknit + f1 3\\nknit + f2 3\\nouthook 3\\n"
    >>> [p.kind.value for p in machine_passes(k)]
    ['knit', 'carriage-move', 'hook-release', 'knit']
    """
    return list(plan_swg(program).passes)
