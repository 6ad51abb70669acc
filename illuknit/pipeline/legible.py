"""How large must a double view be for both sides to read? A search over widths, cheapest first.

:func:`smallest_legible_width` designs a pair of pictures at each width of a list, narrowest
first (a narrow design is the cheapest to search and to read), ranked by the reader's verdict
(:data:`~illuknit.design.options.RankBy.LEGIBILITY`, :mod:`illuknit.design.legibility`), and
notes, per width, whether side A, side B and both sides of one design read. It stops at the
first width where one design reads on both sides: the smallest piece worth knitting. The answer
names the machine's gauge and the finished width, since a width in units means nothing on a
wall; ``illuknit legible`` prints it before anyone waits for a full design.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

from illuknit.core.errors import OptionError
from illuknit.design.options import RankOptions
from illuknit.pipeline.designs import Picture
from illuknit.pipeline.inputs import PictureOptions, check_type, picture_options

__all__ = ["DEFAULT_WIDTHS", "LegibleWidths", "WidthVerdict", "smallest_legible_width"]

#: The widths (units) tried by default, narrowest first.
DEFAULT_WIDTHS = (40, 50, 60, 70, 80, 100, 120)
#: Tile designs searched per width: fewer than a full design's pool (cheap designs first).
SEARCH_POOL = 8


@dataclass(frozen=True)
class WidthVerdict:
    """What the reader found at one width.

    Attributes
    ----------
    width : int
        Units across (1 unit = 2 stitches).
    a_reads, b_reads : bool
        Some design of this width reads on side A (side B).
    both_read : bool
        One design reads on both sides.
    sentence : str
        The best design's verdict, the weaker side first.
    width_cm : float
        The finished width on the machine's gauge.
    """

    width: int
    a_reads: bool
    b_reads: bool
    both_read: bool
    sentence: str
    width_cm: float

    def to_json(self) -> dict[str, Any]:
        return {
            "width": self.width,
            "a_reads": self.a_reads,
            "b_reads": self.b_reads,
            "both_read": self.both_read,
            "sentence": self.sentence,
            "width_cm": round(self.width_cm, 1),
        }


@dataclass(frozen=True)
class LegibleWidths:
    """The search's answer: the verdict per width tried, and the smallest width for each side.

    ``side_a``, ``side_b`` and ``both`` are None when no width tried reads; ``words`` is what
    each picture says (None: a picture, judged by its correlation).
    """

    tried: tuple[WidthVerdict, ...]
    words: tuple[str | None, str | None]
    angle: float
    distance: float
    gauge: str

    def _first(self, pick: Callable[[WidthVerdict], bool]) -> int | None:
        return next((v.width for v in self.tried if pick(v)), None)

    @property
    def side_a(self) -> int | None:
        return self._first(lambda v: v.a_reads)

    @property
    def side_b(self) -> int | None:
        return self._first(lambda v: v.b_reads)

    @property
    def both(self) -> int | None:
        return self._first(lambda v: v.both_read)

    def sentence(self) -> str:
        """The answer in one line, naming the viewpoint and gauge it holds for."""
        seen = f"from {self.distance:g} m at {self.angle:g} degrees, {self.gauge}"
        if self.both is None:
            widest = max(v.width for v in self.tried)
            return f"no width up to {widest} units reads on both sides {seen}"
        v = next(v for v in self.tried if v.width == self.both)
        return (
            f"both sides read from {self.both} units wide ({v.width_cm:.1f} cm) {seen}; "
            f"side A alone from {self.side_a}, side B alone from {self.side_b}"
        )

    def to_json(self) -> dict[str, Any]:
        return {
            "words": list(self.words),
            "angle": self.angle,
            "distance_m": self.distance,
            "gauge": self.gauge,
            "side_a": self.side_a,
            "side_b": self.side_b,
            "both": self.both,
            "tried": [v.to_json() for v in self.tried],
            "sentence": self.sentence(),
        }


def smallest_legible_width(
    picture_a: Picture,
    picture_b: Picture,
    *,
    widths: Sequence[int] = DEFAULT_WIDTHS,
    pictures: PictureOptions | None = None,
    viewpoint: RankOptions | None = None,
    keep_going: bool = False,
    progress: Callable[[float, str], None] | None = None,
    **knobs: Any,
) -> LegibleWidths:
    """The smallest width at which each side of a double view reads, by the reader.

    Parameters
    ----------
    picture_a, picture_b
        The two pictures (file paths or sRGB arrays), as :func:`~illuknit.pipeline.tiles.design_double`.
    widths : sequence of int
        Widths in units to try; they are tried narrowest first.
    pictures : PictureOptions, optional
        ``n_colors``, ``stretch`` and ``unit_aspect`` (the grid's proportions: a design app
        sizes by its machine's fabric gauge), as :func:`~illuknit.pipeline.tiles.design_double`'s.
    viewpoint : RankOptions, optional
        ``angle`` and ``distance``, the viewpoint the sides are read from (degrees of elevation,
        metres; default 30 and 3), and ``machine``, whose gauge sets the finished size and the
        eye's blur (default machine when None); the designs are ranked by legibility.
    keep_going : bool
        Try every width, not only up to the first where both sides read.
    progress : callable, optional
        ``progress(fraction, message)`` before each width.
    **knobs
        Shorthand for the fields above: ``n_colors``, ``stretch`` and ``unit_aspect`` of
        ``pictures``,
        ``angle``, ``distance`` and ``machine`` of ``viewpoint``.

    Raises
    ------
    BackendUnavailableError
        The reader (the ``tesseract`` program) is not installed.
    OptionError
        ``widths`` is empty or holds a width that is not a whole number of at least 4 units.
    """
    from illuknit.core.gauge import finished_size
    from illuknit.core.machine import resolve_machine
    from illuknit.design.legibility import reader_available
    from illuknit.design.options import RankBy, SearchOptions
    from illuknit.pipeline.tiles import design_double

    view = viewpoint if viewpoint is not None else RankOptions()
    check_type("viewpoint", view, RankOptions)
    seen = {k: knobs.pop(k) for k in ("angle", "distance", "machine") if k in knobs}
    view = replace(view, **seen) if seen else view
    opts = picture_options(pictures, knobs, takes=("n_colors", "stretch", "unit_aspect"))
    ws = sorted(set(_check_widths(widths)))
    if not reader_available():
        from illuknit.core.errors import BackendUnavailableError

        raise BackendUnavailableError(
            "finding the smallest legible width needs the tesseract OCR program "
            "(apt-get install tesseract-ocr)"
        )
    spec = resolve_machine(view.machine)
    angle, distance = view.angle, view.distance
    ranking = RankOptions(
        rank_by=RankBy.LEGIBILITY, machine=spec, angle=angle, distance=distance, read=True
    )
    search = SearchOptions(candidates=SEARCH_POOL, pool=SEARCH_POOL)
    tried: list[WidthVerdict] = []
    words: tuple[str | None, str | None] = (None, None)
    for k, w in enumerate(ws):
        if progress is not None:
            progress(k / len(ws), f"designing and reading {w} units wide")
        design = design_double(
            picture_a, picture_b, pictures=replace(opts, n_colors=opts.n_colors or 2, width=w),
            search=search, ranking=ranking,
        )  # fmt: skip
        verdicts = [d.legibility for d in design.designs if d.legibility is not None]
        sides = verdicts[0].sides if verdicts else ()
        words = (sides[0].words, sides[1].words) if sides else words
        size = finished_size(design.quantised["A"].shape, spec.fabric_gauge)
        tried.append(
            WidthVerdict(
                width=int(design.quantised["A"].shape[1]),
                a_reads=any(v.sides[0].reads for v in verdicts),
                b_reads=any(v.sides[1].reads for v in verdicts),
                both_read=any(v.all_read for v in verdicts),
                sentence=verdicts[0].sentence() if verdicts else "not read",
                width_cm=float(size.width_cm),
            )
        )
        if tried[-1].both_read and not keep_going:
            break
    name = f"{spec.name} at {spec.fabric_gauge.stitches_per_10cm:.1f} stitches per 10 cm"
    return LegibleWidths(tuple(tried), words, float(angle), float(distance), name)


def _check_widths(widths: Sequence[int]) -> list[int]:
    ws = list(widths)
    if not ws:
        raise OptionError("`widths` must name at least one width in units")
    for w in ws:
        if isinstance(w, bool) or not isinstance(w, int) or w < 4:
            raise OptionError(f"`widths` must be whole numbers of at least 4 units, got {w!r}")
    return ws
