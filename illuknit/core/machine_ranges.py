"""The ranges of machine values: one table, per machine backend, each range with its source.

A machine value is a number that reaches the machine: the bed width (``;;Width``,
``--machine-width``), the gauge (``;;Gauge``, ``--gauge``), stitch and speed numbers
(``x-stitch-number``, ``x-speed-number``, ``x-xfer-stitch-number``, ``--xfer-stitch``,
``--xfer-speed``), the Kniterate's roller advance (``x-roller-advance``,
``x-add-roller-advance``, ``--xfer-roller``) and the racking. :data:`MACHINE_RANGES` gives the
range of each per backend (``"swg"``: the Shima SWG backend ``knitout-to-dat.js`` and its
``.dat``; ``"kniterate"``: ``knitout-to-kcode.js`` and its ``.kc``; ``"knitout"``: a machine
illuknit writes knitout only for), each with where the range comes from: what the reference
backend accepts or how it encodes the value, the machine's documentation as our docs cite it, or
our own conservative bound, said as such.

Everything that takes a machine value reads this one table: :class:`~illuknit.core.machine.
MachineSpec` and :class:`~illuknit.core.machine.TransferSettings` (and so every CLI option that
builds one) refuse a value out of range with :class:`~illuknit.core.errors.MachineValueError`
naming the parameter, its range and the source; the ``.dat`` and ``.kc`` writers refuse such a
value in the knitout they convert; ``illuknit check`` reports it as the blocking
``machine-value`` finding.

Examples
--------
>>> check_machine_value("speed_number", 5, backend="swg")
5
>>> check_machine_value("speed_number", 10**30, backend="swg")
Traceback (most recent call last):
...
illuknit.core.errors.MachineValueError: `speed_number` (speed number, x-speed-number) must be a whole number in 0..15 on the Shima SWG backend, got a 31-digit number (knitout-to-dat.js writes speed n as option value n + 10 and documents 'speeds 1-15'; 0 is the machine's own)
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from illuknit.core.errors import MachineValueError

__all__ = [
    "BACKEND_NAMES",
    "MACHINE_RANGES",
    "PARAMETERS",
    "ValueRange",
    "check_machine_value",
    "machine_value_problem",
    "ranges_for",
    "ranges_markdown",
]


@dataclass(frozen=True)
class ValueRange:
    """The values a machine takes for one parameter: ``low`` .. ``high`` (both included), whole
    numbers only when ``integer``, and where the range comes from (``source``)."""

    low: float
    high: float
    source: str
    integer: bool = True

    def text(self) -> str:
        """``0..15``, ``1..20``."""
        return f"{self.low:g}..{self.high:g}"

    def contains(self, value: object) -> bool:
        """Whether ``value`` is a finite number in range (a whole number when ``integer``)."""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            return False
        if isinstance(value, float) and not math.isfinite(value):
            return False
        if self.integer and value != int(value):
            return False
        return self.low <= value <= self.high


#: parameter -> what people meet it as (option, knitout line)
PARAMETERS: dict[str, str] = {
    "needles": "needles per bed, ;;Width, --machine-width, check --bed-width",
    "gauge": "needles per inch, ;;Gauge, --gauge",
    "max_racking": "largest |racking|, rack",
    "stitch_number": "stitch number, x-stitch-number",
    "cast_on_stitch_number": "cast-on stitch number, x-stitch-number",
    "speed_number": "speed number, x-speed-number",
    "transfer_stitch_number": "transfer stitch number, x-xfer-stitch-number, --xfer-stitch",
    "transfer_speed_number": "transfer speed number, x-speed-number, --xfer-speed",
    "roller_advance": "roller advance, x-roller-advance, x-add-roller-advance, --xfer-roller",
}

#: backend -> how messages name it
BACKEND_NAMES: dict[str, str] = {
    "swg": "Shima SWG backend",
    "kniterate": "Kniterate backend",
    "knitout": "knitout-only machine",
}

_OWN = "our own conservative bound"
_BED = (
    f"{_OWN}: the widest flat V-beds are about 100 inches, 1,800 needles at 18 gauge; "
    "8 leaves a 3-needle piece between parked carriers"
)
_GAUGE = f"{_OWN}: flat knitting machines are built from about 1.5 to 18 gauge"
_SWG = "knitout-to-dat.js"
_KC = "knitout-to-kcode.js"
_STITCH_SWG = ValueRange(
    0, 255, f"{_SWG} writes it as option value R6, one byte of the .dat (its table uses 81-100)"
)
_SPEED_SWG = ValueRange(
    0,
    15,
    f"{_SWG} writes speed n as option value n + 10 and documents 'speeds 1-15'; 0 is the "
    "machine's own",
)
_STITCH_KC = ValueRange(0, 35, f"{_KC}: a stitch number is one of 0-9 or A-Z")
_SPEED_KC = ValueRange(
    0,
    600,
    "knit.work 'Knitout extensions' (Kniterate speed numbers 0-600; the backend's default 100)",
    integer=False,
)
_ROLLER_KC = ValueRange(
    0,
    1000,
    f"{_OWN}: {_KC} takes any number; its default is 100 for knitting and 0 for transfers, "
    "its waste section's 400",
    integer=False,
)

#: backend -> parameter -> range (see the module docstring); a parameter a backend has no
#: setting for (the SWG's transfer stitch and roller) is absent from its table.
MACHINE_RANGES: dict[str, dict[str, ValueRange]] = {
    "swg": {
        "needles": ValueRange(8, 2000, _BED + f"; {_SWG} takes any positive ;;Width"),
        "gauge": ValueRange(1, 20, _GAUGE, integer=False),
        "max_racking": ValueRange(1, 8, f"{_SWG} refuses a racking beyond 8"),
        "stitch_number": _STITCH_SWG,
        "cast_on_stitch_number": _STITCH_SWG,
        "speed_number": _SPEED_SWG,
        "transfer_speed_number": _SPEED_SWG,
    },
    "kniterate": {
        "needles": ValueRange(
            8, 252, f"{_KC}: the Kniterate's bed is 252 needles (it ignores ;;Width)"
        ),
        "gauge": ValueRange(1, 20, _GAUGE, integer=False),
        "max_racking": ValueRange(1, 8, f"{_OWN}: the SWG backend's 8 ({_KC} sets none)"),
        "stitch_number": _STITCH_KC,
        "cast_on_stitch_number": _STITCH_KC,
        "speed_number": _SPEED_KC,
        "transfer_stitch_number": _STITCH_KC,
        "transfer_speed_number": _SPEED_KC,
        "roller_advance": _ROLLER_KC,
    },
    "knitout": {
        "needles": ValueRange(8, 2000, _BED),
        "gauge": ValueRange(1, 20, _GAUGE, integer=False),
        "max_racking": ValueRange(1, 8, f"{_OWN}: the SWG backend's 8"),
        "stitch_number": ValueRange(0, 255, f"{_OWN}: the SWG .dat's one byte"),
        "cast_on_stitch_number": ValueRange(0, 255, f"{_OWN}: the SWG .dat's one byte"),
        "speed_number": ValueRange(0, 600, f"{_OWN}: the widest a backend takes (Kniterate)"),
        "transfer_stitch_number": ValueRange(0, 35, f"{_OWN}: the Kniterate's 0-9, A-Z"),
        "transfer_speed_number": ValueRange(
            0, 600, f"{_OWN}: the widest a backend takes (Kniterate)"
        ),
        "roller_advance": ValueRange(0, 1000, f"{_OWN}: the Kniterate's"),
    },
}


def ranges_for(backend: str | None) -> Mapping[str, ValueRange]:
    """The ranges of a backend (``None``: the ``"knitout"`` table)."""
    return MACHINE_RANGES[backend or "knitout"]


def _shown(value: object) -> str:
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10**12:
        return f"a {len(str(value))}-digit number"
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def machine_value_problem(
    name: str, value: object, *, backend: str | None, where: str | None = None
) -> str | None:
    """Why ``value`` is not a ``name`` the backend takes (one line naming the parameter, its
    range and source), or None when it is in range or the backend has no range for it.
    ``where`` names the machine in the message (default: ``the`` and the backend's name)."""
    r = ranges_for(backend).get(name)
    if r is None or r.contains(value):
        return None
    kind = "a whole number" if r.integer else "a number"
    where = where or f"the {BACKEND_NAMES[backend or 'knitout']}"
    return (
        f"`{name}` ({PARAMETERS[name]}) must be {kind} in {r.text()} on {where}, "
        f"got {_shown(value)} ({r.source})"
    )


def check_machine_value(
    name: str, value: object, *, backend: str | None, where: str | None = None
) -> object:
    """Return ``value`` when the backend takes it as ``name``; else raise
    :class:`~illuknit.core.errors.MachineValueError` naming the parameter, range and source
    (``where``: how the message names the machine)."""
    problem = machine_value_problem(name, value, backend=backend, where=where)
    if problem is not None:
        r = ranges_for(backend)[name]
        raise MachineValueError(problem, parameter=name, low=r.low, high=r.high, source=r.source)
    return value


def ranges_markdown() -> str:
    """The table as Markdown (``docs/knitting.md`` shows it; a test keeps the two equal)."""
    lines = ["| backend | parameter | range | source |", "|---|---|---|---|"]
    for backend, table in MACHINE_RANGES.items():
        for name, r in table.items():
            lines.append(f"| `{backend}` | `{name}` | {r.text()} | {r.source} |")
    return "\n".join(lines)
