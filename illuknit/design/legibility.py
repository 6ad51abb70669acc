"""Does each side read? Legibility judged by an independent reader, not by our own correlation.

The ranking's **readability** (:mod:`illuknit.design.tiles.perception`) is a Pearson correlation
of blurred luminance: it says how much of a picture's light/dark pattern is there, not whether
a person can read it. A barely legible pair scores 0.93, and on 60-unit word pairs no candidate
side reads at 0.92-0.95. This module asks a reader instead.

* **What the reader sees** (:func:`seen_far`): the side's angled render (the renderer of
  :mod:`illuknit.design.render`, at the design's viewing angle, side B at the negative
  elevation) through the blur the ranking's measures see it with from the viewing distance,
  :func:`~illuknit.design.tiles.perception.seen_blur` (what a 20/20 eye resolves there, then the
  pooling that makes a fill's stripes read as one region), in linear light, as grey levels
  stretched to full contrast (a reader, like an eye, adapts to a dim fabric).
* **The reader** (:func:`read_image`): the tesseract OCR engine, run as the system program
  ``tesseract`` (Debian: ``apt-get install tesseract-ocr``; nothing to install from PyPI, the
  ``ocr`` extra is empty and names the need). It reads one line of text.
* **What a side should say** (:func:`words_of`): the same reader on the side's own picture, sharp.
  A picture it reads as at least two letters or digits, surely (mean confidence at least
  :data:`TEXT_CONFIDENCE`), is *text*, and the
  side reads when the reader reads the same text on the render (letters and digits compared,
  case and spaces ignored). A picture it does not read surely is a *picture*: the side is judged
  by :func:`shape_agreement` -- the share of the view whose light/dark, split as the reader
  splits it (Otsu's threshold), agrees with the picture's -- against :data:`PICTURE_FLOOR`, a
  floor set where that measure best agrees with the reader on words; the verdict then says it
  is an estimate, not a reader's.

:func:`read_sides` judges every side of a design and returns a :class:`Legibility` whose
sentence names the weaker side first ("side B does not read YARN (the reader saw 'VEEN');
side A reads WOOL"). :func:`illuknit.pipeline.legible.smallest_legible_width` searches widths,
cheapest first, for the smallest at which each side of a pair reads.
"""

from __future__ import annotations

import shutil
import subprocess
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.errors import BackendUnavailableError, OptionError
from illuknit.core.pattern import LogicalPattern

__all__ = [
    "PICTURE_FLOOR",
    "READER",
    "READER_ENV",
    "Legibility",
    "Reading",
    "SideReading",
    "read_designs",
    "read_image",
    "read_images",
    "read_sides",
    "reader_available",
    "reader_path",
    "seen_far",
    "shape_agreement",
    "words_of",
]

#: The system program that reads (tesseract OCR).
READER = "tesseract"
#: Pixels per unit the reader's image is drawn at (a unit is 2 x 2 stitches).
READ_SCALE = 4
#: A picture side is called legible when its :func:`shape_agreement` is at least this. Set where
#: that measure best agrees with the reader's verdict on words (320 sides of word-pair designs 50
#: to 100 units wide, half of them read: 77 % agreement in sample, 80 % on widths held out, where
#: a floor on the correlation agrees 65 %); ``benchmarks/legibility_words.py`` prints it. It is
#: an estimate for pictures, not a reader's verdict.
PICTURE_FLOOR = 0.88
#: A picture is text when the reader reads it with at least this mean confidence (0-100). On the
#: bundled double-view instances the drawn shapes and photos read at 61 at most (the ECG trace as
#: "Lh"), the words at 96-97; word pairs quantised 40 and 60 units wide at 91-97.
TEXT_CONFIDENCE = 80.0
#: Seconds one reading may take before the reader is given up on.
READ_TIMEOUT = 30.0


#: The environment variable that names the reader's program, a path or a command on ``PATH``
#: (default: ``tesseract``): another install of tesseract than the one on ``PATH``.
READER_ENV = "ILLUKNIT_READER"


def reader_path() -> str | None:
    """The reader's program, ``$ILLUKNIT_READER`` or ``tesseract``, found as the shell would;
    None when it is not there to run."""
    import os

    return shutil.which(os.environ.get(READER_ENV, "").strip() or READER)


