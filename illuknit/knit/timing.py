"""Knitting time of a program, from the machine's carriage speeds and its passes.

Model (documented in ``docs/knitting.md``, values on :class:`~illuknit.core.machine.CarriageTiming`)::

    time = sum over the machine's passes of
           (needles crossed x needle pitch + overrun) / speed + pass overhead

*Needles crossed* is the span of the pass: rightmost minus leftmost needle it touches, plus one
(transfer targets and parking misses included); the needle pitch comes from the gauge (3.63 mm at
7 needles per inch). The speed is the machine's knitting speed, or its slower transfer speed on
transfer passes; when the machine file states each pass's speed (the Kniterate's ``.kc``: 300
knitting, 100 transfers by default) that speed is used. The overrun is how far the carriage
travels beyond the pass's needles before it reverses; the pass overhead covers reversing,
racking and selecting carriers.

The speeds and overrun come from documented values, and their spread gives the estimate's range
(:attr:`TimeEstimate.low_seconds` .. :attr:`TimeEstimate.high_seconds`: the fast and slow ends,
the pass overhead held). No machine publishes its pass overhead: the Shima's default is fitted
to the paper's one like-for-like timed knit (``benchmarks/knit_time.py`` prints the model against
both of the paper's measured times), and :func:`calibrate_timing` fits it to a knit of yours
(``illuknit calibrate time``).

The machine's passes (:class:`MachineRun`, counted by
:func:`illuknit.knitting.carriage.machine_run` for the Shima and
:func:`illuknit.knitting.carriage.kc_run` for the Kniterate) include the backend's hook passes,
carrier moves and kickbacks; without them the schedule's own passes are used, plus an empty pass
for each of the passes the SWG backend adds for ``releasehook`` and ``outhook``.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from illuknit.core.errors import CalibrationError, OptionError
from illuknit.core.machine import MachineSpec
from illuknit.knit.ir import PassKind
from illuknit.knit.schedule import Schedule

__all__ = [
    "PAPER_SCALE",
    "MachineRun",
    "PaperScaleCheck",
    "TimeEstimate",
    "TimingFit",
    "calibrate_timing",
    "estimate_knit_time",
    "format_duration",
    "paper_scale_text",
    "run_seconds",
]


@dataclass(frozen=True)
class PaperScaleCheck:
    """The time model against a knit the paper timed that it was not fitted to.

    ``estimate_seconds`` and ``high_seconds`` are the model's estimate and the slow end of its
    range for a piece of that size, ``measured_seconds`` the paper's time
    (``python benchmarks/knit_time.py`` prints them; docs/knitting.md, Time model)."""

    piece: str
    estimate_seconds: float
    high_seconds: float
    measured_seconds: float

    @property
    def ratio(self) -> float:
        """Estimate / measured."""
        return self.estimate_seconds / self.measured_seconds

    @property
    def high_ratio(self) -> float:
        """The range's slow end / measured."""
        return self.high_seconds / self.measured_seconds


#: The paper's Van Gogh-size knit (section 9: ten hours on the SWG091N2) against the model's
#: estimate for the bundled tile design of that size (``astronaut-coffee-3``, 400 x 660
#: stitches, 3 yarns) on ``generic540``, as ``benchmarks/knit_time.py`` measured it (2026-12).
PAPER_SCALE = PaperScaleCheck(
    "the paper's Van Gogh size (400 x 660 stitches, timed at 10 h)",
    estimate_seconds=4 * 3600 + 39 * 60,
    high_seconds=6 * 3600 + 16 * 60,
    measured_seconds=10 * 3600.0,
)


def paper_scale_text(check: PaperScaleCheck = PAPER_SCALE) -> str:
    """One line: what the paper-scale check says about the model's range."""
    return (
        f"not a bound on the real time: at {check.piece} the model gives "
        f"{check.ratio:.2f}x the measured time, its slow end {check.high_ratio:.2f}x "
        "(the heart / ECG's 1.00x is fitted)"
    )


