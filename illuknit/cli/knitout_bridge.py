"""Writing a knitout program next to a pattern's other outputs (``--knitout`` of the commands).

One machine for the whole path: the ``--machine`` option (:func:`machine_option`) names a preset
of :data:`illuknit.knit.machine.MACHINES`; :func:`resolve_machine` turns it (and a ``--gauge``)
into the :class:`~illuknit.knit.machine.MachineSpec` that sizes the picture, refuses a pattern too
wide for the bed before any design work (:func:`check_fits`), schedules the program and checks it.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import click

from illuknit.knit.machine import DEFAULT_MACHINE_NAME, MachineSpec, get_machine, machine_names
from illuknit.outputs import atomic_write_text
from illuknit.pattern import LogicalPattern

__all__ = ["check_fits", "machine_option", "resolve_machine", "write_program"]


def machine_option(
    help: str = "Knitting machine the program is made for.",
) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """``--machine NAME``: a machine preset (unknown names are refused with the known ones)."""
    return click.option(
        "--machine",
        "machine",
        metavar="NAME",
        default=None,
        help=f"{help} One of {', '.join(machine_names())} [{DEFAULT_MACHINE_NAME}].",
    )


def resolve_machine(name: str | MachineSpec | None, *, gauge: float | None = None) -> MachineSpec:
    """The machine called ``name`` (default preset when None), at ``gauge`` when one is given.

    Raises :class:`~illuknit.errors.UnknownNameError` (listing the presets) for unknown names.
    """
    spec = get_machine(name)
    if gauge is not None and gauge != spec.gauge:
        spec = spec.with_gauge(gauge)
    return spec


def check_fits(machine: MachineSpec, units: int, *, hint: str | None = None) -> None:
    """Refuse (:class:`~illuknit.errors.SchedulingError`) a pattern ``units`` wide that the bed
    cannot hold; call it before designing, so no time is spent on a piece that cannot be knit."""
    if hint is None:
        machine.check_units(units)
    else:
        machine.check_units(units, hint=hint)


def write_program(
    pattern: LogicalPattern, outdir: Path, *, machine: MachineSpec | str | None = None
) -> dict[str, Path]:
    """Compile ``pattern`` for ``machine`` to ``program.k`` and write the checker's report beside it.

    Writes ``program.k``, ``knit.json`` (passes, lower bound, time estimate, and the machine
    set-up sheet: carriers and their cones, stitch numbers, needle range, passes and time on the
    machine), ``check.json`` and ``check.txt``, and the machine's own file when illuknit writes
    one without a choice to make (``program.kc`` for the Kniterate); returns name -> path. Prints a one-line summary of each. The checker judges
    the program by the same machine the scheduler used.
    """
    import json

    from illuknit.check import check_knitout
    from illuknit.cli.summary import console
    from illuknit.knit import knit_pattern
    from illuknit.knit.machine_sheet import machine_sheet

    spec = get_machine(machine)
    result = knit_pattern(pattern, machine=spec)
    report = check_knitout(result.program, machine=spec)
    summary = result.summary()
    sheet = machine_sheet(result, name="program.kc")
    summary.update(sheet.summary)
    console().print(f"knitout: {_describe(summary)}")
    console().print(f"check: {report.to_text(name='program.k').splitlines()[0]}")
    files = {
        "program": atomic_write_text(outdir / "program.k", result.program),
        "knit": atomic_write_text(outdir / "knit.json", json.dumps(summary, indent=1) + "\n"),
        "check": atomic_write_text(outdir / "check.json", report.to_json(indent=1) + "\n"),
        "check_text": atomic_write_text(
            outdir / "check.txt", report.to_text(name="program.k") + "\n"
        ),
    }
    if "kc" in sheet.files:
        files["kc"] = atomic_write_text(outdir / "program.kc", sheet.files["kc"])
    return files


def _describe(summary: dict[str, object]) -> str:
    parts = [f"machine {summary['machine']}"] if "machine" in summary else []
    for key in ("passes", "lower_bound", "ratio"):
        if key in summary:
            parts.append(f"{key.replace('_', ' ')} {summary[key]}")
    for key, val in summary.items():
        if "time" in key and isinstance(val, (int, float, str)):
            parts.append(f"{key.replace('_', ' ')} {val}")
    return ", ".join(parts) or "written"
