"""What the machine runs: pass counts and kinds of a program, as the SWG machine knits it.

A schedule's own passes are not what the machine runs: the SWG backend adds passes for the
yarn-inserting hook (release, plus an empty carriage move when the hook's pass ran the same way),
for taking carriers out, and for every carrier it has to move out of a pass's way (kickbacks),
and it merges neighbouring operations a schedule wrote as separate passes. The reported passes,
their kinds and the knitting time are therefore counted on the machine's passes for the emitted
program (:func:`illuknit.formats.swg_passes.machine_passes`, a model of the reference backend
whose pass count equals the ``.dat``'s), whenever the machine is one the SWG backend drives (the
ten-carrier Shima header). For other machines the schedule's own passes are reported.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from typing import TYPE_CHECKING

from illuknit.core.machine import MachineSpec
from illuknit.knit.ir import ActionKind, CarrierAction
from illuknit.knit.schedule import Schedule, ScheduleStats
from illuknit.knit.timing import MachineRun
from illuknit.knitout.program import KnitoutProgram

if TYPE_CHECKING:
    from illuknit.formats.kc import KcCode, KcRow

__all__ = ["kc_run", "machine_run", "machine_stats", "runs_on_swg"]


def runs_on_swg(machine: MachineSpec) -> bool:
    """True when the SWG backend drives ``machine`` (:attr:`MachineSpec.backend`)."""
    return machine.runs_on() == "swg"


def machine_run(program: KnitoutProgram | str) -> MachineRun:
    """Count the SWG machine's passes for a knitout program or its text (exactly the
    ``.dat``'s rows)."""
    from illuknit.formats.swg_passes import machine_passes

    ps = machine_passes(program)
    kinds = Counter(p.kind.value for p in ps)
    spans = tuple(p.needle_range[1] - p.needle_range[0] + 1 for p in ps)
    transfers = tuple(p.kind.value in _TRANSFER_KINDS for p in ps)
    return MachineRun(dict(kinds), spans, transfers)


def kc_run(kc: KcCode | str) -> MachineRun:
    """The Kniterate's passes of a ``.kc``: each ``>>`` / ``<<`` row, its carriage travel
    between the turning points (``/`` .. ``\\`` of the needle row before it, in needles) and the
    speed number it states. ``kc`` is what :func:`~illuknit.formats.kc.knitout_to_kc_code`
    returns (its rows as written), or a ``.kc``'s text (read back: a file's edge)."""
    from illuknit.formats.kc import KcCode, KcRow

    if isinstance(kc, KcCode):
        return _kc_rows_run(kc.rows)
    rows: list[KcRow] = []
    row = ""
    for line in kc.split("\n"):
        if line.startswith("FRNT:"):
            row = line
        elif line.startswith((">>", "<<")):
            fields = line.split()
            rows.append(
                KcRow(
                    fields[1] if len(fields) > 1 else "",
                    max(0, row.find("\\") - row.find("/")) if row else 0,
                    fields[3] if len(fields) > 3 else "",
                )
            )
    return _kc_rows_run(rows)


def _kc_rows_run(rows: Sequence[KcRow]) -> MachineRun:
    kinds: Counter[str] = Counter()
    transfers: list[bool] = []
    for r in rows:
        # transfers and splits move loops between beds ("Tr" on either side of the type)
        xfer = "Tr" in r.kind.split("-")
        kinds["transfer" if xfer else "knit" if r.kind != "Tu-Tu" else "soft-miss"] += 1
        transfers.append(xfer)
    return MachineRun(
        dict(kinds),
        tuple(r.span for r in rows),
        tuple(transfers),
        tuple(float(r.speed) if r.speed else None for r in rows),
    )


_HOOK_KINDS = ("hook-release", "carriage-move", "carrier-out")
_TRANSFER_KINDS = ("transfer", "transfer-to-sliders", "transfer-from-sliders")


def machine_stats(schedule: Schedule, run: MachineRun) -> ScheduleStats:
    """Pass counts on the machine's passes; roles (cast-on, body, bind-off) from the schedule.

    The lower bound adds to the schedule's bound the one pass each ``releasehook`` always costs
    (the machine releases the hook before a pass of its own).
    """
    own = schedule.stats
    k = run.kinds
    releases = sum(
        isinstance(s, CarrierAction) and s.action is ActionKind.RELEASEHOOK for s in schedule.steps
    )
    return ScheduleStats(
        passes=run.passes,
        knit_passes=k.get("knit", 0) + k.get("split", 0),
        transfer_passes=sum(k.get(n, 0) for n in _TRANSFER_KINDS),
        miss_passes=k.get("miss", 0),
        cast_on_passes=own.cast_on_passes,
        bind_off_passes=own.bind_off_passes,
        body_passes=own.body_passes,
        body_lower_bound=own.body_lower_bound,
        lower_bound=schedule.lower_bound + releases,
        hook_passes=sum(k.get(n, 0) for n in _HOOK_KINDS),
        kickbacks=k.get("kickback", 0),
        schedule_passes=own.passes,
    )