@dataclass(frozen=True)
class MachineRun:
    """The machine's passes for one program: how many of each kind, and their needle spans.

    ``kinds`` maps the backend's pass kinds (``knit``, ``transfer``, ``miss``, ``kickback``,
    ``hook-release``, ``carriage-move``, ``carrier-out``, ``drop`` ...) to counts; ``spans`` holds
    each pass's needle span (rightmost - leftmost slot + 1) in order; ``transfers`` whether
    each pass moves loops between beds, and ``speeds`` the speed number the machine file gives
    each pass (None where it gives none), for the time model.
    """

    kinds: dict[str, int]
    spans: tuple[int, ...]
    transfers: tuple[bool, ...] = ()
    speeds: tuple[float | None, ...] = ()

    def __post_init__(self) -> None:
        n = len(self.spans)
        if not self.transfers:
            object.__setattr__(self, "transfers", (False,) * n)
        if not self.speeds:
            object.__setattr__(self, "speeds", (None,) * n)
        if len(self.transfers) != n or len(self.speeds) != n:
            raise OptionError("`transfers` and `speeds` must have one entry per pass")

    @property
    def passes(self) -> int:
        return len(self.spans)


@dataclass(frozen=True)
class TimeEstimate:
    """Estimated knitting time and the quantities it was computed from.

    ``low_seconds`` .. ``high_seconds`` is the range the documented carriage speeds and overrun
    give (their fast and slow ends); ``bind_off_seconds`` is the part of ``seconds`` the chain
    bind-off and its tail take (counted on the schedule's bind-off passes).
    """

    seconds: float
    passes: int
    hook_passes: int
    needles_crossed: int
    bind_off_seconds: float = 0.0
    low_seconds: float = 0.0
    high_seconds: float = 0.0
    transfer_passes: int = 0
    #: one line: how the time was counted (model and the source of its values)
    model: str = ""

    def __str__(self) -> str:
        return format_duration(self.seconds)

    @property
    def preset_model(self) -> bool:
        """True when the time is the preset's model (not calibrated on a knit, not linear):
        the one :data:`PAPER_SCALE` checks."""
        return "calibrated on" not in self.model and not self.model.startswith("linear")

    @property
    def range_text(self) -> str:
        """``"44 min 00 s - 1 h 06 min"``: the range of the documented speeds."""
        return f"{format_duration(self.low_seconds)} - {format_duration(self.high_seconds)}"


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


def run_seconds(run: MachineRun, machine: MachineSpec, *, end: str = "") -> float:
    """Seconds for the passes of ``run`` on ``machine`` (``end``: ``""`` nominal, ``"slow"`` or
    ``"fast"`` at the ends of the documented ranges)."""
    return sum(
        machine.pass_seconds(n, transfer=x, speed_number=v, end=end)
        for n, x, v in zip(run.spans, run.transfers, run.speeds, strict=True)
    )


def _model_line(m: MachineSpec) -> str:
    if m.seconds_per_needle is not None:
        return (
            f"linear model: {m.seconds_per_turn:g} s a pass + {m.seconds_per_needle:g} s a needle"
        )
    t = m.timing
    how = f"calibrated on {t.calibrated_from}" if t.calibrated_from else t.source
    return (
        f"carriage {t.knit_speed:g} m/s, transfers {t.transfer_speed:g} m/s, overrun "
        f"{t.overrun_m:g} m, {t.pass_overhead_s:.2f} s a pass ({how})"
    )


def _schedule_run(schedule: Schedule) -> MachineRun:
    """The schedule's own passes, plus one empty pass for each hook pass the SWG backend adds."""
    spans = [p.needle_span[1] - p.needle_span[0] + 1 for p in schedule.passes]
    transfers = [p.kind is PassKind.XFER for p in schedule.passes]
    hooks = schedule.stats.hook_passes
    kinds = {"schedule": len(spans), "hook": hooks}
    return MachineRun(kinds, tuple(spans + [0] * hooks), tuple(transfers + [False] * hooks))


