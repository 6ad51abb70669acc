"""What a machine knitter needs beside the program: the machine file, and a set-up sheet.

:func:`machine_sheet` turns a :class:`~illuknit.knitting.pipeline.KnitResult` into the files its
machine reads (the Kniterate's ``.kc``) and the facts to set the machine up with: which cone goes
on which carrier (waste yarn and draw thread included), the stitch numbers used, the needles the
piece occupies, and the passes and time on that machine. For the Kniterate these are read from
the ``.kc`` itself (waste section and the backend's carriage moves included); for a Shima machine
from the SWG backend's passes (:func:`illuknit.formats.machine_passes`: kickbacks, carrier moves
and hook passes included).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

# one format check for the CLI, the sheet and the app
from illuknit.formats import check_format, machine_passes
from illuknit.knit.timing import format_duration
from illuknit.knitting.pipeline import KnitResult

__all__ = ["MachineSheet", "check_format", "machine_headline", "machine_sheet"]


@dataclass(frozen=True)
class MachineSheet:
    """Machine files by format (``{"kc": text}``) and the JSON-ready set-up summary."""

    files: dict[str, str]
    summary: dict[str, Any]


def _carrier_table(result: KnitResult) -> list[dict[str, str]]:
    m = result.machine
    sched = result.schedule
    rows: list[dict[str, str]] = []
    owner: dict[str, int] = {}
    for y, cars in sched.carrier_of_yarn.items():
        for c in cars:
            owner.setdefault(c, y)
    for c in m.carriers:
        if c == m.waste_carrier:
            rows.append(
                {"carrier": c, "role": "waste yarn", "yarn": "waste yarn (any contrast cone)"}
            )
        elif c == m.draw_carrier:
            rows.append(
                {"carrier": c, "role": "draw thread", "yarn": "draw thread (smooth, strong)"}
            )
        elif c in owner:
            yarn = sched.yarns[owner[c]]
            color = "#{:02x}{:02x}{:02x}".format(*yarn.rgb)
            rows.append({"carrier": c, "role": "pattern", "yarn": f"{yarn.name} ({color})"})
    return rows


def machine_sheet(result: KnitResult, *, name: str = "command.kc") -> MachineSheet:
    """The machine files and set-up summary of ``result``.

    Parameters
    ----------
    result : KnitResult
    name : str
        File name written in the ``.kc``'s comment line (Kniterate).

    Returns
    -------
    MachineSheet
        ``summary`` holds ``carrier_table``, ``stitch_numbers``, ``needle_range``,
        ``machine_passes``, ``machine_time_seconds``, ``machine_time``, and the settings of
        knit passes (``knit_settings``) and transfer passes (``transfer_settings``: stitch
        number, speed, roller advance and their source; ``None`` is the machine's own).
    """
    m = result.machine
    files: dict[str, str] = {}
    if result.kc_figures is not None:
        from illuknit.formats.kc import named_kc, summarise_kc

        # the result's own .kc (made once, and the same one its summary counts), named here
        kc = named_kc(result.kc_figures.kc, name)
        files["kc"] = kc
        facts = summarise_kc(kc)
        passes = result.kc_figures.passes
        estimate = result.kc_figures.time
        needles = facts["needles"]
        numbers = list(facts["stitch_numbers"])  # type: ignore[call-overload]
    elif "dat" in m.formats:
        # the Shima SWG backend's own passes: its kickbacks, carrier moves and hook passes
        runs = [p.needle_range for p in machine_passes(result.knitout)]
        passes = len(runs)
        estimate = result.time  # counted on these passes (knit_pattern)
        needles = (min(lo for lo, _ in runs), max(hi for _, hi in runs))
        found = re.findall(r"^x-stitch-number (\S+)", result.text, flags=re.MULTILINE)
        numbers = sorted(set(found))
    else:
        stats = result.stats
        passes = stats.passes + stats.hook_passes
        estimate = result.time
        spans = [p.needle_span for p in result.schedule.passes]
        needles = (min(s[0] for s in spans), max(s[1] for s in spans))
        found = re.findall(r"^x-stitch-number (\S+)", result.text, flags=re.MULTILINE)
        numbers = sorted(set(found))
    return MachineSheet(
        files=files,
        summary={
            "carrier_table": _carrier_table(result),
            "stitch_numbers": numbers,
            "needle_range": list(needles) if needles else None,  # type: ignore[call-overload]
            "machine_passes": passes,
            "machine_time_seconds": round(estimate.seconds, 1),
            "machine_time": format_duration(estimate.seconds),
            "machine_time_range": estimate.range_text,
            "machine_time_range_seconds": [
                round(estimate.low_seconds, 1),
                round(estimate.high_seconds, 1),
            ],
            "machine_bind_off_time_seconds": round(estimate.bind_off_seconds, 1),
            "time_model": estimate.model,
            "knit_settings": {"stitch_number": m.stitch_number, "speed_number": m.speed_number},
            "transfer_settings": {
                **m.transfer.describe(),
                # the take-down roller is a Kniterate setting (the SWG backend has none)
                **({} if "kc" in m.formats else {"roller_advance": None}),
            },
        },
    )


#: The schedule's own figures a Kniterate summary adds beside the ``.kc``'s headline ones
#: (``schedule_passes`` is a :class:`~illuknit.knit.schedule.ScheduleStats` field already).
_SCHEDULE_KEYS = (
    "schedule_time",
    "passes_counted_on",
    "schedule_lower_bound",
    "schedule_ratio",
)


def machine_headline(summary: dict[str, Any], sheet: MachineSheet) -> dict[str, Any]:
    """``summary`` (a :meth:`~illuknit.knitting.pipeline.KnitResult.summary`, whose headline
    ``passes`` and ``time`` are the machine's on every machine) with the sheet's facts.

    On the Kniterate the schedule's own figures (``schedule_time``, ``passes_counted_on``,
    ``schedule_lower_bound``, ``schedule_ratio``) follow the sheet's facts, in the order this
    has always written them.
    """
    late = [k for k in _SCHEDULE_KEYS if k in summary]
    head = {k: v for k, v in summary.items() if k not in late}
    return {**head, **sheet.summary, **{k: summary[k] for k in late}}
