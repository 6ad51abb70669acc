"""What a pattern costs on the machine: its carriage passes and knitting time, measured by knitting
it (:func:`knit_stats`). The benchmark, the app and the ranking of designs by knitting time (which
takes it as a :data:`~illuknit.design.tiles.perception.KnitMeasure`) share this one measure.

:func:`calibrate_knit_time` fits the time model to a knit you timed (``illuknit calibrate
time``); :func:`program_run` counts the passes a machine runs for any knitout program."""

from __future__ import annotations

import os
import warnings
from typing import Any

from illuknit.core.machine import MachineSpec
from illuknit.core.pattern import LogicalPattern
from illuknit.knit.timing import MachineRun, TimingFit

__all__ = ["calibrate_knit_time", "knit_stats", "program_run"]


def knit_stats(
    pattern: LogicalPattern, *, machine: str | MachineSpec | None = None
) -> dict[str, Any]:
    """Carriage passes and knitting time as the machine runs them.

    The pattern is knit with :func:`illuknit.knit.knit_pattern` on ``machine`` (a preset of
    :func:`illuknit.core.machine.get_machine`; default the ``generic540`` bed), which reports the
    passes the SWG machine runs for the program (the pass rows of the reference backend's
    ``.dat``: carrier moves, kickbacks and hook passes included) and the time on them.

    Long floats are allowed here (``allow_long_floats=True``), unlike in the CLI and the app: the
    bench compares design methods by the passes and time their patterns take, and a pattern
    with a float over the machine's limit still has passes worth comparing; refusing it would
    drop that method's numbers from the table. The floats are not hidden: ``knit_note`` says
    how many stay long and how long the longest is. Any other scheduling refusal is a note too,
    with the numbers None.

    Returns
    -------
    dict
        ``carriage_passes`` (the machine's passes), ``transfer_passes`` (of them, transfers),
        ``scheduled_passes`` (the scheduler's own count), ``knit_time_min`` (None when
        unavailable) and ``knit_note`` (empty, or why the numbers are missing).
    """
    from illuknit.core.errors import IlluknitError
    from illuknit.core.machine import get_machine
    from illuknit.knitting import knit_pattern
    from illuknit.knitting.pipeline import LongFloatWarning, long_float_warning

    try:
        with warnings.catch_warnings():
            # kept long floats are reported in the note below, not as a warning per pattern
            warnings.simplefilter("ignore", LongFloatWarning)
            result = knit_pattern(pattern, machine=get_machine(machine), allow_long_floats=True)
    except IlluknitError as e:
        return {
            "carriage_passes": None,
            "transfer_passes": None,
            "scheduled_passes": None,
            "knit_time_min": None,
            "knit_note": f"not schedulable: {e}",
        }
    return {
        "carriage_passes": int(result.stats.passes),
        "transfer_passes": int(result.stats.transfer_passes),
        "scheduled_passes": int(result.schedule.stats.passes),
        "knit_time_min": float(result.time.seconds) / 60.0,
        "knit_note": long_float_warning(result),
    }


def program_run(text: str, machine: str | MachineSpec | None = None) -> MachineRun:
    """The passes ``machine`` runs for the knitout program ``text``: the SWG backend's
    (:func:`~illuknit.knitting.carriage.machine_run`) on a Shima, the ``.kc``'s
    (:func:`~illuknit.knitting.carriage.kc_run`) on the Kniterate.

    Raises
    ------
    OptionError
        For a machine whose passes illuknit cannot count (knitout only).
    """
    from illuknit.core.errors import OptionError
    from illuknit.core.machine import resolve_machine
    from illuknit.knitting.carriage import kc_run, machine_run

    m = resolve_machine(machine)
    backend = m.runs_on()
    if backend == "swg":
        return machine_run(text)
    if backend == "kniterate":
        from illuknit.formats.kc import knitout_to_kc

        return kc_run(knitout_to_kc(text, name="program.kc"))
    raise OptionError(f"illuknit cannot count the passes the {m.label} runs (no backend)")


def calibrate_knit_time(
    program: str | os.PathLike[str] | LogicalPattern,
    measured_minutes: float,
    *,
    machine: str | MachineSpec | None = None,
) -> TimingFit:
    """Fit the machine's time model to one timed knit: the pass overhead that makes the
    program's passes take ``measured_minutes`` (:func:`~illuknit.knit.timing.calibrate_timing`).

    ``program`` is what was knitted: a pattern (or a pattern JSON file), knitted here as
    ``illuknit knit`` does; a knitout file; or a Kniterate ``.kc``. Save the fitted machine with
    :func:`~illuknit.core.machine.save_machine_file` and name that file as the machine
    (``--machine FILE.json``) for later estimates.

    Raises
    ------
    CalibrationError
        For a time that is not positive or shorter than the carriage travel alone.
    """
    from pathlib import Path

    from illuknit.core.documents import read_text_file
    from illuknit.core.errors import CalibrationError
    from illuknit.core.machine import resolve_machine
    from illuknit.core.pattern import load_pattern
    from illuknit.knit.timing import calibrate_timing
    from illuknit.knitting import knit_pattern
    from illuknit.knitting.carriage import kc_run

    m = resolve_machine(machine)
    try:
        minutes = float(measured_minutes)
    except (TypeError, ValueError):
        raise CalibrationError(
            f"the measured time must be minutes, got {measured_minutes!r}"
        ) from None
    if isinstance(program, LogicalPattern):
        pattern: LogicalPattern | None = program
        what = "a pattern"
    else:
        path = Path(program)
        what = path.name
        pattern = load_pattern(path) if path.suffix.lower() == ".json" else None
    if pattern is not None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            text = knit_pattern(pattern, machine=m, allow_long_floats=True).text
        run = program_run(text, m)
    else:
        text = read_text_file(path, error=CalibrationError, what="program")
        run = kc_run(text) if path.suffix.lower() == ".kc" else program_run(text, m)
    return calibrate_timing(run, minutes * 60.0, m, what=what)
