"""The knitting machine as data: every machine limit and default lives in :class:`MachineSpec`.

Nothing in illuknit hard-codes a needle count, a carrier name, a racking limit, a float limit or a
speed: the lowering, the scheduler, the knitout writer, the time model and the checker all read
them from the spec they are given, and one spec travels with a piece from scheduling to checking.

Presets (:data:`MACHINES`, looked up with :func:`get_machine`; ``--machine NAME`` on the CLI):

``generic540`` (the default)
    A generic 540-needle V-bed with the rules of the paper's machine, a 7-gauge Shima Seiki
    SWG091N2, as the CMU knitout-to-dat converter and the PyPI virtual knitting machine model it:
    540 needles per bed, carriers ``"1"`` .. ``"10"``, racking within +/-4. The converter assumes
    540 needles when a program has no ``;;Width`` header (``knitout-to-dat.js``), so every
    program written for it fits this bed. No SWG091N2 has 540 needles, so it is called what it
    is (:attr:`MachineSpec.label`: ``generic 540-needle V-bed (SWG091N2 rules)``); its knitout
    still says ``;;Machine: SWG091N2``, the model whose rules and backend it follows, and a
    comment line under the header names the bed.
``swg091n2``
    The same machine with its physical needle count. The SWG091N2 is one of Shima Seiki's compact
    WHOLEGARMENT machines (the SWG-N2 series: SWG041N2, SWG061N2, SWG091N2; e.g. asiantex.net,
    2020, "Shima Seiki releases additional data for knitted masks") with a 36-inch (91 cm)
    needle bed: at 7 needles per inch that is 252 needles per bed. Knitout programs published
    for this machine by the CMU Textiles Lab declare ``;;Width: 250``, consistent with it. Pieces
    wider than 247 stitches (123 units) do not fit this bed. The only preset called
    ``SWG091N2`` (:attr:`MachineSpec.real_bed`); with another ``--machine-width`` or ``--gauge``
    it is a generic bed with its rules.

``kniterate``
    The Kniterate: 252 needles at 7 gauge (the bed ``knitout-to-kcode.js`` assumes), six carriers
    (``;;Carriers: 1 2 3 4 5 6`` exactly), racking within +/-4, no yarn-inserting hook: yarns come
    in with ``in`` from the edge and the piece starts on a waste section and draw thread
    (:mod:`illuknit.knit.hookless`). Carrier 1 holds the draw thread and 6 the waste yarn, a common
    convention, leaving 2-5 for the pattern. Stitch numbers run 0-9/A-Z (``x-stitch-number``); 6
    is the waste section's default. Its machine file is the ``.kc`` (:mod:`illuknit.formats.kc`).

A program's own headers name its machine: :func:`machine_from_headers` maps ``;;Machine``,
``;;Width``, ``;;Gauge`` and ``;;Carriers`` back to a spec (the checker's default).
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
from pathlib import Path

from illuknit.core.errors import OptionError, SchedulingError, UnknownNameError
from illuknit.core.gauge import STOCKINETTE_COURSE_ASPECT, Gauge
from illuknit.core.machine_ranges import check_machine_value, ranges_for

__all__ = [
    "BACKENDS",
    "DEFAULT_MACHINE",
    "DEFAULT_MACHINE_NAME",
    "KNITERATE",
    "KNITERATE_TIMING",
    "MACHINES",
    "SWG_CARRIERS",
    "SWG_TIMING",
    "BedFitWarning",
    "CarriageTiming",
    "MachineSpec",
    "TransferSettings",
    "get_machine",
    "load_machine_file",
    "machine_from_headers",
    "machine_names",
    "resolve_machine",
    "save_machine_file",
]

_POSITIONS = ("Left", "Right", "Center", "Keep")

#: The carriers of a Shima machine, the only carrier header the SWG backend accepts.
SWG_CARRIERS = tuple(str(i) for i in range(1, 11))

#: Reference backends a machine's knitout can go through (:attr:`MachineSpec.backend`).
BACKENDS = ("swg", "kniterate")

#: TransferSettings field -> its parameter in :data:`~illuknit.core.machine_ranges.MACHINE_RANGES`
_TRANSFER_RANGE = {
    "stitch_number": "transfer_stitch_number",
    "speed_number": "transfer_speed_number",
    "roller_advance": "roller_advance",
}


class BedFitWarning(UserWarning):
    """A design that fits no bed of the machine it is for, or only a generic bed and not the real
    machine whose rules it has (:meth:`MachineSpec.fit_note`)."""


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


def _check_field_types(spec: MachineSpec) -> None:
    """Each field of ``spec`` of its type, before any range is checked (a field of the wrong
    type is named, not a TypeError from deep inside)."""
    from illuknit.core.arguments import check_bool, check_instance, got

    real, whole = (int, float), int
    kinds: dict[str, tuple[type, ...]] = {
        "name": (str,),
        "position": (str,),
        "yarn_weight": (str,),
        "description": (str,),
        "needles": (whole,),
        "max_racking": (whole,),
        "float_limit": (whole,),
        "park_distance": (whole,),
        "gauge": real,
        "course_aspect": real,
        "timing": (CarriageTiming,),
        "transfer": (TransferSettings,),
    }
    optional: dict[str, tuple[type, ...]] = {
        "stitch_number": (whole,),
        "cast_on_stitch_number": (whole,),
        "speed_number": (whole,),
        "seconds_per_needle": real,
        "seconds_per_turn": real,
        "waste_carrier": (str,),
        "draw_carrier": (str,),
        "backend": (str,),
        "fabric": (Gauge,),
    }
    for name, cls in (*kinds.items(), *optional.items()):
        value = getattr(spec, name)
        if not (value is None and name in optional):
            check_instance(value, cls, name)
    check_bool(spec.inserting_hook, "inserting_hook")
    for name, item in (("carriers", (str, int)), ("formats", (str,))):
        value = getattr(spec, name)
        if not isinstance(value, (tuple, list)) or not all(
            isinstance(v, item) and not isinstance(v, bool) for v in value
        ):
            raise OptionError(f"`{name}` must be a tuple of names, got {got(value)}")


@dataclass(frozen=True)
class MachineSpec:
    """A V-bed knitting machine and the settings illuknit knits with.

    Parameters
    ----------
    name : str
        Machine model written to the ``;;Machine:`` header: the model whose rules (carriers,
        racking, backend) the spec follows. People see :attr:`label`, which says whether the
        spec is that machine or a generic bed with its rules.
    needles : int
        Needles per bed (the ``;;Width:`` header). Needle numbers used are ``0 .. needles - 1``.
    gauge : float
        Needles per inch (the ``;;Gauge:`` header); also sets the physical stitch width.
    carriers : tuple of str
        Carrier names, front rail to back rail (the ``;;Carriers:`` header).
    max_racking : int
        Largest allowed ``|rack|`` in needle pitches.
    float_limit : int
        Longest acceptable float, in needles (a yarn crossing this many needles without knitting).
    park_distance : int
        How many needles beyond the fabric edge an idle carrier is parked (with ``miss``), so that
        it is never in the way of another carrier's knitting.
    position : str
        ``;;Position:`` header: ``Left``, ``Right``, ``Center`` or ``Keep``.
    stitch_number, cast_on_stitch_number, speed_number : int or None
        Shima stitch (loop length) and speed table indices, written as ``x-stitch-number`` /
        ``x-speed-number``; ``None`` leaves the machine's own defaults.
    yarn_weight : str
        Yarn description for the ``;;Yarn-N:`` headers (e.g. ``"50-50"``).
    timing : CarriageTiming
        Time model: carriage speeds, overrun and pass overhead (:data:`SWG_TIMING`,
        :data:`KNITERATE_TIMING`; calibrate from a timed knit with ``illuknit calibrate time``).
    seconds_per_needle, seconds_per_turn : float or None
        A simpler linear model of your own instead of ``timing`` (both must be given): each pass
        takes ``seconds_per_turn`` plus ``seconds_per_needle`` per needle crossed.
    course_aspect : float
        Course height divided by stitch width (default 0.7, the 5 : 7 stitch-to-row ratio of
        stocking stitch; unmeasured on illusion fabric): the row gauge of :attr:`fabric_gauge`.
    fabric : Gauge or None
        The finished fabric's measured stitch and row gauge (from a swatch, ``--fabric-gauge``);
        ``None`` derives it from ``gauge`` and ``course_aspect``.
    description : str
        One line for people choosing a machine (the app's selector, ``--help``).
    inserting_hook : bool
        Whether yarns can come in on a yarn-inserting hook (``inhook``/``releasehook``/
        ``outhook``). Without one (the Kniterate) every yarn enters with ``in`` from the edge and
        the piece starts on a waste section.
    waste_carrier, draw_carrier : str or None
        Carriers reserved for the waste yarn and the draw thread of the waste section (machines
        without an inserting hook); they are not free for the pattern's colours.
    formats : tuple of str
        Machine files illuknit can write for this machine besides knitout (``"dat"``, ``"kc"``).
    transfer : TransferSettings
        Stitch number, speed and roller advance of transfer passes (override per run with
        ``dataclasses.replace``; ``--xfer-stitch``, ``--xfer-speed``, ``--xfer-roller``).
    backend : {"swg", "kniterate"} or None
        The reference backend that turns this machine's knitout into what the machine runs:
        ``"swg"`` (Shima SWG, ``.dat``; the knitting path then counts the machine's passes as
        that backend makes them), ``"kniterate"`` (``.kc``), or None: not said, taken as
        ``"swg"`` for a machine with the Shima carriers (:data:`SWG_CARRIERS`), else knitout only
        (:meth:`runs_on`).
    real_bed : tuple of (int, float) or None
        Needles per bed and gauge of the real machine ``name``: the spec is that machine only
        when its own ``needles`` and ``gauge`` are these (:attr:`label`); None: no real machine
        has this bed (a generic bed with ``name``'s rules).

    Examples
    --------
    >>> MachineSpec().needles
    540
    >>> MachineSpec(needles=252).with_width(300).needles
    300
    """

    name: str = "SWG091N2"
    needles: int = 540
    gauge: float = 7.0
    carriers: tuple[str, ...] = tuple(str(i) for i in range(1, 11))
    max_racking: int = 4
    float_limit: int = 20
    park_distance: int = 2
    position: str = "Center"
    stitch_number: int | None = None
    cast_on_stitch_number: int | None = None
    speed_number: int | None = None
    yarn_weight: str = "50-50"
    timing: CarriageTiming = SWG_TIMING
    seconds_per_needle: float | None = None
    seconds_per_turn: float | None = None
    course_aspect: float = STOCKINETTE_COURSE_ASPECT
    description: str = ""
    inserting_hook: bool = True
    waste_carrier: str | None = None
    draw_carrier: str | None = None
    formats: tuple[str, ...] = ("dat",)
    transfer: TransferSettings = TransferSettings()
    fabric: Gauge | None = None
    backend: str | None = None
    real_bed: tuple[int, float] | None = None

    def __post_init__(self) -> None:
        _check_field_types(self)

        def positive(name: str, value: float, *, integer: bool = False) -> None:
            if integer and (not isinstance(value, int) or isinstance(value, bool)):
                raise OptionError(f"`{name}` must be an integer, got {value!r}")
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise OptionError(f"`{name}` must be a number, got {value!r}")
            if not value > 0:
                raise OptionError(f"`{name}` must be positive, got {value!r}")

        positive("needles", self.needles, integer=True)
        positive("gauge", self.gauge)
        positive("max_racking", self.max_racking, integer=True)
        positive("float_limit", self.float_limit, integer=True)
        positive("park_distance", self.park_distance, integer=True)
        positive("course_aspect", self.course_aspect)
        linear = (self.seconds_per_needle, self.seconds_per_turn)
        if (linear[0] is None) != (linear[1] is None):
            raise OptionError("give both `seconds_per_needle` and `seconds_per_turn`, or neither")
        if linear[0] is not None and (linear[0] < 0 or linear[1] < 0):  # type: ignore[operator]
            raise OptionError("time model seconds must be >= 0")
        carriers = tuple(str(c) for c in self.carriers)
        if not carriers or len(set(carriers)) != len(carriers):
            raise OptionError(f"`carriers` must be distinct names, got {self.carriers!r}")
        if any(not c or any(ch.isspace() for ch in c) for c in carriers):
            raise OptionError("carrier names must be non-empty and contain no spaces")
        object.__setattr__(self, "carriers", carriers)
        if self.backend is not None and self.backend not in BACKENDS:
            raise OptionError(
                f"`backend` must be one of {', '.join(BACKENDS)} or None, got {self.backend!r}"
            )
        if self.backend == "swg" and carriers != SWG_CARRIERS:
            raise OptionError("the SWG backend takes the Shima carriers 1 to 10 only")
        for name in ("waste_carrier", "draw_carrier"):
            c = getattr(self, name)
            if c is not None and c not in carriers:
                raise OptionError(f"`{name}` {c!r} is not one of the carriers")
        if self.position not in _POSITIONS:
            raise OptionError(
                f"`position` must be one of {', '.join(_POSITIONS)}, got {self.position!r}"
            )
        for name in ("stitch_number", "cast_on_stitch_number", "speed_number"):
            v = getattr(self, name)
            if v is not None and (not isinstance(v, int) or isinstance(v, bool) or v < 0):
                raise OptionError(f"`{name}` must be a non-negative integer or None, got {v!r}")
        self._check_ranges()
        rb = self.real_bed
        if rb is not None and not (
            isinstance(rb, tuple)
            and len(rb) == 2
            and isinstance(rb[0], int)
            and isinstance(rb[1], (int, float))
        ):
            raise OptionError(f"`real_bed` must be (needles, gauge) or None, got {rb!r}")
        if "kc" not in self.formats:
            # the SWG backend knows neither x-xfer-stitch-number nor take-down roller extensions
            if self.transfer.stitch_number is not None:
                raise OptionError(
                    f"the {self.label} takes no transfer stitch number (the SWG backend transfers "
                    "at the machine's own transfer stitch); set the transfer speed only"
                )
            if self.transfer.roller_advance:
                raise OptionError(f"the {self.label} has no roller-advance setting")

    def _check_ranges(self) -> None:
        """Every machine value within the range of :data:`~illuknit.core.machine_ranges.
        MACHINE_RANGES` for this machine's backend (:class:`MachineValueError` otherwise)."""
        backend = self.runs_on()
        values: dict[str, object] = {
            "needles": self.needles,
            "gauge": self.gauge,
            "max_racking": self.max_racking,
            "stitch_number": self.stitch_number,
            "cast_on_stitch_number": self.cast_on_stitch_number,
            "speed_number": self.speed_number,
            "transfer_stitch_number": self.transfer.stitch_number,
            "transfer_speed_number": self.transfer.speed_number,
            "roller_advance": self.transfer.roller_advance or None,
        }
        for name, value in values.items():
            if value is not None:
                check_machine_value(name, value, backend=backend)

    # -- derived quantities --------------------------------------------------------------------
    @property
    def is_real(self) -> bool:
        """Whether this is the real machine :attr:`name` (its needles and gauge are
        :attr:`real_bed`), not a generic bed that borrows its rules."""
        return self.real_bed is not None and (self.needles, self.gauge) == self.real_bed

    @property
    def label(self) -> str:
        """What people are told the machine is: the model's name on its real bed, else what it
        is, e.g. ``generic 540-needle V-bed (SWG091N2 rules)``.

        >>> MACHINES["swg091n2"].label, MACHINES["generic540"].label
        ('SWG091N2', 'generic 540-needle V-bed (SWG091N2 rules)')
        >>> MACHINES["swg091n2"].with_width(300).label
        'generic 300-needle V-bed (SWG091N2 rules)'
        """
        if self.is_real:
            return self.name
        return f"generic {self.needles}-needle V-bed ({self.name} rules)"

    @property
    def bed_text(self) -> str:
        """The bed in a sentence: ``the SWG091N2's bed of 252 needles`` on a real machine,
        ``the generic 540-needle V-bed (SWG091N2 rules)`` on any other."""
        if self.is_real:
            return f"the {self.name}'s bed of {self.needles} needles"
        return f"the {self.label}"

    @property
    def needle_pitch_cm(self) -> float:
        """Distance between neighbouring needles, in cm."""
        return 2.54 / self.gauge

    @property
    def fabric_gauge(self) -> Gauge:
        """Stitch and row gauge of the fabric: ``fabric`` when measured, else one stitch per
        needle pitch and courses ``course_aspect`` of a pitch tall (with that source)."""
        if self.fabric is not None:
            return self.fabric
        return Gauge.for_machine(
            self.gauge,
            self.course_aspect,
            source=f"{self.label}: one stitch per needle at gauge {self.gauge:g}, rows at "
            f"{self.course_aspect:g} of a stitch (the 5:7 stocking-stitch ratio; unmeasured, "
            "knit a swatch)",
        )

    @property
    def max_fabric_width(self) -> int:
        """Widest fabric in stitches: the bed minus room to park carriers on both sides."""
        return self.needles - 2 * self.park_distance - 1

    @property
    def fabric_left(self) -> int:
        """Needle of the fabric's leftmost wale (room to park a carrier at needle >= 1 on its left)."""
        return self.park_distance + 1

    @property
    def cast_on_stitch(self) -> int | None:
        """Stitch number of the cast-on passes: ``cast_on_stitch_number``, else ``stitch_number``."""
        if self.cast_on_stitch_number is not None:
            return self.cast_on_stitch_number
        return self.stitch_number

    @property
    def pattern_carriers(self) -> tuple[str, ...]:
        """Carriers free for the pattern's yarns: all but the waste-yarn and draw-thread ones."""
        reserved = {self.waste_carrier, self.draw_carrier}
        return tuple(c for c in self.carriers if c not in reserved)

    @property
    def needle_pitch_m(self) -> float:
        """Distance between neighbouring needles, in m."""
        return 0.0254 / self.gauge

    def pass_seconds(
        self,
        needles_crossed: int,
        *,
        transfer: bool = False,
        speed_number: float | None = None,
        end: str = "",
    ) -> float:
        """Time model: seconds for one carriage pass across ``needles_crossed`` needles
        (:class:`CarriageTiming`, or the linear ``seconds_per_*`` model when set)."""
        if self.seconds_per_needle is not None and self.seconds_per_turn is not None:
            return needles_crossed * self.seconds_per_needle + self.seconds_per_turn
        return self.timing.pass_seconds(
            needles_crossed,
            transfer=transfer,
            pitch_m=self.needle_pitch_m,
            speed_number=speed_number,
            end=end,
        )

    @property
    def max_units(self) -> int:
        """Widest pattern in units (one unit is two wales) that fits on the bed."""
        return self.max_fabric_width // 2

    def check_width(self, wales: int) -> None:
        """Raise :class:`~illuknit.core.errors.SchedulingError` unless ``wales`` fit on the bed."""
        if wales > self.max_fabric_width:
            raise SchedulingError(
                f"piece is {wales} stitches wide but {self.bed_text} holds at most "
                f"{self.max_fabric_width} (use a narrower pattern or a wider --machine)"
            )

    def check_units(
        self, units: int, *, hint: str = "use a narrower --width or a wider --machine"
    ) -> None:
        """Raise :class:`~illuknit.core.errors.SchedulingError` unless a pattern ``units`` wide fits.

        Called before any design work, so that a pattern too wide for the bed is refused at once;
        ``hint`` ends the message (what the user can change).
        """
        if units > self.max_units:
            raise SchedulingError(
                f"pattern is {units} units = {2 * units} stitches wide but {self.bed_text} "
                f"holds at most {self.max_units} units ({self.max_fabric_width} stitches); {hint}"
            )

    def fit_note(self, units: int) -> str | None:
        """What a designer should know about a pattern ``units`` wide on this machine: that no
        bed of it holds the pattern (``knit`` would refuse it), or, on a generic bed, that the
        real machine whose rules it has does not; None when it fits.

        >>> print(MACHINES["generic540"].fit_note(130))
        the pattern is 130 units = 260 stitches wide: it fits the generic 540-needle V-bed (SWG091N2 rules) but not a real SWG091N2, whose 252 needles hold at most 123 units (--machine swg091n2)
        >>> MACHINES["generic540"].fit_note(100) is None
        True
        """
        size = f"the pattern is {units} units = {2 * units} stitches wide"
        if units > self.max_units:
            return (
                f"{size}, but {self.bed_text} holds at most {self.max_units} units "
                f"({self.max_fabric_width} stitches): `illuknit knit` would refuse it; "
                f"make it at most {self.max_units} units wide or choose a wider "
                "--machine"
            )
        if self.is_real:
            return None
        for key, real in MACHINES.items():
            if real.is_real and real.name == self.name and units > real.max_units:
                return (
                    f"{size}: it fits {self.bed_text} but not a real {real.name}, whose "
                    f"{real.needles} needles hold at most {real.max_units} units (--machine {key})"
                )
        return None

    def with_width(self, needles: int) -> MachineSpec:
        """A copy with another bed width (the ``--machine-width`` option)."""
        spec = replace(self, needles=needles)
        return replace(spec, description=spec.label)

    def with_gauge(self, gauge: float) -> MachineSpec:
        """A copy with another gauge (the ``--gauge`` option)."""
        spec = replace(self, gauge=gauge)
        return replace(spec, description=f"{spec.label} at gauge {gauge:g}")

    def runs_on(self) -> str | None:
        """The reference backend of this machine: :attr:`backend`, or when it is not said,
        ``"swg"`` for the Shima carriers and None (knitout only) for any others."""
        if self.backend is not None:
            return self.backend
        return "swg" if self.carriers == SWG_CARRIERS else None


#: Machine presets by name (lower case); see the module docstring for their sources.
MACHINES: dict[str, MachineSpec] = {
    "generic540": MachineSpec(
        backend="swg",
        description="generic 540-needle V-bed (SWG091N2 rules), 7 gauge: the bed the reference "
        "knitout tools assume; the real SWG091N2 has 252 needles (swg091n2)",
    ),
    "swg091n2": MachineSpec(
        needles=252,
        backend="swg",
        real_bed=(252, 7.0),
        description="7-gauge Shima SWG091N2 with its physical 36-inch bed (252 needles)",
    ),
    "kniterate": MachineSpec(
        name="Kniterate",
        needles=252,
        gauge=7.0,
        carriers=("1", "2", "3", "4", "5", "6"),
        max_racking=4,
        stitch_number=6,
        speed_number=300,
        inserting_hook=False,
        waste_carrier="6",
        draw_carrier="1",
        formats=("kc",),
        timing=KNITERATE_TIMING,
        transfer=TransferSettings(
            stitch_number=3,
            speed_number=100,
            roller_advance=0,
            source=(
                "Kniterate support, 'Transfers': speed 100 and roller 0 for transfers; "
                "stitch about half the knitting's (6 -> 3, knitout-backend-kniterate #35)"
            ),
        ),
        backend="kniterate",
        real_bed=(252, 7.0),
        description="Kniterate, 252 needles, 6 carriers (1 draw thread, 6 waste, 2-5 pattern)",
    ),
}

#: Preset used when no machine is named (the bed the reference tools assume).
DEFAULT_MACHINE_NAME = "generic540"

#: The default machine: a generic 540-needle V-bed with the SWG091N2's rules (the bed the reference
#: tools assume; the paper's real SWG091N2 is ``MACHINES["swg091n2"]``).
DEFAULT_MACHINE = MACHINES[DEFAULT_MACHINE_NAME]

#: The Kniterate preset.
KNITERATE = MACHINES["kniterate"]


def machine_names() -> list[str]:
    """Names of the presets in :data:`MACHINES`."""
    return list(MACHINES)


#: ``kind`` of a machine file (:func:`save_machine_file`).
MACHINE_FILE_KIND = "illuknit-machine"


def save_machine_file(spec: MachineSpec, path: str | os.PathLike[str], *, base: str) -> Path:
    """Write ``spec`` as a machine file: the preset ``base`` and the time model
    (:class:`CarriageTiming`) measured on your machine. ``--machine FILE.json`` (and
    :func:`get_machine`) read it back, so later estimates use the calibration."""
    from illuknit.core.files import atomic_write_text

    doc = {
        "kind": MACHINE_FILE_KIND,
        "version": 1,
        "base": base,
        "timing": {f.name: getattr(spec.timing, f.name) for f in fields(CarriageTiming)},
    }
    return atomic_write_text(path, json.dumps(doc, indent=1) + "\n")


def load_machine_file(path: str | os.PathLike[str]) -> MachineSpec:
    """The machine a machine file describes (:func:`save_machine_file`): its base preset with
    the file's time model.

    Raises
    ------
    OptionError
        For a missing, unreadable or malformed file (one line saying what is wrong).
    """
    from illuknit.core.documents import read_json_file

    doc = read_json_file(path, error=OptionError, what="machine")
    if not isinstance(doc, dict) or doc.get("kind") != MACHINE_FILE_KIND:
        raise OptionError(f"{path} is not an illuknit machine file (written by `calibrate time`)")
    base = get_machine(str(doc.get("base", "")))
    raw = doc.get("timing")
    names = {f.name for f in fields(CarriageTiming)}
    if not isinstance(raw, dict) or not set(raw) <= names:
        raise OptionError(f"{path}: `timing` must be an object with keys among {sorted(names)}")
    try:
        timing = replace(base.timing, **raw)
    except (TypeError, ValueError) as e:
        raise OptionError(f"{path}: bad `timing`: {e}") from None
    return replace(base, timing=timing, description=f"{base.label} calibrated ({Path(path).name})")


def get_machine(name: str | MachineSpec | None = None) -> MachineSpec:
    """The preset called ``name`` (case-insensitive); ``None`` gives the default machine; a
    name ending in ``.json`` is a machine file (:func:`load_machine_file`).

    A :class:`MachineSpec` is returned as it is, so callers may take either.

    Raises
    ------
    UnknownNameError
        For a name not in :data:`MACHINES`; the message lists the known ones.

    Examples
    --------
    >>> get_machine("swg091n2").needles
    252
    """
    if name is None:
        return MACHINES[DEFAULT_MACHINE_NAME]
    if isinstance(name, MachineSpec):
        return name
    key = str(name).strip().lower()
    if key.endswith(".json"):
        return load_machine_file(str(name).strip())
    if key not in MACHINES:
        raise UnknownNameError("machine", str(name), machine_names())
    return MACHINES[key]


def resolve_machine(machine: str | MachineSpec | None = None) -> MachineSpec:
    """The machine an argument names: a preset name (case-insensitive), a
    :class:`MachineSpec` (returned as it is) or None (the default machine).

    Every public call that takes a ``machine`` reads it through this function, so a name and
    the spec it names give the same result everywhere.

    Raises
    ------
    UnknownNameError
        For a name not in :data:`MACHINES`; the message lists the valid names.
    OptionError
        For anything else (the message names the argument and its type).

    Examples
    --------
    >>> resolve_machine("Kniterate") is MACHINES["kniterate"]
    True
    >>> resolve_machine("swg09")
    Traceback (most recent call last):
    ...
    illuknit.core.errors.UnknownNameError: unknown machine 'swg09'; valid: generic540, swg091n2, kniterate
    """
    if machine is not None and not isinstance(machine, (str, MachineSpec)):
        raise OptionError(
            "`machine` must be a machine name "
            f"({', '.join(machine_names())}) or a MachineSpec, got {type(machine).__name__}"
        )
    return get_machine(machine)


def machine_from_headers(headers: Mapping[str, str]) -> MachineSpec:
    """The machine a knitout program was written for, from its ``;;`` headers.

    The preset whose ``;;Machine`` name and bed width match is taken as it is; otherwise the
    first preset of that name (else the default machine) with the program's ``;;Width`` and
    ``;;Gauge``. The preset's carriers, racking and float limits apply: headers do not carry them,
    and a program whose ``;;Machine`` or ``;;Carriers`` differ from the preset's is what the
    checker's header rules report. Malformed values are left to those rules too.

    Examples
    --------
    >>> machine_from_headers({"Machine": "SWG091N2", "Width": "252"}) is MACHINES["swg091n2"]
    True
    """
    model = headers.get("Machine", "").strip().lower()
    width = _int_or_none(headers.get("Width"))
    gauge = _float_or_none(headers.get("Gauge"))
    same_model = [m for m in MACHINES.values() if model and m.name.lower() == model]
    base = same_model[0] if same_model else DEFAULT_MACHINE
    base = next((m for m in same_model if m.needles == width), base)
    changes: dict[str, float] = {}
    # a value out of range is left to the checker's machine-value rule, not taken as the bed
    ranges = ranges_for(base.runs_on())
    if width is not None and width != base.needles and ranges["needles"].contains(width):
        changes["needles"] = width
    if gauge is not None and gauge != base.gauge and ranges["gauge"].contains(gauge):
        changes["gauge"] = gauge
    if not changes:
        return base
    return replace(base, description="from the program's headers", **changes)  # type: ignore[arg-type]


def _int_or_none(value: str | None) -> int | None:
    v = (value or "").strip()
    return int(v) if v.isdigit() and int(v) > 0 else None


def _float_or_none(value: str | None) -> float | None:
    try:
        v = float((value or "").strip())
    except ValueError:
        return None
    return v if v > 0 else None