def reader_available() -> bool:
    """Whether the reader (the ``tesseract`` program, or ``$ILLUKNIT_READER``) can be run."""
    return reader_path() is not None


def _normal(text: str) -> str:
    """Letters and digits only, upper case: what two readings are compared by."""
    return "".join(ch for ch in text.upper() if ch.isalnum())


@dataclass(frozen=True)
class Reading:
    """What the reader read in one image: the text (words joined by spaces) and its confidence,
    the mean of the words' (0-100; 0 when nothing was read)."""

    text: str
    confidence: float


def read_images(images: Sequence[ArrayLike]) -> list[Reading]:
    """What the reader reads in each image, as one line of text, with its confidence.

    All images go to one run of the reader (its start-up is most of its time).

    Parameters
    ----------
    images : sequence of ndarray of shape (H, W) or (H, W, 3), uint8
        Dark text on a light ground or light on dark.

    Raises
    ------
    BackendUnavailableError
        The ``tesseract`` program is not installed, cannot run, or fails (its last line of
        complaint is the message).
    """
    import os
    import tempfile

    from PIL import Image

    exe = reader_path()
    if exe is None:
        raise BackendUnavailableError(
            "reading a side needs the tesseract OCR program (apt-get install tesseract-ocr)"
            + (
                f"; {READER_ENV} names {os.environ[READER_ENV]!r}"
                if READER_ENV in os.environ
                else ""
            )
        )
    arrays = [np.asarray(g) for g in images]
    for a in arrays:
        if a.dtype != np.uint8 or a.ndim not in (2, 3) or a.size == 0:
            raise OptionError(f"`images` must be uint8 images (H, W), got {a.dtype} {a.shape}")
    if not arrays:
        return []
    with tempfile.TemporaryDirectory(prefix="illuknit-read-") as tmp:
        names = []
        for k, a in enumerate(arrays):
            names.append(os.path.join(tmp, f"{k}.png"))
            Image.fromarray(a).save(names[-1])
        listing = os.path.join(tmp, "images.txt")
        with open(listing, "w", encoding="utf-8") as f:
            f.write("\n".join(names) + "\n")
        # --psm 7: each image is one line of text; tsv: words with their confidence, per
        # image (page); one thread: the machine is shared
        try:
            got = subprocess.run(
                [exe, listing, "stdout", "--psm", "7", "tsv"],
                capture_output=True,
                timeout=READ_TIMEOUT + 2.0 * len(arrays),
                check=False,
                env={**os.environ, "OMP_THREAD_LIMIT": "1"},
            )
        except (OSError, subprocess.TimeoutExpired) as e:
            raise BackendUnavailableError(f"the reader ({exe}) could not run: {e}") from None
    # a reader that fails (no language data, a broken install) prints nothing to parse: said,
    # not taken for "the reader saw nothing" on every side
    if got.returncode != 0:
        said = got.stderr.decode("utf-8", "replace").strip().splitlines()
        why = said[-1] if said else f"exit code {got.returncode}"
        raise BackendUnavailableError(f"the reader ({exe}) failed: {why}")
    return _parse_tsv(got.stdout.decode("utf-8", "replace"), len(arrays))


def _parse_tsv(tsv: str, pages: int) -> list[Reading]:
    """tesseract's tsv (level, page_num, ..., conf, text) -> one :class:`Reading` per page."""
    words: list[list[tuple[str, float]]] = [[] for _ in range(pages)]
    for line in tsv.splitlines()[1:]:
        cols = line.split("\t")
        if len(cols) < 12 or cols[0] != "5" or not cols[11].strip():
            continue
        page = int(cols[1]) - 1
        if 0 <= page < pages:
            words[page].append((cols[11].strip(), float(cols[10])))
    return [
        Reading(" ".join(w for w, _ in ws), float(np.mean([c for _, c in ws])) if ws else 0.0)
        for ws in words
    ]


def read_image(grey: ArrayLike) -> Reading:
    """What the reader reads in one image (:func:`read_images`)."""
    return read_images([grey])[0]


