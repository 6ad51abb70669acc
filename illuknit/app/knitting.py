"""The app's machine side: knitout for the picked pattern on the chosen machine, its check, and
the machine files and facts a machine knitter needs beside it.

    pattern -> knit_and_check(doc, machine) -> CheckedKnitout (knitout, stats, check report,
               carrier-to-yarn table, needle range, estimated time)
            -> machine_file(knit) -> Shima ``.dat`` (illuknit.formats.dat)

:func:`knit_and_check` runs in a worker process (:meth:`illuknit.app.jobs.Job.run_isolated`), so
it takes and returns plain data.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from illuknit.app.design import blame
from illuknit.errors import AppRequestError
from illuknit.knit.machine import MACHINES, MachineSpec, get_machine

__all__ = [
    "CheckedKnitout",
    "knit_and_check",
    "machine_file",
    "machines_json",
]


@dataclass(frozen=True)
class CheckedKnitout:
    """Knitout for one pattern on one machine, the checker's report, and the knitter's facts."""

    key: str  # identifies the pattern it was made from
    machine: str  # preset name
    knitout: str
    stats: dict[str, Any]
    report: dict[str, Any]
    report_text: str
    #: which cone goes on which carrier: [{"carriers": [...], "yarn": name, "rgb": "#rrggbb"}]
    carriers: tuple[dict[str, Any], ...]
    #: first and last needle the fabric occupies (the bed's needles are 0 .. needles - 1)
    needle_range: tuple[int, int]


def machines_json() -> list[dict[str, Any]]:
    """The machine presets as the page's selector shows them."""
    return [
        {
            "name": key,
            "label": spec.name,
            "description": spec.description,
            "needles": spec.needles,
            "gauge": spec.gauge,
            "carriers": len(spec.carriers),
            "max_units": spec.max_units,
            "formats": list(formats_of(spec)),
        }
        for key, spec in MACHINES.items()
    ]


def formats_of(spec: MachineSpec) -> tuple[str, ...]:
    """Machine files illuknit writes for ``spec``: Shima ``.dat`` for the Shima SWG presets."""
    return ("dat",) if spec.name.upper().startswith("SWG") else ()


def knit_and_check(doc: dict[str, Any], machine: str) -> dict[str, Any]:
    """Compile a pattern (as JSON) to knitout on ``machine`` and check it (in a worker process)."""
    from illuknit.check import check_knitout
    from illuknit.knit import knit_pattern
    from illuknit.pattern import pattern_from_json

    result = knit_pattern(pattern_from_json(doc), machine=get_machine(machine))
    report = check_knitout(result.text)
    sched = result.schedule
    carriers = [
        {
            "carriers": list(sched.carrier_of_yarn[k]),
            "yarn": sched.yarns[k].name,
            "rgb": sched.yarns[k].hex,
        }
        for k in sorted(sched.carrier_of_yarn)
    ]
    return {
        "knitout": result.text,
        "stats": result.summary(),
        "report": report.to_dict(),
        "report_text": report.to_text(name="knitout.k"),
        "carriers": carriers,
        "needle_range": (sched.left, sched.left + sched.wales - 1),
    }


def machine_file(knit: CheckedKnitout, fmt: str) -> bytes:
    """The machine file ``fmt`` ("dat") of ``knit``; 409 when its machine does not take it."""
    spec = get_machine(knit.machine)
    if fmt not in formats_of(spec):
        raise AppRequestError(
            f"the {spec.name} does not take .{fmt} files; choose a Shima SWG machine and make "
            "the knitout again",
            field="machine",
            code="wrong_format",
            status=409,
        )
    from illuknit.formats.dat import knitout_to_dat

    with blame("knit"):
        return knitout_to_dat(knit.knitout)
