"""The app's machine side: knitout for the picked pattern on the chosen machine, its check, and
the machine files and facts a machine knitter needs beside it.

    pattern -> knit_and_check(doc, machine) -> CheckedKnitout (knitout, stats, check report,
               carrier-to-yarn table, needle range, estimated time)
            -> machine_file(knit, fmt) -> Shima ``.dat`` (illuknit.formats.dat) or
                                          Kniterate ``.kc`` (illuknit.formats.kc)

:func:`knit_and_check` runs in a worker process (:meth:`illuknit.app.jobs.Job.run_isolated`), so
it takes and returns plain data.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from illuknit.app.controls import blame
from illuknit.core.errors import AppRequestError
from illuknit.core.machine import MACHINES, get_machine

if TYPE_CHECKING:
    from illuknit.core.errors import LongFloatError

__all__ = [
    "CheckedKnitout",
    "knit_and_check",
    "long_float_message",
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
    """The machine presets as the page's selector shows them, each under its own label."""
    return [
        {
            "name": key,
            # what the machine is: a real machine's name only on its real bed
            "label": spec.label,
            "description": spec.description,
            "needles": spec.needles,
            "gauge": spec.gauge,
            "carriers": len(spec.carriers),
            "max_units": spec.max_units,
            "formats": list(spec.formats),
        }
        for key, spec in MACHINES.items()
    ]


def knit_and_check(
    doc: dict[str, Any], machine: str, allow_long_floats: bool = False
) -> dict[str, Any]:
    """Compile a pattern (as JSON) to knitout on ``machine`` and check it (in a worker process).

    A float that stays longer than the machine's float limit is refused with a message for the
    designer (:func:`long_float_message`, an :class:`~illuknit.core.errors.AppRequestError` aimed at
    the knit controls) unless ``allow_long_floats``; kept long floats are in ``stats``
    (``long_floats``, ``longest_float``, ``longest_float_at``), which the page shows.
    """
    from illuknit.check import check_knitout
    from illuknit.core.errors import LongFloatError
    from illuknit.core.pattern import pattern_from_json
    from illuknit.knitting import knit_pattern
    from illuknit.knitting.pipeline import LongFloatWarning

    spec = get_machine(machine)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", LongFloatWarning)  # the page shows the stats
            result = knit_pattern(
                pattern_from_json(doc), machine=spec, allow_long_floats=bool(allow_long_floats)
            )
    except LongFloatError as e:
        raise AppRequestError(
            long_float_message(e, spec.label), field="knit", code="long_floats", status=409
        ) from None
    from illuknit.outputs.machine_sheet import machine_headline, machine_sheet

    report = check_knitout(result.knitout, split_bumps=result.split_bumps > 0)
    sched = result.schedule
    carriers: list[dict[str, Any]] = [
        {
            "carriers": list(sched.carrier_of_yarn[k]),
            "yarn": sched.yarns[k].name,
            "rgb": sched.yarns[k].hex,
        }
        for k in sorted(sched.carrier_of_yarn)
    ]
    # a machine without a yarn-inserting hook starts on a waste section and a draw thread
    for carrier, role in ((spec.draw_carrier, "draw thread"), (spec.waste_carrier, "waste yarn")):
        if carrier is not None:
            carriers.append({"carriers": [carrier], "yarn": role, "rgb": None})
    return {
        "knitout": result.text,
        # the machine's passes and time on every machine (the .kc's on the Kniterate; a Shima's
        # summary counts the SWG backend's passes already)
        "stats": (
            machine_headline(result.summary(), machine_sheet(result))
            if "kc" in spec.formats
            else result.summary()
        ),
        "report": report.to_dict(),
        "report_text": report.to_text(name="knitout.k"),
        "carriers": carriers,
        "needle_range": (sched.left, sched.left + sched.wales - 1),
    }


def long_float_message(e: LongFloatError, machine: str) -> str:
    """What the designer reads when a pattern is refused for a float over the float limit."""
    if e.course is not None:
        where = e.where.replace("course", "knitting course", 1)
    elif e.where == "the bind-off":
        where = "the bind-off (the last row ends far from where the bind-off starts)"
    else:  # the cast-on, or a machine's waste section
        where = e.where
    return (
        f"This pattern cannot be knit on the {machine} with short floats: at {where} a yarn "
        f"would float {e.length} needles behind the fabric (the machine's limit is {e.limit}), "
        "because that row has more colour regions than the machine has carriers to keep them "
        "apart. Simplify that row (fewer, larger colour regions, e.g. a smoother picture or "
        "fewer colours), choose a machine with more carriers, or tick 'allow long floats' "
        "to make the knitout anyway."
    )


def machine_file(knit: CheckedKnitout, fmt: str, *, name: str) -> bytes:
    """The machine file ``fmt`` ("dat" or "kc") of ``knit``, called ``name``; 409 when the
    knitout's machine does not take that format."""
    spec = get_machine(knit.machine)
    if fmt not in spec.formats:
        takes = " or ".join(f".{f}" for f in spec.formats) or "no machine file illuknit writes"
        raise AppRequestError(
            f"the {spec.label} takes {takes}, not .{fmt}; choose a machine that takes .{fmt} "
            "and make the knitout again",
            field="machine",
            code="wrong_format",
            status=409,
        )
    with blame("knit"):
        if fmt == "kc":
            from illuknit.formats.kc import knitout_to_kc

            return knitout_to_kc(knit.knitout, name=name).encode()
        from illuknit.formats.dat import knitout_to_dat

        return knitout_to_dat(knit.knitout)
