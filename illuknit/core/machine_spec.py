"""The knitting machine as data: every machine limit and default lives in :class:`MachineSpec`.

Nothing in illuknit hard-codes a needle count, a carrier name, a racking limit, a float limit or a
speed: the lowering, the scheduler, the knitout writer, the time model and the checker all read
them from the spec they are given, and one spec travels with a piece from scheduling to checking.

Presets (:data:`MACHINES`, looked up with :func:`~illuknit.core.machine.get_machine`;
``--machine NAME`` on the CLI):

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

A program's own headers name its machine: :func:`~illuknit.core.machine.machine_from_headers` maps ``;;Machine``,
``;;Width``, ``;;Gauge`` and ``;;Carriers`` back to a spec (the checker's default).

The machine's carriage (transfer settings and time model) is :mod:`illuknit.core.machine_timing`;
finding a machine by name, in a machine file or in a program's headers is
:mod:`illuknit.core.machine`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from illuknit.core.errors import OptionError, SchedulingError
from illuknit.core.gauge import STOCKINETTE_COURSE_ASPECT, Gauge
from illuknit.core.machine_ranges import check_machine_value
from illuknit.core.machine_timing import (
    KNITERATE_TIMING,
    SWG_TIMING,
    CarriageTiming,
    TransferSettings,
)

__all__ = [
    "BACKENDS",
    "DEFAULT_MACHINE",
    "DEFAULT_MACHINE_NAME",
    "KNITERATE",
    "MACHINES",
    "SWG_CARRIERS",
    "BedFitWarning",
    "MachineSpec",
    "machine_names",
]

_POSITIONS = ("Left", "Right", "Center", "Keep")

#: The carriers of a Shima machine, the only carrier header the SWG backend accepts.
SWG_CARRIERS = tuple(str(i) for i in range(1, 11))

#: Reference backends a machine's knitout can go through (:attr:`MachineSpec.backend`).
BACKENDS = ("swg", "kniterate")


class BedFitWarning(UserWarning):
    """A design that fits no bed of the machine it is for, or only a generic bed and not the real
    machine whose rules it has (:meth:`MachineSpec.fit_note`)."""


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
    transfer: TransferSettings = TransferSettings()  # noqa: RUF009 (frozen, so one is shared)
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
