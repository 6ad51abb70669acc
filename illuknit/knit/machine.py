"""The knitting machine as data: every machine limit and default lives in :class:`MachineSpec`.

Nothing else in :mod:`illuknit.knit` hard-codes a needle count, a carrier name, a racking limit or
a speed: the lowering, the scheduler, the knitout writer and the time model all read them from the
spec they are given. The default describes the machine the paper knit on, a 7-gauge Shima Seiki
SWG091N2, as the CMU knitout-to-dat converter and the PyPI virtual knitting machine model it
(540 needles per bed, carriers ``"1"`` .. ``"10"``, racking within +/-4).

The physical SWG091N2 has a 91 cm (36 inch) bed, which holds about 252 needles at 7 gauge; both
reference tools still use 540, so illuknit does too and ``--machine-width`` overrides it.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from illuknit.errors import OptionError, SchedulingError, UnknownNameError

__all__ = ["DEFAULT_MACHINE", "KNITERATE", "MACHINES", "MachineSpec", "get_machine"]

_POSITIONS = ("Left", "Right", "Center", "Keep")


@dataclass(frozen=True)
class MachineSpec:
    """A V-bed knitting machine and the settings illuknit knits with.

    Parameters
    ----------
    name : str
        Machine model written to the ``;;Machine:`` header.
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
    seconds_per_needle : float
        Time model: carriage time per needle crossed (about 0.36 m/s at 7 gauge's 3.63 mm pitch).
    seconds_per_turn : float
        Time model: fixed time per carriage pass (turning round and clearing the carriage's own length).
    course_aspect : float
        Course height divided by stitch width, used to estimate the piece's physical height.
    inserting_hook : bool
        Whether yarns can come in on a yarn-inserting hook (``inhook``/``releasehook``/
        ``outhook``). Without one (the Kniterate) every yarn enters with ``in`` from the edge and
        the piece starts on a waste section.
    waste_carrier, draw_carrier : str or None
        Carriers reserved for the waste yarn and the draw thread of the waste section (machines
        without an inserting hook); they are not free for the pattern's colours.
    formats : tuple of str
        Machine files illuknit can write for this machine besides knitout (``"dat"``, ``"kc"``).

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
    seconds_per_needle: float = 0.01
    seconds_per_turn: float = 1.5
    course_aspect: float = 0.7
    inserting_hook: bool = True
    waste_carrier: str | None = None
    draw_carrier: str | None = None
    formats: tuple[str, ...] = ("dat",)

    def __post_init__(self) -> None:
        def positive(name: str, value: float, *, integer: bool = False) -> None:
            if integer and (not isinstance(value, int) or isinstance(value, bool)):
                raise OptionError(f"`{name}` must be an integer, got {value!r}")
            if not value > 0:
                raise OptionError(f"`{name}` must be positive, got {value!r}")

        positive("needles", self.needles, integer=True)
        positive("gauge", self.gauge)
        positive("max_racking", self.max_racking, integer=True)
        positive("float_limit", self.float_limit, integer=True)
        positive("park_distance", self.park_distance, integer=True)
        positive("course_aspect", self.course_aspect)
        if self.seconds_per_needle < 0 or self.seconds_per_turn < 0:
            raise OptionError("time model seconds must be >= 0")
        carriers = tuple(str(c) for c in self.carriers)
        if not carriers or len(set(carriers)) != len(carriers):
            raise OptionError(f"`carriers` must be distinct names, got {self.carriers!r}")
        if any(not c or any(ch.isspace() for ch in c) for c in carriers):
            raise OptionError("carrier names must be non-empty and contain no spaces")
        object.__setattr__(self, "carriers", carriers)
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
            if v is not None and (not isinstance(v, int) or v < 0):
                raise OptionError(f"`{name}` must be a non-negative integer or None")

    # -- derived quantities --------------------------------------------------------------------
    @property
    def needle_pitch_cm(self) -> float:
        """Distance between neighbouring needles, in cm."""
        return 2.54 / self.gauge

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

    def check_width(self, wales: int) -> None:
        """Raise :class:`~illuknit.errors.SchedulingError` unless ``wales`` fit on the bed."""
        if wales > self.max_fabric_width:
            raise SchedulingError(
                f"piece is {wales} stitches wide but the {self.name} bed of {self.needles} "
                f"needles holds at most {self.max_fabric_width} (use a narrower pattern or a "
                "wider --machine-width)"
            )

    def with_width(self, needles: int) -> MachineSpec:
        """A copy with another bed width (the ``--machine-width`` option)."""
        return replace(self, needles=needles)

    def with_gauge(self, gauge: float) -> MachineSpec:
        """A copy with another gauge (the ``--gauge`` option)."""
        return replace(self, gauge=gauge)


#: The paper's machine: a 7-gauge Shima SWG091N2 (540 needles as the reference tools model it).
DEFAULT_MACHINE = MachineSpec()

#: The Kniterate: 252 needles at 7 gauge (the reference backend's bed), six carriers, no
#: inserting hook. Carrier 1 holds the draw thread and 6 the waste yarn, a common convention,
#: leaving 2-5 for the pattern. Its stitch numbers run 0-9/A-Z; 6 is the waste-section default.
KNITERATE = MachineSpec(
    name="Kniterate",
    needles=252,
    gauge=7.0,
    carriers=("1", "2", "3", "4", "5", "6"),
    max_racking=4,
    stitch_number=6,
    inserting_hook=False,
    waste_carrier="6",
    draw_carrier="1",
    formats=("kc",),
)

#: Machines known by name (``--machine``).
MACHINES: dict[str, MachineSpec] = {
    "swg091n2": DEFAULT_MACHINE,
    "generic540": DEFAULT_MACHINE,
    "kniterate": KNITERATE,
}


def get_machine(name: str) -> MachineSpec:
    """The preset called ``name`` (case-insensitive).

    Raises
    ------
    UnknownNameError
        Listing the known machine names.
    """
    try:
        return MACHINES[name.lower()]
    except KeyError:
        raise UnknownNameError("machine", name, sorted(MACHINES)) from None
