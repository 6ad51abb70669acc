"""The knitting machine as data: every machine limit and default lives in :class:`MachineSpec`.

Nothing in illuknit hard-codes a needle count, a carrier name, a racking limit, a float limit or a
speed: the lowering, the scheduler, the knitout writer, the time model and the checker all read
them from the spec they are given, and one spec travels with a piece from scheduling to checking.

Presets (:data:`MACHINES`, looked up with :func:`get_machine`; ``--machine NAME`` on the CLI):

``generic540`` (the default)
    The paper's machine, a 7-gauge Shima Seiki SWG091N2, as the CMU knitout-to-dat converter and
    the PyPI virtual knitting machine model it: 540 needles per bed, carriers ``"1"`` .. ``"10"``,
    racking within +/-4. The converter assumes 540 needles when a program has no ``;;Width``
    header (``knitout-to-dat.js``), so every program written for it fits this bed.
``swg091n2``
    The same machine with its physical needle count. The SWG091N2 is one of Shima Seiki's compact
    WHOLEGARMENT machines (the SWG-N2 series: SWG041N2, SWG061N2, SWG091N2; e.g. asiantex.net,
    2020, "Shima Seiki releases additional data for knitted masks") with a 36-inch (91 cm)
    needle bed: at 7 needles per inch that is 252 needles per bed. Knitout programs published
    for this machine by the CMU Textiles Lab declare ``;;Width: 250``, consistent with it. Pieces
    wider than 247 stitches (123 units) do not fit this bed.

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

from collections.abc import Mapping
from dataclasses import dataclass, replace

from illuknit.core.errors import OptionError, SchedulingError, UnknownNameError
from illuknit.core.gauge import STOCKINETTE_COURSE_ASPECT, Gauge

__all__ = [
    "BACKENDS",
    "DEFAULT_MACHINE",
    "DEFAULT_MACHINE_NAME",
    "KNITERATE",
    "MACHINES",
    "SWG_CARRIERS",
    "MachineSpec",
    "TransferSettings",
    "get_machine",
    "machine_from_headers",
    "machine_names",
    "resolve_machine",
]

_POSITIONS = ("Left", "Right", "Center", "Keep")

#: The carriers of a Shima machine, the only carrier header the SWG backend accepts.
SWG_CARRIERS = tuple(str(i) for i in range(1, 11))

#: Reference backends a machine's knitout can go through (:attr:`MachineSpec.backend`).
BACKENDS = ("swg", "kniterate")


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
        for name, top in (("stitch_number", 35), ("speed_number", None), ("roller_advance", None)):
            v = getattr(self, name)
            if v is None:
                continue
            if not isinstance(v, int) or isinstance(v, bool) or v < 0:
                raise OptionError(f"transfer `{name}` must be a non-negative integer, got {v!r}")
            if top is not None and v > top:
                raise OptionError(f"transfer `{name}` must be at most {top}, got {v!r}")

    def describe(self) -> dict[str, object]:
        """The settings as JSON-ready values (``None``: the machine's own)."""
        return {
            "stitch_number": self.stitch_number,
            "speed_number": self.speed_number,
            "roller_advance": self.roller_advance or 0,
            "source": self.source,
        }


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
    course_aspect: float = STOCKINETTE_COURSE_ASPECT
    description: str = ""
    inserting_hook: bool = True
    waste_carrier: str | None = None
    draw_carrier: str | None = None
    formats: tuple[str, ...] = ("dat",)
    transfer: TransferSettings = TransferSettings()
    fabric: Gauge | None = None
    backend: str | None = None

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
            if v is not None and (not isinstance(v, int) or v < 0):
                raise OptionError(f"`{name}` must be a non-negative integer or None")
        if "kc" not in self.formats:
            # the SWG backend knows neither x-xfer-stitch-number nor take-down roller extensions
            if self.transfer.stitch_number is not None:
                raise OptionError(
                    f"the {self.name} takes no transfer stitch number (the SWG backend transfers "
                    "at the machine's own transfer stitch); set the transfer speed only"
                )
            if self.transfer.roller_advance:
                raise OptionError(f"the {self.name} has no roller-advance setting")

    # -- derived quantities --------------------------------------------------------------------
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
            source=f"{self.name}: one stitch per needle at gauge {self.gauge:g}, rows at "
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

    def pass_seconds(self, needles_crossed: int) -> float:
        """Time model: seconds for one carriage pass across ``needles_crossed`` needles."""
        return needles_crossed * self.seconds_per_needle + self.seconds_per_turn

    @property
    def max_units(self) -> int:
        """Widest pattern in units (one unit is two wales) that fits on the bed."""
        return self.max_fabric_width // 2

    def check_width(self, wales: int) -> None:
        """Raise :class:`~illuknit.core.errors.SchedulingError` unless ``wales`` fit on the bed."""
        if wales > self.max_fabric_width:
            raise SchedulingError(
                f"piece is {wales} stitches wide but the {self.name} bed of {self.needles} "
                f"needles holds at most {self.max_fabric_width} (use a narrower pattern or a "
                "wider --machine)"
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
                f"pattern is {units} units = {2 * units} stitches wide but the {self.name} bed of "
                f"{self.needles} needles holds at most {self.max_units} units "
                f"({self.max_fabric_width} stitches); {hint}"
            )

    def with_width(self, needles: int) -> MachineSpec:
        """A copy with another bed width (the ``--machine-width`` option)."""
        return replace(self, needles=needles, description=f"{self.name} with {needles} needles")

    def with_gauge(self, gauge: float) -> MachineSpec:
        """A copy with another gauge (the ``--gauge`` option)."""
        return replace(self, gauge=gauge, description=f"{self.name} at gauge {gauge:g}")

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
        description="7-gauge Shima SWG091N2 as the reference knitout tools model it (540 needles)",
    ),
    "swg091n2": MachineSpec(
        needles=252,
        backend="swg",
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
        description="Kniterate, 252 needles, 6 carriers (1 draw thread, 6 waste, 2-5 pattern)",
    ),
}

#: Preset used when no machine is named (the bed the reference tools assume).
DEFAULT_MACHINE_NAME = "generic540"

#: The paper's machine: a 7-gauge Shima SWG091N2 (540 needles as the reference tools model it).
DEFAULT_MACHINE = MACHINES[DEFAULT_MACHINE_NAME]

#: The Kniterate preset.
KNITERATE = MACHINES["kniterate"]


def machine_names() -> list[str]:
    """Names of the presets in :data:`MACHINES`."""
    return list(MACHINES)


def get_machine(name: str | MachineSpec | None = None) -> MachineSpec:
    """The preset called ``name`` (case-insensitive); ``None`` gives the default machine.

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
    if width is not None and width != base.needles:
        changes["needles"] = width
    if gauge is not None and gauge != base.gauge:
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
