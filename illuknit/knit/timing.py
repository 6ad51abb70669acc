"""Knitting-time estimate from a schedule.

Model (documented in ``docs/knitting.md``)::

    time = sum over the machine's passes of (needles crossed x seconds_per_needle + seconds_per_turn)

*Needles crossed* is the span of the pass: rightmost minus leftmost needle it touches, plus one
(transfer targets and parking misses included). The machine's passes
(:class:`MachineRun`, counted by :func:`illuknit.knitting.carriage.machine_run`) include the backend's hook passes, carrier moves
and kickbacks; without them the schedule's own passes are used, plus ``seconds_per_turn`` for
each of the empty passes the SWG backend adds for ``releasehook`` and ``outhook``. The defaults (0.01 s per needle, about 0.36 m/s at
7 gauge's 3.63 mm needle pitch, and 1.5 s per pass for turning and clearing the carriage) come from
:class:`~illuknit.core.machine.MachineSpec` and can be overridden per call. They are rough: real
machines run transfers, knitting and the yarn-inserting hook at different speeds set by the
operator; treat the estimate as a way to compare programs, not a promise.
"""

from __future__ import annotations

from dataclasses import dataclass

from illuknit.core.errors import OptionError
from illuknit.knit.schedule import Schedule

__all__ = ["MachineRun", "TimeEstimate", "estimate_knit_time", "format_duration"]


@dataclass(frozen=True)
class MachineRun:
    """The machine's passes for one program: how many of each kind, and their needle spans.

    ``kinds`` maps the backend's pass kinds (``knit``, ``transfer``, ``miss``, ``kickback``,
    ``hook-release``, ``carriage-move``, ``carrier-out``, ``drop`` ...) to counts; ``spans`` holds
    each pass's needle span (rightmost - leftmost slot + 1) in order, for the time model.
    """

    kinds: dict[str, int]
    spans: tuple[int, ...]

    @property
    def passes(self) -> int:
        return len(self.spans)


@dataclass(frozen=True)
class TimeEstimate:
    """Estimated knitting time and the quantities it was computed from."""

    seconds: float
    passes: int
    hook_passes: int
    needles_crossed: int
    seconds_per_needle: float
    seconds_per_turn: float
    #: of ``seconds``, the chain bind-off and its tail (counted on the schedule's bind-off passes)
    bind_off_seconds: float = 0.0

    def __str__(self) -> str:
        return format_duration(self.seconds)


def format_duration(seconds: float) -> str:
    """``"2 h 05 min"``, ``"12 min 30 s"`` or ``"40 s"``."""
    s = round(seconds)
    h, rem = divmod(s, 3600)
    m, sec = divmod(rem, 60)
    if h:
        return f"{h} h {m:02d} min"
    if m:
        return f"{m} min {sec:02d} s"
    return f"{sec} s"


def estimate_knit_time(
    schedule: Schedule,
    *,
    seconds_per_needle: float | None = None,
    seconds_per_turn: float | None = None,
    run: MachineRun | None = None,
) -> TimeEstimate:
    """Estimate how long the machine takes to knit a schedule.

    Parameters
    ----------
    schedule : Schedule
    seconds_per_needle, seconds_per_turn : float, optional
        Override the schedule machine's time model.
    run : MachineRun, optional
        The machine's passes for the schedule's program
        (:func:`illuknit.knitting.carriage.machine_run`): the time is then counted on them, hook
        passes, carrier moves and kickbacks included. Without it, on the schedule's own passes
        plus its hook passes.

    Returns
    -------
    TimeEstimate
    """
    m = schedule.machine
    spn = m.seconds_per_needle if seconds_per_needle is None else float(seconds_per_needle)
    spt = m.seconds_per_turn if seconds_per_turn is None else float(seconds_per_turn)
    if spn < 0 or spt < 0:
        raise OptionError("`seconds_per_needle` and `seconds_per_turn` must be >= 0")
    # the bind-off apart: it is a large share of small pieces (one step per wale)
    bind_off = sum(
        (p.needle_span[1] - p.needle_span[0] + 1) * spn + spt
        for p in schedule.passes
        if p.role in ("bind-off", "tail")
    )
    if run is not None:
        crossed = sum(run.spans)
        hooks = sum(run.kinds.get(k, 0) for k in ("hook-release", "carriage-move", "carrier-out"))
        return TimeEstimate(
            crossed * spn + run.passes * spt, run.passes, hooks, crossed, spn, spt, bind_off
        )
    passes = schedule.passes
    crossed = 0
    for p in passes:
        lo, hi = p.needle_span
        crossed += hi - lo + 1
    hooks = schedule.stats.hook_passes
    seconds = crossed * spn + (len(passes) + hooks) * spt
    return TimeEstimate(seconds, len(passes), hooks, crossed, spn, spt, bind_off)