def _as_seen(rgb: NDArray[np.uint8], sigma_px: float) -> NDArray[np.uint8]:
    """Blurred in linear light, as luminance stretched to full range (no margin is added: on
    word pairs a margin made the reader read fewer sides, 6 of 30 against 10 of 30)."""
    from illuknit.core.colors import luminance, srgb_from_linear
    from illuknit.design.measures import blur_image

    blurred = blur_image(rgb.astype(np.float64) / 255.0, sigma=sigma_px)
    lum = luminance(blurred * 255.0)
    grey = srgb_from_linear(lum) / 255.0
    lo, hi = np.quantile(grey, 0.01), np.quantile(grey, 0.99)
    if hi - lo < 1e-6:
        out = np.full(grey.shape, 255, dtype=np.uint8)
    else:
        out = (np.clip((grey - lo) / (hi - lo), 0, 1) * 255 + 0.5).astype(np.uint8)
    return out


def _sigma_px(distance: float, gauge: float) -> float:
    from illuknit.design.tiles.perception import seen_blur

    return seen_blur(distance, gauge=gauge) * READ_SCALE


def seen_far(
    pattern: LogicalPattern,
    view: str,
    *,
    angle: float = 30.0,
    distance: float = 3.0,
    gauge: float = 7.0,
    params: Any = None,
) -> NDArray[np.uint8]:
    """One side of a pattern as the reader sees it: (H, W) uint8 grey levels.

    ``view`` is ``"A"`` (seen from ``angle`` degrees above) or ``"B"`` (from below); the render
    is blurred as the ranking's measures see it from ``distance`` metres at ``gauge`` stitches
    per inch (:func:`~illuknit.design.tiles.perception.seen_blur`), drawn at
    :data:`READ_SCALE` pixels per unit, and stretched to full contrast.
    """
    from illuknit.design.render.raycast import render_image

    if view not in ("A", "B"):
        raise OptionError(f"`view` must be 'A' or 'B', got {view!r}")
    elevation = angle if view == "A" else -angle
    near = render_image(pattern, elevation, scale=READ_SCALE, params=params)
    return _as_seen(near, _sigma_px(distance, gauge))


def _ink(grey: NDArray[np.uint8]) -> NDArray[np.bool_]:
    """The darker side of Otsu's threshold (the reader's own binarisation); all False for a
    plain image."""
    from skimage.filters import threshold_otsu

    g = grey.astype(np.float64)
    if float(np.ptp(g)) == 0.0:
        return np.zeros(g.shape, dtype=bool)
    return np.asarray(g < threshold_otsu(g))


def shape_agreement(
    pattern: LogicalPattern,
    picture: ArrayLike,
    view: str,
    *,
    angle: float = 30.0,
    distance: float = 3.0,
    gauge: float = 7.0,
    params: Any = None,
) -> float:
    """The share of a side's view whose light/dark agrees with its picture's, both seen as the
    reader sees them (:func:`seen_far`) and split light from dark as it does (Otsu's threshold):
    the picture measure, in [0, 1]. A side is legible at :data:`PICTURE_FLOOR` or more.

    ``picture`` is the (N, M, 3) uint8 target of side ``view`` (``"A"`` or ``"B"``).
    """
    want = np.asarray(picture)
    if want.ndim != 3 or want.shape[2] != 3 or want.shape[:2] != pattern.shape:
        raise OptionError(f"`picture` must have shape {(*pattern.shape, 3)}, got {want.shape}")
    seen = seen_far(pattern, view, angle=angle, distance=distance, gauge=gauge, params=params)
    big = np.repeat(np.repeat(want.astype(np.uint8), READ_SCALE, 0), READ_SCALE, 1)
    target = _as_seen(big, _sigma_px(distance, gauge))
    return float((_ink(seen) == _ink(target)).mean())


def _sizes(grey: NDArray[np.uint8]) -> list[NDArray[np.uint8]]:
    """The image at the sizes the reader is shown it: as drawn and twice as large (the reader's
    verdict on a blurred line depends on its size in pixels; a person's does not)."""
    from PIL import Image

    im = Image.fromarray(grey)
    twice = im.resize((im.width * 2, im.height * 2), Image.Resampling.BICUBIC)
    return [grey, np.asarray(twice)]


