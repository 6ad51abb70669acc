"""What a pattern costs on the machine: its carriage passes and knitting time, measured by knitting
it (:func:`knit_stats`). The benchmark, the app and the ranking of designs by knitting time (which
takes it as a :data:`~illuknit.design.tiles.perception.KnitMeasure`) share this one measure."""

from __future__ import annotations

import warnings
from typing import Any

from illuknit.core.machine import MachineSpec
from illuknit.core.pattern import LogicalPattern

__all__ = ["knit_stats"]


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
