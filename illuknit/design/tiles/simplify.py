"""Suggested edits to a double-view design's pictures (the paper's designer loop, Fig. 11-12).

When two pictures are over-constrained, a designer edits them -- erases a detail, smooths an
outline, uses fewer colours -- until the illusion reads. This module proposes such edits
automatically, on the quantised pictures (colour regions), and measures each one by what it does
to the *original* pictures' readability (an edit is judged by the picture the designer wanted,
never by its own simplified version):

* ``requantise`` -- the source pictures re-read with one colour fewer or one more (never fewer
  than 2, never more than ``max_colors``: the yarn count the designer allows);
* ``merge-small-regions`` -- connected regions smaller than ``min_region`` units take the colour
  that surrounds them most (specks a tile cannot show anyway);
* ``smooth-boundaries`` -- each unit takes the most common colour of its 3 x 3 neighbourhood when
  that colour holds a clear majority (ragged, one-unit steps in an outline become straight);
* ``drop-small-overlaps`` -- an overlap pair (colour of A over colour of B) covering fewer than
  ``min_overlap`` units is removed by repainting those units of B in the colour of B that most
  often lies under that colour of A (a pair that is never seen need not constrain the tiles).

The API a user interface builds on:

* :func:`suggest_edits` -- the :class:`Suggestion` objects for a pair of pictures. Each carries
  its ``kind``, a unique ``name``, a one-line ``description``, the pictures ``before`` and
  ``after`` (:class:`~illuknit.design.tiles.assignment.Regions`: index map and colours; as RGB arrays via
  :meth:`Suggestion.pictures`) and the units it changes. *Applying* a suggestion is designing
  with ``suggestion.after``: ``assign_tiles(*suggestion.after, bank=...)``.
* :func:`review_edits` -- the one path the CLI, the app and the benchmark share: builds the
  suggestions, designs each (best of ``candidates`` tile designs, ranked by perception), and
  returns an :class:`EditReview` whose ``results`` are :class:`EditResult` objects (suggestion,
  ``before`` / ``after`` measures: worse-view readability and worst ghosting, ``accepted``).
  With ``apply=True`` it keeps, one kind after the other, the edits that raise the worse view's
  readability (``--simplify``); with ``apply=False`` each suggestion is measured on its own
  against the unedited pictures and none is kept (``--suggest``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.arguments import check_int, got, with_knobs
from illuknit.core.errors import ImageInputError, OptionError
from illuknit.design.tiles.assignment import Regions, regions_of
from illuknit.design.tiles.picture_edits import (
    drop_small_overlaps,
    index_map,
    merge_small_regions,
    requantise_pair,
    smooth_boundaries,
)

__all__ = [
    "EDIT_KINDS",
    "EDIT_NAMES",
    "MIN_GAIN",
    "EditOptions",
    "EditResult",
    "EditReview",
    "Suggestion",
    "apply_edits",
    "best_reading",
    "drop_small_overlaps",
    "measure_edits",
    "merge_small_regions",
    "requantise_pair",
    "review_edits",
    "smooth_boundaries",
    "suggest_edits",
]

#: The kinds of edit, in the order they are tried (a re-quantisation first: the others then
#: clean up the colour regions it leaves).
EDIT_KINDS = ("requantise", "merge-small-regions", "smooth-boundaries", "drop-small-overlaps")
#: Former name of :data:`EDIT_KINDS`.
EDIT_NAMES = EDIT_KINDS

#: An edit is kept when it raises the worse view's readability by more than this: a gain the
#: 4-decimal reports (suggestions.json) can show.
MIN_GAIN = 1e-4

Measure = Callable[[Regions, Regions], tuple[float, float]]


def _as_regions(x: Any, name: str) -> Regions:
    """Regions from anything :func:`regions_of` takes, or from a bare index map (then painted in
    a grey ramp: edits of index maps need no colours)."""
    if isinstance(x, np.ndarray) or (isinstance(x, list) and np.ndim(x) == 2):
        idx = index_map(x, name)
        if idx.min() < 0:
            raise ImageInputError(f"`{name}` indices must be >= 0")
        ramp = np.linspace(0, 255, int(idx.max()) + 1).round().astype(np.uint8)
        return regions_of((idx, np.repeat(ramp[:, None], 3, axis=1)), name=name)
    return regions_of(x, name=name)


def _rgb(r: Regions) -> NDArray[np.uint8]:
    return np.asarray(r.colors)[np.asarray(r.indices)]


@dataclass(frozen=True)
class Suggestion:
    """One edit of the pair of pictures.

    Attributes
    ----------
    kind : str
        One of :data:`EDIT_KINDS`.
    name : str
        Unique among the suggestions of one pair: the kind, or ``requantise-K`` for a
        re-quantisation to K colours.
    description : str
        One line saying what the edit does, for the designer.
    before, after : (Regions, Regions)
        Pictures A and B before and after the edit (index map of shape (N, M) and colours of
        shape (K, 3)). Designing with ``after`` applies the edit.
    changed : (int, int)
        Units whose colour changes in A and in B.
    """

    kind: str
    name: str
    description: str
    before: tuple[Regions, Regions]
    after: tuple[Regions, Regions]
    changed: tuple[int, int]

    @property
    def a(self) -> NDArray[np.int16]:
        """Index map of the edited picture A."""
        return self.after[0].indices

    @property
    def b(self) -> NDArray[np.int16]:
        """Index map of the edited picture B."""
        return self.after[1].indices

    def pictures(self, *, edited: bool = True) -> tuple[NDArray[np.uint8], NDArray[np.uint8]]:
        """Pictures A and B as (N, M, 3) uint8 RGB, after the edit (or before it)."""
        pair = self.after if edited else self.before
        return _rgb(pair[0]), _rgb(pair[1])

    def to_json(self) -> dict[str, Any]:
        return {
            "kind": self.kind,
            "edit": self.name,
            "description": self.description,
            "units_changed": {"A": self.changed[0], "B": self.changed[1]},
            "colors_before": [len(r.colors) for r in self.before],
            "colors_after": [len(r.colors) for r in self.after],
        }


def _suggestion(
    kind: str, name: str, text: str, before: tuple[Regions, Regions], after: tuple[Regions, Regions]
) -> Suggestion | None:
    changed = tuple(
        int((_rgb(b0) != _rgb(b1)).any(axis=-1).sum()) for b0, b1 in zip(before, after, strict=True)
    )
    if changed == (0, 0):
        return None
    return Suggestion(kind, name, text, before, after, (changed[0], changed[1]))


def _requantise_suggestions(
    pair: tuple[Regions, Regions],
    sources: Sequence[ArrayLike],
    max_colors: int | None,
    yarns: Sequence[Any] | None,
) -> list[Suggestion | None]:
    if len(sources) != 2:
        raise OptionError(f"`sources` must hold the two pictures, got {len(sources)}")
    for src, r, side in zip(sources, pair, "AB", strict=True):
        if np.shape(src)[:2] != r.indices.shape or np.ndim(src) != 3:
            raise ImageInputError(
                f"source picture {side} must have shape {(*r.indices.shape, 3)}, got {np.shape(src)}"
            )
    n = max(len(r.colors) for r in pair)
    counts = [k for k in (n - 1, n + 1) if k >= 2 and (k < n or (max_colors or 0) >= k)]
    out = []
    for k in counts:
        what = "larger regions, fewer overlaps" if k < n else "finer shading"
        text = f"reduce both pictures to {k} colours instead of {n} ({what})"
        out.append(
            _suggestion(
                "requantise",
                f"requantise-{k}",
                text,
                pair,
                requantise_pair(sources, k, yarns=yarns),
            )
        )
    return out


def suggest_edits(
    a: Any,
    b: Any,
    *,
    sources: Sequence[ArrayLike] | None = None,
    max_colors: int | None = None,
    source_yarns: Sequence[Any] | None = None,
    min_region: int = 4,
    min_overlap: int = 4,
    kinds: Sequence[str] = EDIT_KINDS,
) -> list[Suggestion]:
    """The edits of ``kinds`` that change something, each applied to ``a`` and ``b``.

    Parameters
    ----------
    a, b : Regions, QuantisedImage, (indices, colors) or ndarray of shape (N, M)
        The quantised pictures (a bare index map is painted in a grey ramp).
    sources : pair of ndarray of shape (N, M, 3), optional
        The pictures before quantisation; without them no ``requantise`` edit is suggested.
    max_colors : int, optional
        The most colours a re-quantisation may use (the yarn count the designer allows); without
        it only one colour fewer is suggested.
    source_yarns : sequence of Yarn, optional
        See :func:`requantise_pair`.
    min_region, min_overlap : int
        Sizes, in units, below which a region is merged / an overlap pair removed.
    kinds : sequence of str
        Which of :data:`EDIT_KINDS` to try.
    """
    unknown = [n for n in kinds if n not in EDIT_KINDS]
    if unknown:
        raise OptionError(f"unknown edit {unknown[0]!r}; known: {', '.join(EDIT_KINDS)}")
    ra, rb = _as_regions(a, "a"), _as_regions(b, "b")
    if ra.indices.shape != rb.indices.shape:
        raise ImageInputError(
            f"the pictures differ in size: {ra.indices.shape} and {rb.indices.shape}"
        )
    pair = (ra, rb)
    out: list[Suggestion | None] = []
    for kind in kinds:
        if kind == "requantise":
            if sources is not None:
                out += _requantise_suggestions(pair, sources, max_colors, source_yarns)
        elif kind == "merge-small-regions":
            text = f"merge regions smaller than {min_region} units into their surroundings"
            after = tuple(
                replace(r, indices=merge_small_regions(r.indices, min_region=min_region))
                for r in pair
            )
            out.append(_suggestion(kind, kind, text, pair, (after[0], after[1])))
        elif kind == "smooth-boundaries":
            text = "smooth ragged outlines (a unit takes the colour most of its neighbours have)"
            after = tuple(replace(r, indices=smooth_boundaries(r.indices)) for r in pair)
            out.append(_suggestion(kind, kind, text, pair, (after[0], after[1])))
        else:
            text = (
                f"remove overlaps smaller than {min_overlap} units: where a colour of A lies "
                "over a colour of B that rarely, B takes the colour it mostly has under that "
                "colour of A"
            )
            new_b = drop_small_overlaps(ra.indices, rb.indices, min_overlap=min_overlap)
            out.append(_suggestion(kind, kind, text, pair, (ra, replace(rb, indices=new_b))))
    return [s for s in out if s is not None]


@dataclass(frozen=True)
class EditResult:
    """A suggestion measured: ``before`` and ``after`` are (worse-view readability, worst
    ghosting) of the best design for the pictures without and with the edit, both judged
    against the original pictures; ``accepted`` says whether the edit was kept."""

    suggestion: Suggestion
    before: tuple[float, float]
    after: tuple[float, float]
    accepted: bool

    def to_json(self) -> dict[str, object]:
        return {
            **self.suggestion.to_json(),
            "readability_before": round(self.before[0], 4),
            "readability_after": round(self.after[0], 4),
            "ghosting_before": round(self.before[1], 4),
            "ghosting_after": round(self.after[1], 4),
            "accepted": self.accepted,
        }


def best_reading(
    a: Any,
    b: Any,
    *,
    targets: Sequence[ArrayLike],
    colors: tuple[ArrayLike, ArrayLike] | None = None,
    candidates: int = 5,
    **assign: object,
) -> tuple[float, float]:
    """Worse-view readability and worst ghosting of the best-reading tile design for pictures
    ``a``, ``b`` (:class:`Regions` or anything :func:`regions_of` takes; or index maps whose
    colours are ``colors``), judged against ``targets`` -- the original pictures. A pair with no
    tile design at all scores (-1, 1). ``assign`` goes to
    :func:`~illuknit.design.tiles.assign.assign_tiles` (bank, yarns, solver, brightness, ...)."""
    from illuknit.core.errors import TileAssignmentError
    from illuknit.design.tiles.assign import assign_tiles
    from illuknit.design.tiles.perception import rank_designs

    if colors is not None:
        a, b = (np.asarray(a), np.asarray(colors[0])), (np.asarray(b), np.asarray(colors[1]))
    try:
        found = assign_tiles(a, b, candidates=candidates, explain=False, **assign)  # type: ignore[arg-type]
    except TileAssignmentError:
        return (-1.0, 1.0)
    best = rank_designs(found, targets)[0].measures
    return (best.worse_readability, best.worst_ghosting)


def measure_edits(suggestions: Sequence[Suggestion], measure: Measure) -> list[EditResult]:
    """Each suggestion measured on its own against the unedited pictures (none accepted)."""
    before: dict[tuple[int, int], tuple[float, float]] = {}
    out = []
    for s in suggestions:
        key = (id(s.before[0]), id(s.before[1]))
        if key not in before:
            before[key] = measure(*s.before)
        out.append(EditResult(s, before[key], measure(*s.after), False))
    return out


def apply_edits(
    a: Any,
    b: Any,
    measure: Measure,
    *,
    sources: Sequence[ArrayLike] | None = None,
    max_colors: int | None = None,
    source_yarns: Sequence[Any] | None = None,
    min_region: int = 4,
    min_overlap: int = 4,
) -> tuple[Regions, Regions, list[EditResult]]:
    """Try each kind of edit on the pictures as edited so far; keep those that raise the worse
    view's readability by more than :data:`MIN_GAIN` (of several suggestions of one kind, the
    best-reading one).

    Parameters
    ----------
    a, b
        The quantised pictures (see :func:`suggest_edits`).
    measure : callable
        ``measure(a, b) -> (worse-view readability, worst ghosting)`` of the best design for the
        edited pictures (:class:`Regions`), judged against the ORIGINAL pictures.
    sources, max_colors, source_yarns, min_region, min_overlap
        See :func:`suggest_edits`.

    Returns
    -------
    (a, b, results)
        The edited pictures (the inputs when nothing helped) and every edit tried, in order.
    """
    ra, rb = _as_regions(a, "a"), _as_regions(b, "b")
    current = measure(ra, rb)
    results: list[EditResult] = []
    for kind in EDIT_KINDS:
        found = suggest_edits(
            ra, rb, sources=sources, max_colors=max_colors, source_yarns=source_yarns,
            min_region=min_region, min_overlap=min_overlap, kinds=[kind],
        )  # fmt: skip
        after = [measure(*s.after) for s in found]
        best = max(range(len(found)), key=lambda i: after[i][0], default=None)
        keep = best is not None and after[best][0] > current[0] + MIN_GAIN
        results += [
            EditResult(s, current, m, keep and i == best)
            for i, (s, m) in enumerate(zip(found, after, strict=True))
        ]
        if keep and best is not None:
            (ra, rb), current = found[best].after, after[best]
    return ra, rb, results


@dataclass(frozen=True)
class EditReview:
    """What :func:`review_edits` found: the pictures to design with (edited when edits were
    applied, else the inputs) and every suggestion measured."""

    a: Regions
    b: Regions
    results: tuple[EditResult, ...]

    @property
    def accepted(self) -> tuple[EditResult, ...]:
        return tuple(r for r in self.results if r.accepted)

    def to_json(self) -> list[dict[str, object]]:
        return [r.to_json() for r in self.results]


@dataclass(frozen=True)
class EditOptions:
    """Which edits :func:`review_edits` looks for (see :func:`suggest_edits`).

    Parameters
    ----------
    max_colors : int, optional
        The most colours a re-quantisation may use (the yarn count the designer allows); without
        it only one colour fewer is suggested.
    source_yarns : sequence of Yarn, optional
        See :func:`requantise_pair`.
    min_region, min_overlap : int
        Sizes, in units, below which a region is merged / an overlap pair removed.
    """

    max_colors: int | None = None
    source_yarns: tuple[Any, ...] | None = None
    min_region: int = 4
    min_overlap: int = 4

    def __post_init__(self) -> None:
        if self.max_colors is not None:
            check_int(self.max_colors, "max_colors", min=1, max=MAX_COUNT)
        if self.source_yarns is not None:
            if isinstance(self.source_yarns, str) or not isinstance(self.source_yarns, Sequence):
                raise OptionError(
                    f"`source_yarns` must be a sequence of Yarn, got {got(self.source_yarns)}"
                )
            object.__setattr__(self, "source_yarns", tuple(self.source_yarns))
        check_int(self.min_region, "min_region", min=1, max=MAX_COUNT)
        check_int(self.min_overlap, "min_overlap", min=1, max=MAX_COUNT)

    def as_keywords(self, sources: Sequence[ArrayLike] | None) -> dict[str, Any]:
        """The keywords of :func:`suggest_edits` and :func:`apply_edits` these options set,
        with the pictures' ``sources``."""
        return dict(
            sources=sources, max_colors=self.max_colors, source_yarns=self.source_yarns,
            min_region=self.min_region, min_overlap=self.min_overlap,
        )  # fmt: skip


