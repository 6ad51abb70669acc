"""Does each side read? The reader's verdict in the app (issue 38).

The ranking's *readability* is a correlation, not a legibility scale
(:mod:`illuknit.design.legibility`); the app asks the reader as ``illuknit double`` does:

* **On the cards.** When tesseract is installed, the tile search of a double view reads both
  sides of the designs it keeps (:class:`~illuknit.design.options.RankOptions` ``read=True``, at
  the session's measuring viewpoint and machine), and each card carries the verdict, weaker
  side first (:func:`legibility_json`). Without tesseract, or when it fails, the cards say that
  the sides were not read and why: the search itself never fails for want of a reader. When the
  viewpoint changes, the measures job reads the same designs again from there
  (:func:`read_candidates`).
* **How wide must it be** (:func:`legible_widths`, the ``widths`` job): the session's two
  pictures designed at a few widths, narrowest first, by
  :func:`~illuknit.pipeline.legible.smallest_legible_width`, until one design reads on both sides.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from illuknit.core.errors import AppRequestError, BackendUnavailableError

if TYPE_CHECKING:
    from illuknit.app.design_session import UploadedImage
    from illuknit.app.schemas import DesignSettings
    from illuknit.core.pattern import LogicalPattern
    from illuknit.design.legibility import Legibility
    from illuknit.pipeline.legible import LegibleWidths

__all__ = [
    "INSTALL",
    "NOT_INSTALLED",
    "WidthsResult",
    "legibility_json",
    "legible_widths",
    "read_candidates",
    "reader_failed",
    "require_reader",
    "widths_key",
    "widths_to_try",
]

#: Why the sides were not read when the reader is missing (short: every card says it).
NOT_INSTALLED = "tesseract is not installed"
#: How to install the reader.
INSTALL = "apt-get install tesseract-ocr"


def reader_failed(error: BaseException) -> bool:
    """Whether ``error`` is the reader's failure (missing or broken tesseract), raised here or in
    a job's worker process (where it comes back as an :class:`AppRequestError` naming it)."""
    if isinstance(error, BackendUnavailableError):
        return True
    return isinstance(error, AppRequestError) and error.code == BackendUnavailableError.__name__


def legibility_json(legibility: Legibility | None, not_read: str | None) -> dict[str, Any]:
    """A card's verdict: ``read`` True with every side, **weaker side first** (``sides``), the
    viewpoint and whether a side's verdict is an estimate (a picture, judged by its shapes); or
    ``read`` False and why (``why``)."""
    if legibility is None:
        why = not_read or "the reader was not asked"
        return {"read": False, "why": why, "sentence": f"not read: {why}"}
    sides = legibility.weaker_first
    return {
        "read": True,
        "reader": legibility.to_json()["reader"],
        "angle": legibility.angle,
        "distance_m": legibility.distance,
        "all_read": legibility.all_read,
        "estimate": any(s.judge == "shapes" for s in sides),
        "sides": [s.to_json() for s in sides],
        "sentence": legibility.sentence(),
    }


def read_candidates(
    patterns: Sequence[LogicalPattern],
    prepared: Any,
    *,
    machine: str,
    viewpoint: tuple[float, float],
    correlations: Sequence[Sequence[float | None]] | None = None,
) -> list[Legibility]:
    """The reader's verdict on each of a double view's designs, seen from ``viewpoint`` (angle
    in degrees, distance in metres) at ``machine``'s gauge: one run of the reader for all
    (:func:`~illuknit.design.legibility.read_designs`).

    Raises
    ------
    BackendUnavailableError
        The reader is missing or fails.
    """
    from illuknit.core.machine import resolve_machine
    from illuknit.design.legibility import read_designs
    from illuknit.design.tiles.perception import seen_targets

    q = prepared.quantised
    targets = seen_targets(q["a"], q["b"])
    angle, distance = viewpoint
    return read_designs(
        list(patterns), targets, correlations=correlations, angle=angle, distance=distance,
        gauge=resolve_machine(machine).gauge,
    )  # fmt: skip


def require_reader(field: str) -> None:
    """Refuse at once, naming the page control, when the reader is not installed."""
    from illuknit.design.legibility import reader_available

    if not reader_available():
        raise AppRequestError(
            f"finding the smallest width that reads needs the reader: {NOT_INSTALLED} ({INSTALL})",
            field=field,
            code="no_reader",
            status=409,
        )


def widths_to_try(machine: str, asked: Sequence[int] | None = None) -> tuple[int, ...]:
    """The widths the widths job tries: ``asked``, or the library's defaults, those the chosen
    machine's bed holds (a width it cannot knit is not worth reading)."""
    from illuknit.core.machine import get_machine
    from illuknit.pipeline.legible import DEFAULT_WIDTHS

    most = get_machine(machine).max_units
    ws = tuple(sorted({int(w) for w in (asked or DEFAULT_WIDTHS) if w <= most}))
    if not ws:
        raise AppRequestError(
            f"no width to try: the machine's bed holds at most {most} units",
            field="widths",
            code="range",
        )
    return ws


def widths_key(images: dict[str, UploadedImage], settings: DesignSettings) -> str:
    """What a widths answer depends on: both pictures and the settings it was found with
    (colours, stretching, square units, viewpoint, machine, and made for hands, which sizes the
    grid by the hand gauge), never the width itself."""
    h = hashlib.sha256()
    for slot in ("a", "b"):
        im = images.get(slot)
        h.update(slot.encode() + (b"-" if im is None else im.rgb.tobytes()))
    s = settings
    # made for a machine the key is what it was before made_for sized anything, so answers
    # stored then still hold
    hands = ("hands",) if s.made_for == "hands" else ()
    h.update(repr((s.n_colors, s.resize, s.square_units, s.viewpoint, s.machine, *hands)).encode())
    return h.hexdigest()[:24]


@dataclass(frozen=True)
class WidthsResult:
    """The widths job's answer, kept with the session, and the inputs it holds for."""

    key: str
    found: LegibleWidths

    def to_json(self) -> dict[str, Any]:
        return self.found.to_json()


def legible_widths(
    picture_a: Any,
    picture_b: Any,
    settings: DesignSettings,
    widths: Sequence[int],
    progress: Callable[[float, str], None] | None = None,
) -> LegibleWidths:
    """:func:`~illuknit.pipeline.legible.smallest_legible_width` of the session's pictures
    under its settings (colours, stretching, grid proportions, measuring viewpoint, machine),
    as the app designs them; the widths job runs
    this in its worker process, killed by Cancel."""
    from illuknit.app.inputs import sizing_aspect
    from illuknit.pipeline.inputs import PictureOptions
    from illuknit.pipeline.legible import smallest_legible_width

    angle, distance = settings.viewpoint
    # sized as the app sizes its grid (the fabric's proportions, or square units)
    sizing = PictureOptions(
        n_colors=settings.n_colors, stretch=settings.resize, unit_aspect=sizing_aspect(settings)
    )
    return smallest_legible_width(
        picture_a, picture_b, widths=widths, pictures=sizing, angle=angle, distance=distance,
        machine=settings.machine, progress=progress,
    )  # fmt: skip
