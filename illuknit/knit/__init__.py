"""Knitting: a logical pattern -> stitches -> carriage passes -> knitout, for V-bed machines.

One module per stage::

    LogicalPattern -> stitches.lower_to_stitches -> StitchPattern
                   -> schedule.schedule_courses  -> Schedule   (one colour per course)
                   -> mixed.schedule_mixed       -> Schedule   (colour changes inside courses)
                   -> knitout.lower_to_knitout   -> KnitoutProgram (write_knitout: its text)
                      timing.estimate_knit_time  -> TimeEstimate

The machine's limits are :class:`illuknit.core.machine.MachineSpec`; the whole path in one call,
measured on the machine, is :func:`illuknit.knitting.knit_pattern`.
"""

from __future__ import annotations

from illuknit.knit.knitout import lower_to_knitout, write_knitout
from illuknit.knit.mixed import schedule_mixed
from illuknit.knit.schedule import (
    CarrierAction,
    Op,
    Pass,
    Schedule,
    ScheduleStats,
    schedule_courses,
)
from illuknit.knit.stitches import KNIT, PURL, StitchPattern, lower_to_stitches
from illuknit.knit.timing import TimeEstimate, estimate_knit_time

__all__ = [
    "KNIT",
    "PURL",
    "CarrierAction",
    "Op",
    "Pass",
    "Schedule",
    "ScheduleStats",
    "StitchPattern",
    "TimeEstimate",
    "estimate_knit_time",
    "lower_to_knitout",
    "lower_to_stitches",
    "schedule_courses",
    "schedule_mixed",
    "write_knitout",
]