#: The most colours, or units of a region, an edit option counts: more is a slip.
MAX_COUNT = 10**6


def review_edits(
    a: Any,
    b: Any,
    *,
    apply: bool,
    targets: Sequence[ArrayLike] | None = None,
    sources: Sequence[ArrayLike] | None = None,
    edits: EditOptions | None = None,
    candidates: int = 5,
    progress: Callable[[float, str], None] | None = None,
    **knobs: Any,
) -> EditReview:
    """Suggest edits of a pair of quantised pictures and measure each by its best design.

    Parameters
    ----------
    a, b
        The quantised pictures (see :func:`suggest_edits`).
    apply : bool
        True: keep, kind after kind, the edits that raise the worse view's readability
        (:func:`apply_edits`; ``--simplify``). False: measure each suggestion on its own against
        the unedited pictures and keep none (:func:`measure_edits`; ``--suggest``).
    targets : pair of ndarray of shape (N, M, 3), optional
        What the views should show; default the pictures ``a`` and ``b`` themselves.
    sources : pair of ndarray of shape (N, M, 3), optional
        See :func:`suggest_edits`.
    edits : EditOptions, optional
        Which edits to look for (``max_colors``, ``source_yarns``, ``min_region``,
        ``min_overlap``; defaults: ``EditOptions()``).
    candidates : int
        Tile designs per measurement.
    progress : callable, optional
        ``progress(fraction, message)`` is called before the edits are found and before each
        measurement (one tile search each), with a rising fraction in [0, 1) and what comes
        next. Whatever it raises stops the review and propagates: that is how a caller (the
        app's cancellable job) cancels it. The results do not depend on it.
    **knobs
        Fields of ``edits`` as a shorthand (``max_colors=4`` replaces that field), and the
        options of :func:`~illuknit.design.tiles.assign.assign_tiles` each measurement's tile
        search takes (bank or yarns, solver, brightness, ...).
    """
    from functools import partial

    ra, rb = _as_regions(a, "a"), _as_regions(b, "b")
    goal = list(targets) if targets is not None else [_rgb(ra), _rgb(rb)]
    edit_fields = {f.name for f in fields(EditOptions)}
    shorthand = {k: v for k, v in knobs.items() if k in edit_fields}
    assign = {k: v for k, v in knobs.items() if k not in edit_fields}
    chosen = with_knobs(EditOptions, edits, shorthand, name="edits", what="edit")
    measure: Measure = partial(best_reading, targets=goal, candidates=candidates, **assign)
    options = chosen.as_keywords(sources)
    if progress is not None:
        progress(0.0, "finding edits")
    found = [] if apply else suggest_edits(ra, rb, **options)
    if progress is not None:
        # measurements to come: the pictures as they are, then each suggestion (with apply,
        # at most two re-quantisations and one edit of every other kind, found as it goes)
        total = 1 + (len(found) if not apply else len(EDIT_KINDS) - 1 + 2 * (sources is not None))
        named = {(id(s.after[0]), id(s.after[1])): s.description for s in found}
        done, quiet, report = [0], measure, progress

        def reported(x: Regions, y: Regions) -> tuple[float, float]:
            k = done[0]
            done[0] += 1
            what = named.get((id(x), id(y)), "the pictures as they are" if k == 0 else f"edit {k}")
            report(min(k + 1, total) / (total + 1), f"measuring {what}")
            return quiet(x, y)

        measure = reported

    if apply:
        ea, eb, results = apply_edits(ra, rb, measure, **options)
        return EditReview(ea, eb, tuple(results))
    return EditReview(ra, rb, tuple(measure_edits(found, measure)))