def _best_reading(readings: Sequence[Reading], want: str) -> str:
    """Of the readings of one image at its sizes: one that says ``want``, else the surest."""
    for r in readings:
        if _normal(r.text) == _normal(want):
            return r.text
    return max(readings, key=lambda r: r.confidence).text if readings else ""


def words_of(pictures: Sequence[ArrayLike]) -> list[str | None]:
    """What each picture says, as the reader reads it; None where it reads no text: fewer than
    two letters or digits, or read with a confidence under :data:`TEXT_CONFIDENCE` (a picture,
    not words), or a plain field.

    Each picture, (N, M, 3) sRGB (uint8, or floats in [0, 1]), is read sharp (no distance blur),
    enlarged to at least 120 pixels high, at two sizes; the surer reading counts.
    """
    from PIL import Image

    shown = []
    for p in pictures:
        a = np.asarray(p)
        if a.ndim != 3 or a.shape[2] != 3:
            raise OptionError(f"each picture must have shape (N, M, 3), got {a.shape}")
        if not np.issubdtype(a.dtype, np.integer):
            a = np.clip(a * 255.0 + 0.5, 0, 255)
        im = Image.fromarray(a.astype(np.uint8)).convert("L")
        k = max(1, -(-120 // im.height))
        im = im.resize((im.width * k, im.height * k), Image.Resampling.BICUBIC)
        shown += _sizes(np.asarray(im))
    got = read_images(shown)
    out: list[str | None] = []
    for k, p in enumerate(pictures):
        best = max(got[2 * k : 2 * k + 2], key=lambda r: r.confidence)
        plain = float(np.ptp(np.asarray(p, dtype=np.float64))) == 0.0
        text = len(_normal(best.text)) >= 2 and best.confidence >= TEXT_CONFIDENCE
        out.append(best.text if text and not plain else None)
    return out


@dataclass(frozen=True)
class SideReading:
    """The verdict on one side.

    Attributes
    ----------
    view : str
        ``"A"`` or ``"B"``.
    words : str or None
        What the side's picture says (None: a picture, judged by :func:`shape_agreement`).
    read : str or None
        What the reader read on the side (None for a picture side).
    reads : bool
        The side reads: the reader read its words, or (a picture) its shape agreement reaches
        :data:`PICTURE_FLOOR`.
    correlation : float or None
        The ranking's readability of the side (Pearson correlation, -1 to 1), when given.
    agreement : float or None
        A picture side's :func:`shape_agreement` (None for words).
    """

    view: str
    words: str | None
    read: str | None
    reads: bool
    correlation: float | None = None
    agreement: float | None = None

    @property
    def judge(self) -> str:
        """``"reader"`` (the OCR verdict) or ``"shapes"`` (a picture's estimate)."""
        return "reader" if self.words is not None else "shapes"

    def sentence(self) -> str:
        """``"side A reads KNIT"``, ``"side B does not read FELT (the reader saw 'FEIT')"``."""
        side = f"side {self.view}"
        if self.words is not None:
            if self.reads:
                return f"{side} reads {self.words}"
            saw = f"the reader saw {self.read!r}" if self.read else "the reader saw nothing"
            return f"{side} does not read {self.words} ({saw})"
        a = "unknown" if self.agreement is None else f"{100 * self.agreement:.0f} %"
        verb = "likely reads" if self.reads else "may not read"
        sign = ">=" if self.reads else "<"
        return (
            f"{side} (a picture) {verb}: its light/dark shapes agree with the picture on {a} of "
            f"the view ({sign} {100 * PICTURE_FLOOR:.0f} %), an estimate, not a reader's verdict"
        )

    def to_json(self) -> dict[str, Any]:
        def r(x: float | None) -> float | None:
            return None if x is None or x != x else round(float(x), 4)

        return {
            "view": self.view,
            "words": self.words,
            "read": self.read,
            "reads": self.reads,
            "judge": self.judge,
            "correlation": r(self.correlation),
            "shape_agreement": r(self.agreement),
            "sentence": self.sentence(),
        }


@dataclass(frozen=True)
class Legibility:
    """Every side's verdict, from ``angle`` degrees and ``distance`` metres.

    ``sides`` are in view order (A, B); :attr:`weaker_first` puts a side that does not read (or
    the lower correlation) first, as :meth:`sentence` says them.
    """

    sides: tuple[SideReading, ...]
    angle: float
    distance: float

    @property
    def all_read(self) -> bool:
        return all(s.reads for s in self.sides)

    @property
    def sides_read(self) -> int:
        return sum(s.reads for s in self.sides)

    @property
    def weaker_first(self) -> tuple[SideReading, ...]:
        def key(s: SideReading) -> tuple[bool, float]:
            c = s.correlation
            return (s.reads, 2.0 if c is None or c != c else float(c))

        return tuple(sorted(self.sides, key=key))

    def sentence(self) -> str:
        """Every side's verdict, the weaker side first, joined by ``"; "``."""
        return "; ".join(s.sentence() for s in self.weaker_first)

    def to_json(self) -> dict[str, Any]:
        return {
            "reader": READER,
            "angle": self.angle,
            "distance_m": self.distance,
            "all_read": self.all_read,
            "sides": [s.to_json() for s in self.sides],
            "sentence": self.sentence(),
        }


def read_sides(
    pattern: LogicalPattern,
    pictures: Sequence[ArrayLike],
    *,
    correlations: Sequence[float | None] | None = None,
    words: Sequence[str | None] | None = None,
    angle: float = 30.0,
    distance: float = 3.0,
    gauge: float = 7.0,
    params: Any = None,
) -> Legibility:
    """Judge each side of a double-view pattern: does it read from ``distance`` metres?

    Parameters
    ----------
    pattern : LogicalPattern
    pictures : pair of ndarray of shape (N, M, 3)
        What side A and side B should show (sRGB).
    correlations : pair of float, optional
        The sides' readability (the ranking's correlation): judges a picture side, and is kept.
    words : pair of str or None, optional
        What each picture says, if known (:func:`words_of` the pictures otherwise; pass it to
        judge many designs of one pair without reading the pictures again).
    angle, distance, gauge, params
        As :func:`seen_far`.

    Raises
    ------
    BackendUnavailableError
        The reader is not installed.
    """
    return read_designs(
        [pattern],
        pictures,
        correlations=None if correlations is None else [correlations],
        words=words,
        angle=angle,
        distance=distance,
        gauge=gauge,
        params=params,
    )[0]


def read_designs(
    patterns: Sequence[LogicalPattern],
    pictures: Sequence[ArrayLike],
    *,
    correlations: Sequence[Sequence[float | None]] | None = None,
    words: Sequence[str | None] | None = None,
    angle: float = 30.0,
    distance: float = 3.0,
    gauge: float = 7.0,
    params: Any = None,
) -> list[Legibility]:
    """:func:`read_sides` of many designs of one pair of pictures, in one run of the reader."""
    if len(pictures) != 2:
        raise OptionError(f"`pictures` must be the two sides' pictures, got {len(pictures)}")
    said = list(words) if words is not None else words_of(pictures)
    corr: list[list[float | None]] = (
        [list(c) for c in correlations]
        if correlations is not None
        else [[None, None] for _ in patterns]
    )
    if len(said) != 2 or len(corr) != len(patterns) or any(len(c) != 2 for c in corr):
        raise OptionError("`correlations` and `words` must have one entry per side (A, B)")
    shown: list[NDArray[np.uint8]] = []
    for pattern in patterns:
        for view, want in zip(("A", "B"), said, strict=True):
            if want is not None:
                seen = seen_far(
                    pattern, view, angle=angle, distance=distance, gauge=gauge, params=params
                )
                shown += _sizes(seen)
    texts = iter(read_images(shown))
    out = []
    for pattern, c in zip(patterns, corr, strict=True):
        sides = []
        for view, want, r in zip(("A", "B"), said, c, strict=True):
            if want is None:
                agree = shape_agreement(
                    pattern, pictures[0 if view == "A" else 1], view, angle=angle,
                    distance=distance, gauge=gauge, params=params,
                )  # fmt: skip
                sides.append(SideReading(view, None, None, agree >= PICTURE_FLOOR, r, agree))
                continue
            got = _best_reading([next(texts), next(texts)], want)
            sides.append(SideReading(view, want, got, _normal(got) == _normal(want), r))
        out.append(Legibility(tuple(sides), float(angle), float(distance)))
    return out
