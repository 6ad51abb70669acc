"""How the machine's carriage moves: transfer settings and the time model of a pass.

:class:`TransferSettings` holds the machine settings of transfer passes, apart from the
knitting's; :class:`CarriageTiming` the time model :mod:`illuknit.knit.timing` estimates a knit
with, and :data:`SWG_TIMING` / :data:`KNITERATE_TIMING` the presets' models with their sources.
Both travel inside a :class:`~illuknit.core.machine_spec.MachineSpec`.
"""

from __future__ import annotations

from dataclasses import dataclass

from illuknit.core.errors import OptionError
from illuknit.core.machine_ranges import check_machine_value

__all__ = ["KNITERATE_TIMING", "SWG_TIMING", "CarriageTiming", "TransferSettings"]

#: TransferSettings field -> its parameter in :data:`~illuknit.core.machine_ranges.MACHINE_RANGES`
_TRANSFER_RANGE = {
    "stitch_number": "transfer_stitch_number",
    "speed_number": "transfer_speed_number",
    "roller_advance": "roller_advance",
}


@dataclass(frozen=True)
class TransferSettings:
    """Machine settings of transfer passes, apart from the knitting's.

    A loop moved between beds is stretched over two needles' hooks, so machines transfer with a
    smaller stitch (loop length) and, on the Kniterate, with no take-down pull. Each value is
    written explicitly around transfer passes; ``None`` leaves the backend's own value.

    Parameters
    ----------
    stitch_number : int or None
        Stitch number of transfer passes (Kniterate ``x-xfer-stitch-number``, 0-35 for 0-9/A-Z).
        The SWG backend has no such extension (it always transfers at the machine's own transfer
        stitch), so it must be ``None`` on a Shima.
    speed_number : int or None
        Carriage speed of transfer passes (``x-speed-number`` switched before each transfer pass
        and back to the knitting speed before the next knit pass).
    roller_advance : int or None
        Kniterate take-down roller advance of the first transfer pass of a run of transfers
        (``x-add-roller-advance`` before its first ``xfer``); the backend runs every other
        transfer pass at 0. ``None`` or 0 writes nothing (the backend's transfers run at 0).
    source : str
        Where the values come from (printed on the set-up sheet).

    Examples
    --------
    >>> from dataclasses import replace
    >>> from illuknit.core.machine import KNITERATE
    >>> replace(KNITERATE, transfer=replace(KNITERATE.transfer, speed_number=300)).transfer.speed_number
    300
    """

    stitch_number: int | None = None
    speed_number: int | None = None
    roller_advance: int | None = None
    source: str = "the machine's own transfer settings"

    def __post_init__(self) -> None:
        for name in ("stitch_number", "speed_number", "roller_advance"):
            v = getattr(self, name)
            if v is None:
                continue
            if not isinstance(v, int) or isinstance(v, bool) or v < 0:
                raise OptionError(f"transfer `{name}` must be a non-negative integer, got {v!r}")
            # the widest range of any machine; the machine's own is checked by MachineSpec
            check_machine_value(_TRANSFER_RANGE[name], v, backend=None, where="any machine")
        if not isinstance(self.source, str):
            raise OptionError(f"transfer `source` must be a string, got {self.source!r}")

    def describe(self) -> dict[str, object]:
        """The settings as JSON-ready values (``None``: the machine's own)."""
        return {
            "stitch_number": self.stitch_number,
            "speed_number": self.speed_number,
            "roller_advance": self.roller_advance or 0,
            "source": self.source,
        }


