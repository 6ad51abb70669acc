"""The order a ranking of tile designs used, and why (:class:`RankChoice`): what
:func:`~illuknit.pipeline.tile_search.choose_order` makes of
:attr:`~illuknit.design.options.RankBy.AUTO` (or of an order given), carried by
:attr:`~illuknit.pipeline.designs.TileDesign.order` and said in ``illuknit double``'s summary.

Examples
--------
>>> RankChoice("legibility", "auto", "both pictures are words (MILK, HAZE)").sentence()
'ranked by the reader (legibility): both pictures are words (MILK, HAZE)'
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from illuknit.core.errors import OptionError
from illuknit.design.options import RankBy, enum_option

__all__ = ["RankChoice"]


@dataclass(frozen=True)
class RankChoice:
    """The order a ranking used, and why.

    Attributes
    ----------
    by : RankBy
        The order the designs were ranked in (never ``AUTO``).
    asked : RankBy
        The order asked for (``AUTO``: chosen by the pictures and the reader).
    reason : str
        Why ``by``, in words for a designer: "both pictures are words (WOOL, YARN)", "as
        asked", "the reader (tesseract) is not installed, ...", ...
    words : tuple of (str or None), optional
        What the reader read on each picture (None: a picture, not words), when it was asked.
    """

    by: RankBy
    asked: RankBy
    reason: str
    words: tuple[str | None, ...] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "by", enum_option(RankBy, "by", self.by))
        object.__setattr__(self, "asked", enum_option(RankBy, "asked", self.asked))
        if self.by is RankBy.AUTO:
            raise OptionError("`by` is the order used, not auto")
        if not isinstance(self.reason, str) or not self.reason.strip():
            raise OptionError(f"`reason` must be a sentence, got {self.reason!r}")
        words = self.words
        if words is not None:
            if not isinstance(words, (tuple, list)) or not all(
                w is None or isinstance(w, str) for w in words
            ):
                raise OptionError(f"`words` must be a text or None per picture, got {words!r}")
            object.__setattr__(self, "words", tuple(words))

    def sentence(self) -> str:
        """``"ranked by the reader (legibility): both pictures are words (WOOL, YARN)"``."""
        name = "the reader (legibility)" if self.by is RankBy.LEGIBILITY else self.by.value
        return f"ranked by {name}: {self.reason}"

    def to_json(self) -> dict[str, Any]:
        return {
            "by": self.by.value,
            "asked": self.asked.value,
            "reason": self.reason,
            "sentence": self.sentence(),
            "words": None if self.words is None else list(self.words),
        }