def estimate_knit_time(
    schedule: Schedule,
    *,
    seconds_per_needle: float | None = None,
    seconds_per_turn: float | None = None,
    run: MachineRun | None = None,
    machine: MachineSpec | None = None,
) -> TimeEstimate:
    """Estimate how long the machine takes to knit a schedule.

    Parameters
    ----------
    schedule : Schedule
    seconds_per_needle, seconds_per_turn : float, optional
        A linear model instead of the machine's (both, or one with the other 0).
    run : MachineRun, optional
        The machine's passes for the schedule's program
        (:func:`illuknit.knitting.carriage.machine_run`): the time is then counted on them, hook
        passes, carrier moves and kickbacks included. Without it, on the schedule's own passes
        plus its hook passes.
    machine : MachineSpec, optional
        The machine whose time model applies (default: the schedule's).

    Returns
    -------
    TimeEstimate
    """
    m = machine if machine is not None else schedule.machine
    if seconds_per_needle is not None or seconds_per_turn is not None:
        spn = float(seconds_per_needle or 0.0)
        spt = float(seconds_per_turn or 0.0)
        if spn < 0 or spt < 0:
            raise OptionError("`seconds_per_needle` and `seconds_per_turn` must be >= 0")
        m = replace(m, seconds_per_needle=spn, seconds_per_turn=spt)
    # the bind-off apart: it is a large share of small pieces (one step per wale)
    bind_off = sum(
        m.pass_seconds(p.needle_span[1] - p.needle_span[0] + 1, transfer=p.kind is PassKind.XFER)
        for p in schedule.passes
        if p.role in ("bind-off", "tail")
    )
    if run is not None:
        hooks = sum(run.kinds.get(k, 0) for k in ("hook-release", "carriage-move", "carrier-out"))
        passes = run.passes
    else:
        run = _schedule_run(schedule)
        hooks = schedule.stats.hook_passes
        passes = len(schedule.passes)
    return TimeEstimate(
        seconds=run_seconds(run, m),
        passes=passes,
        hook_passes=hooks,
        needles_crossed=sum(run.spans),
        bind_off_seconds=bind_off,
        low_seconds=run_seconds(run, m, end="fast"),
        high_seconds=run_seconds(run, m, end="slow"),
        transfer_passes=sum(run.transfers),
        model=_model_line(m),
    )


@dataclass(frozen=True)
class TimingFit:
    """A pass overhead fitted to a timed knit (:func:`calibrate_timing`).

    ``machine`` is the machine with the fitted :class:`~illuknit.core.machine.CarriageTiming`;
    ``travel_seconds`` the carriage travel of the program at the documented speeds, and
    ``before_seconds`` the estimate the machine gave before.
    """

    machine: MachineSpec
    measured_seconds: float
    before_seconds: float
    travel_seconds: float
    passes: int

    def report(self) -> str:
        t = self.machine.timing
        return (
            f"measured {format_duration(self.measured_seconds)} for {self.passes} passes on the "
            f"{self.machine.label}; the model said {format_duration(self.before_seconds)}.\n"
            f"carriage travel at {t.knit_speed:g} m/s (transfers {t.transfer_speed:g} m/s, "
            f"overrun {t.overrun_m:g} m): {format_duration(self.travel_seconds)}; the rest is "
            f"{t.pass_overhead_s:.2f} s a pass (reversing, racking, selecting carriers)."
        )


def calibrate_timing(
    run: MachineRun, measured_seconds: float, machine: MachineSpec, *, what: str = "a timed knit"
) -> TimingFit:
    """Fit the machine's pass overhead so that ``run`` takes ``measured_seconds``.

    One timed knit gives one equation, so one value is fitted: the pass overhead (the part no
    machine documents); the carriage speeds and overrun stay the documented ones. ``what``
    names the knit in the fitted timing's ``calibrated_from``.

    Raises
    ------
    CalibrationError
        For a time that is not positive, a program without passes, or a measured time shorter
        than the carriage travel alone at the documented speeds (a slower machine than
        documented, or the wrong program or machine).
    """
    if not measured_seconds > 0:
        raise CalibrationError(f"the measured time must be positive, got {measured_seconds!r}")
    if not run.passes:
        raise CalibrationError("the program has no carriage passes to time")
    linear = replace(machine, seconds_per_needle=None, seconds_per_turn=None)
    free = replace(linear, timing=replace(linear.timing, pass_overhead_s=0.0))
    travel = run_seconds(run, free)
    if measured_seconds < travel:
        raise CalibrationError(
            f"the measured {format_duration(measured_seconds)} is shorter than the carriage "
            f"travel alone ({format_duration(travel)} for {run.passes} passes at "
            f"{linear.timing.knit_speed:g} m/s): check the program and --machine"
        )
    overhead = (measured_seconds - travel) / run.passes
    note = f"{what}: {format_duration(measured_seconds)} for {run.passes} passes"
    timing = replace(linear.timing, pass_overhead_s=round(overhead, 4), calibrated_from=note)
    return TimingFit(
        replace(linear, timing=timing),
        float(measured_seconds),
        run_seconds(run, machine),
        travel,
        run.passes,
    )