@dataclass(frozen=True)
class CarriageTiming:
    """How long the machine's carriage takes for a pass (the time model of
    :mod:`illuknit.knit.timing`)::

        pass time = (needles crossed x needle pitch + overrun) / speed + pass overhead

    where the speed is ``knit_speed`` for passes that knit, tuck or only move carriers, and
    ``transfer_speed`` for transfer passes; or, when the machine file states each pass's speed
    (the Kniterate's ``.kc``) and ``speed_unit`` is set, that speed number x ``speed_unit``.

    Parameters
    ----------
    knit_speed, transfer_speed : float
        Carriage speed in m/s of knitting and of transfer passes.
    overrun_m : float
        Carriage travel beyond the pass's outermost needles, both ends together, in m: a
        carriage reverses only once its cam system has left the last needle it works.
    pass_overhead_s : float
        Seconds per pass besides travel: reversing, racking, selecting carriers. Not published
        for any machine: fitted to a timed knit (:func:`illuknit.knit.timing.calibrate_timing`).
    knit_speed_range, transfer_speed_range, overrun_range : tuple of float
        The spread of the documented values (low, high): the estimate's range
        (:attr:`illuknit.knit.timing.TimeEstimate.low_seconds`) takes the slow and the fast
        ends with ``pass_overhead_s`` held.
    speed_unit : float or None
        m/s per speed number written in the machine file, for machines whose file states each
        pass's speed (the Kniterate); None: ``knit_speed`` / ``transfer_speed``.
    source : str
        Where the values come from.
    calibrated_from : str
        Empty, or the timed knit ``pass_overhead_s`` was fitted to.

    Examples
    --------
    >>> t = CarriageTiming(knit_speed=1.0, transfer_speed=0.5, overrun_m=0.3, pass_overhead_s=2.0)
    >>> round(t.pass_seconds(100, transfer=False, pitch_m=0.0036), 2)
    2.66
    """

    knit_speed: float
    transfer_speed: float
    overrun_m: float
    pass_overhead_s: float
    knit_speed_range: tuple[float, float] | None = None
    transfer_speed_range: tuple[float, float] | None = None
    overrun_range: tuple[float, float] | None = None
    speed_unit: float | None = None
    source: str = ""
    calibrated_from: str = ""

    def __post_init__(self) -> None:
        for name in ("knit_speed", "transfer_speed"):
            if not getattr(self, name) > 0:
                raise OptionError(f"`{name}` must be positive m/s, got {getattr(self, name)!r}")
        for name in ("overrun_m", "pass_overhead_s"):
            if not getattr(self, name) >= 0:
                raise OptionError(f"`{name}` must be >= 0, got {getattr(self, name)!r}")
        if self.speed_unit is not None and not self.speed_unit > 0:
            raise OptionError(f"`speed_unit` must be positive, got {self.speed_unit!r}")
        for name in ("knit_speed_range", "transfer_speed_range", "overrun_range"):
            r = getattr(self, name)
            if r is None:
                continue
            lo, hi = (float(v) for v in r)
            if not 0 <= lo <= hi or (name != "overrun_range" and lo <= 0):
                raise OptionError(f"`{name}` must be (low, high) with 0 < low <= high, got {r!r}")
            object.__setattr__(self, name, (lo, hi))

    def pass_seconds(
        self,
        needles: int,
        *,
        transfer: bool,
        pitch_m: float,
        speed_number: float | None = None,
        end: str = "",
    ) -> float:
        """Seconds for one pass across ``needles`` needles (``end``: ``""`` the nominal values,
        ``"slow"`` / ``"fast"`` the ends of the documented ranges)."""
        knit, xfer, overrun = self.knit_speed, self.transfer_speed, self.overrun_m
        if end:
            slow = end == "slow"
            knit = _end(self.knit_speed_range, knit, slow, low_is_slow=True)
            xfer = _end(self.transfer_speed_range, xfer, slow, low_is_slow=True)
            overrun = _end(self.overrun_range, overrun, slow, low_is_slow=False)
        if speed_number is not None and self.speed_unit is not None and speed_number > 0:
            # the file's own speed, scaled as the nominal speed is within its range
            speed = speed_number * self.speed_unit * (knit / self.knit_speed)
        else:
            speed = xfer if transfer else knit
        return (needles * pitch_m + overrun) / speed + self.pass_overhead_s

    def describe(self) -> dict[str, object]:
        """The values as JSON-ready numbers."""
        return {
            "knit_speed_m_s": self.knit_speed,
            "transfer_speed_m_s": self.transfer_speed,
            "overrun_m": self.overrun_m,
            "pass_overhead_s": self.pass_overhead_s,
            "knit_speed_range_m_s": self.knit_speed_range,
            "transfer_speed_range_m_s": self.transfer_speed_range,
            "overrun_range_m": self.overrun_range,
            "speed_unit_m_s": self.speed_unit,
            "source": self.source,
            "calibrated_from": self.calibrated_from,
        }


def _end(r: tuple[float, float] | None, nominal: float, slow: bool, *, low_is_slow: bool) -> float:
    if r is None:
        return nominal
    return r[0] if slow == low_is_slow else r[1]


#: Time model of the Shima SWG091N2 (:class:`CarriageTiming`). Speeds: flat knitting machines
#: traverse at 0.8-1.4 m/s (mapofsciences.com, "Flat knitting machine speed and carriage
#: technology"); Stoll's CMS manual recommends starting at 0.7 m/s and raising it step by step
#: ("Yarns and stitch tension"); no speed is published for the SWG-N2 itself: 0.7-1.4 m/s,
#: 1.0 nominal. Transfers: 1/3 of the knitting speed (Kniterate support: speed 100 against
#: 300) to the same (knitout-backend-kniterate #35: 300 works for transfers): 0.23-1.4 m/s,
#: 0.5 nominal. Overrun: the carriage reverses once its cam system has left the last needle
#: it works (Stoll CMS manual, "Carriage assembly"); the SWG-N2's carriage length is not
#: published: 0.15-0.5 m assumed, 0.3 nominal. Pass overhead: fitted so that the paper's
#: heart / ECG (200 x 200 stitches, measured 50 min on this machine) comes to 50 min on the
#: machine passes of illuknit's tile design of it (``benchmarks/knit_time.py``).
SWG_TIMING = CarriageTiming(
    knit_speed=1.0,
    transfer_speed=0.5,
    overrun_m=0.3,
    pass_overhead_s=2.65,
    knit_speed_range=(0.7, 1.4),
    transfer_speed_range=(0.7 / 3, 1.4),
    overrun_range=(0.15, 0.5),
    source=(
        "carriage 0.7-1.4 m/s (flat machines 0.8-1.4 m/s; Stoll's recommended start 0.7), "
        "transfers 1/3 to 1 of it, overrun 0.15-0.5 m (not published), 2.65 s a pass "
        "fitted to the paper's heart / ECG (50 min)"
    ),
)

#: Time model of the Kniterate. The ``.kc`` states each pass's speed number (300 knitting,
#: 100 transfers by default; 0-600, knit.work "Knitout extensions"); its unit is not published
#: (knitout-backend-kniterate #2: "an actual speed (though the units aren't clear)"): read as
#: mm/s, with 0.5-1.5x of that as the range. Overrun and pass overhead as on the Shima (no
#: timed Kniterate knit is published): calibrate with one of yours.
KNITERATE_TIMING = CarriageTiming(
    knit_speed=0.3,
    transfer_speed=0.1,
    overrun_m=0.3,
    pass_overhead_s=2.65,
    knit_speed_range=(0.15, 0.45),
    transfer_speed_range=(0.05, 0.15),
    overrun_range=(0.15, 0.5),
    speed_unit=0.001,
    source=(
        "the .kc's speed numbers read as mm/s (unit not published; 0.5-1.5x as the range), "
        "overrun and pass overhead as the Shima's (no timed Kniterate knit published)"
    ),
)
