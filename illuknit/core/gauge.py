"""Gauge and finished size: how big a pattern comes out, and what shape its units are.

A knitted stitch is not square. The *stitch gauge* (stitches per 10 cm across) and the *row
gauge* (rows per 10 cm up) of the finished fabric fix its size, and one unit of a pattern is
2 stitches x 2 rows (paper 4.1), so its height over its width is
``stitches_per_10cm / rows_per_10cm`` (:attr:`Gauge.unit_aspect`). Stocking stitch has about 5 stitches to 7 rows (the ratio of
knitter's graph paper), so a grid of square units comes out at 0.7 of the picture's height
unless the grid is given more rows; :func:`illuknit.pictures.sizing.size_pair` does that with the
gauge's ``unit_aspect``.

Measure your own gauge on a swatch (``docs/knitting.md``, *Gauge and finished size*) and give it
as ``"22x30/10cm"`` (stitches x rows per 10 cm), ``"20x28/4in"`` or ``"5.5x7.5/in"``
(:func:`parse_gauge`; ``--fabric-gauge`` on the commands).

>>> g = parse_gauge("22x30/10cm")
>>> round(g.unit_aspect, 3)
0.733
>>> finished_size((30, 40), g).describe()
'36.4 x 20.0 cm (14.3 x 7.9 in)'
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from illuknit.core.errors import OptionError

__all__ = [
    "CM_PER_INCH",
    "DEFAULT_HAND_GAUGE",
    "HAND_ILLUSION_ROWS_PER_STITCH",
    "STOCKINETTE_COURSE_ASPECT",
    "SWATCH_MARGIN_CM",
    "SWATCH_MEASURE_CM",
    "FinishedSize",
    "Gauge",
    "drawn_gauge",
    "finished_size",
    "hand_gauge",
    "hand_illusion_gauge",
    "parse_gauge",
    "swatch_size",
]

CM_PER_INCH = 2.54

#: Course height over stitch width of stocking stitch: the 5 : 7 stitch-to-row ratio of
#: knitter's graph paper (and of the Craft Yarn Council's standard gauges, e.g. DK 22 x 30).
#: The default for machine presets, whose row gauge nobody has measured for illusion fabric.
STOCKINETTE_COURSE_ASPECT = 0.7


@dataclass(frozen=True)
class Gauge:
    """Stitch and row gauge of the finished fabric.

    Parameters
    ----------
    stitches_per_10cm, rows_per_10cm : float
        Stitches across and rows (courses) up 10 cm of fabric, both > 0.
    source : str
        Where the numbers come from (a preset, a swatch), printed with the finished size.
    estimate : bool
        True when nobody measured it (a machine's needle pitch, a hand-knitting rule of thumb):
        a hand pattern then says so and asks for a swatch.
    """

    stitches_per_10cm: float
    rows_per_10cm: float
    source: str = ""
    estimate: bool = False

    def __post_init__(self) -> None:
        for name in ("stitches_per_10cm", "rows_per_10cm"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not 0 < v < 1000:
                raise OptionError(f"gauge `{name}` must be a number in (0, 1000), got {v!r}")

    @classmethod
    def per_inch(cls, stitches: float, rows: float, *, source: str = "") -> Gauge:
        """A gauge given in stitches and rows per inch."""
        return cls(stitches * 10 / CM_PER_INCH, rows * 10 / CM_PER_INCH, source)

    @classmethod
    def for_machine(cls, gauge: float, course_aspect: float, *, source: str = "") -> Gauge:
        """A machine's fabric: one stitch per needle pitch, courses ``course_aspect`` as tall."""
        stitches = gauge * 10 / CM_PER_INCH
        return cls(stitches, stitches / course_aspect, source, estimate=True)

    @property
    def stitch_cm(self) -> float:
        """Width of one stitch in cm."""
        return 10.0 / self.stitches_per_10cm

    @property
    def row_cm(self) -> float:
        """Height of one row (course) in cm."""
        return 10.0 / self.rows_per_10cm

    @property
    def unit_aspect(self) -> float:
        """Height over width of one unit (2 stitches x 2 rows): ``stitches / rows``."""
        return self.stitches_per_10cm / self.rows_per_10cm

    def describe(self) -> str:
        """``"22 sts x 30 rows per 10 cm (5.6 x 7.6 per inch)"``."""
        s, r = self.stitches_per_10cm, self.rows_per_10cm
        return (
            f"{s:.3g} sts x {r:.3g} rows per 10 cm "
            f"({s * CM_PER_INCH / 10:.2g} x {r * CM_PER_INCH / 10:.2g} per inch)"
        )


#: A common hand-knitting gauge: DK yarn on 4 mm needles, 22 sts per 10 cm (Craft Yarn Council,
#: Standard Yarn Weight System, weight 3: 21-24 sts per 4 in on 3.75-4.5 mm), rows at 5 : 7.
DEFAULT_HAND_GAUGE = Gauge(
    22.0, 30.0, "DK yarn on 4 mm needles (Craft Yarn Council weight 3; rows at the 5:7 ratio)"
)


#: Rows per stitch of hand-knitted illusion fabric (2 rows stocking stitch, 2 rows with garter
#: ridges), an estimate from published illusion patterns: 4 sts x 7 rows per inch (1.75; Knit-O-Rama
#: Designs, "Year of Illusion", swatch of 2 rows stocking and 2 rows garter) and 24 sts x 46 rows
#: per 10 cm (1.92; Vivian Hoxbro's shadow-knitting jacket on 3 mm needles). The garter rows pull
#: up, so there are more rows per stitch than stocking stitch's 1.4 (5:7). Until a swatch says
#: otherwise.
HAND_ILLUSION_ROWS_PER_STITCH = 1.8
#: A hand swatch is measured over this many cm each way, in its middle ...
SWATCH_MEASURE_CM = 10.0
#: ... with this much fabric around the measured square on every side (garter border included).
SWATCH_MARGIN_CM = 2.5


def hand_illusion_gauge(stitches_per_10cm: float) -> Gauge:
    """The estimated gauge of hand-knitted illusion fabric at a stitch gauge: rows
    :data:`HAND_ILLUSION_ROWS_PER_STITCH` per stitch (an estimate: knit a swatch).

    >>> hand_illusion_gauge(22).rows_per_10cm
    39.6
    """
    return Gauge(
        stitches_per_10cm,
        round(stitches_per_10cm * HAND_ILLUSION_ROWS_PER_STITCH, 1),
        f"estimate for hand-knitted illusion fabric: {HAND_ILLUSION_ROWS_PER_STITCH:g} rows a "
        "stitch (published illusion patterns knit 1.75-1.92)",
        estimate=True,
    )


def hand_gauge(gauge: Gauge) -> Gauge:
    """The gauge a hand knitter is told to expect of a design drawn at ``gauge``: the
    estimate for hand-knitted illusion fabric (:func:`hand_illusion_gauge`) at its stitch gauge
    when ``gauge`` is itself an estimate (a machine's unmeasured row gauge), else ``gauge`` (a
    fabric gauge measured on a swatch, ``--fabric-gauge``).

    >>> hand_gauge(Gauge(27.56, 39.37, estimate=True)).rows_per_10cm
    49.7
    >>> hand_gauge(Gauge(22, 30)) == Gauge(22, 30)
    True
    """
    return hand_illusion_gauge(round(gauge.stitches_per_10cm, 1)) if gauge.estimate else gauge


def drawn_gauge(gauge: Gauge, made_for: str) -> Gauge:
    """The gauge a design made for ``made_for`` (``"machine"`` or ``"hands"``, a
    :class:`~illuknit.design.options.MadeFor`) is sized, drawn and described at, ``gauge``
    being the machine's fabric gauge: ``gauge`` itself, or for hands :func:`hand_gauge`."""
    return hand_gauge(gauge) if made_for == "hands" else gauge


def swatch_size(gauge: Gauge) -> tuple[int, int]:
    """(stitches, rows) of a swatch big enough to measure :data:`SWATCH_MEASURE_CM` both ways in
    its middle, :data:`SWATCH_MARGIN_CM` to spare on every side: stitches even, rows a
    multiple of 4 (2 stocking rows and 2 ridge rows).

    >>> swatch_size(Gauge(22, 39.6))
    (34, 60)
    """
    span = SWATCH_MEASURE_CM + 2 * SWATCH_MARGIN_CM
    stitches = math.ceil(span * gauge.stitches_per_10cm / 10 / 2) * 2
    rows = math.ceil(span * gauge.rows_per_10cm / 10 / 4) * 4
    return stitches, rows


@dataclass(frozen=True)
class FinishedSize:
    """Width and height of the finished body (cast-on and bind-off edges not counted)."""

    width_cm: float
    height_cm: float
    gauge: Gauge

    @property
    def width_in(self) -> float:
        return self.width_cm / CM_PER_INCH

    @property
    def height_in(self) -> float:
        return self.height_cm / CM_PER_INCH

    def describe(self) -> str:
        """``"36.4 x 20.0 cm (14.3 x 7.9 in)"`` (width x height)."""
        return (
            f"{self.width_cm:.1f} x {self.height_cm:.1f} cm "
            f"({self.width_in:.1f} x {self.height_in:.1f} in)"
        )

    def as_dict(self) -> dict[str, object]:
        return {
            "width_cm": round(self.width_cm, 1),
            "height_cm": round(self.height_cm, 1),
            "width_in": round(self.width_in, 1),
            "height_in": round(self.height_in, 1),
            "gauge": self.gauge.describe(),
            "gauge_source": self.gauge.source,
        }


def finished_size(shape: tuple[int, int], gauge: Gauge) -> FinishedSize:
    """Size of a pattern of ``shape`` = (rows, cols) units at ``gauge`` (2 x 2 stitches a unit)."""
    n, m = int(shape[0]), int(shape[1])
    return FinishedSize(2 * m * gauge.stitch_cm, 2 * n * gauge.row_cm, gauge)


_GAUGE_RE = re.compile(
    r"^\s*(?P<s>\d+(?:\.\d+)?)\s*[x×]\s*(?P<r>\d+(?:\.\d+)?)\s*/\s*"
    r"(?P<n>\d+(?:\.\d+)?)?\s*(?P<u>cm|in|inch|inches|\")\s*$",
    re.IGNORECASE,
)


def parse_gauge(text: str, *, source: str = "given") -> Gauge:
    """Read ``"22x30/10cm"``, ``"20x28/4in"`` or ``"5.5x7.5/in"`` (stitches x rows per length).

    Raises
    ------
    OptionError
        For anything else, with an example of the expected form.
    """
    m = _GAUGE_RE.match(str(text))
    if m is None:
        raise OptionError(
            f"gauge must look like 22x30/10cm or 5.5x7.5/in (stitches x rows per length), "
            f"got {text!r}"
        )
    length = float(m["n"]) if m["n"] else 1.0
    if length <= 0:
        raise OptionError(f"gauge length must be positive, got {text!r}")
    cm = length * (1.0 if m["u"].lower() == "cm" else CM_PER_INCH)
    return Gauge(float(m["s"]) * 10 / cm, float(m["r"]) * 10 / cm, f"{source}: {text.strip()}")
