"""The design stages: from pictures to ranked designs, one library call per kind of illusion.

=====================  ========================================================================
stage                  what it returns
=====================  ========================================================================
:func:`design_single`  :class:`SingleDesign`: the single-view pattern for each stripe order
                       (paper section 5), ranked by how well each shows the picture
:func:`design_double`  :class:`TileDesign`: tile designs showing one picture from above and
                       another from below (paper section 6), ranked by how they read
:func:`design_headon`  :class:`TileDesign`: tile designs showing a picture head-on that
                       disappears at an angle (paper Fig. 17)
:func:`design_tiles`   the same from pictures already quantised (what the app calls)
:func:`solve_design`   :class:`SolvedDesign`: the pattern a constraint model and a solver find
                       (paper section 4), with the solver's answer and its report
:func:`measure_design` how one pattern reads (a design edited by hand), as the ranking measures
:func:`retile_design`  a tile design compiled again with per-pair tile overrides
=====================  ========================================================================

Every stage takes frozen option objects (:mod:`illuknit.design.options`), returns a frozen
result whose designs carry their measures and their rank key (why each ranks where it does),
and never changes its inputs. Knitting a design is the next step,
:func:`~illuknit.knitting.pipeline.knit_pattern` (a machine name or spec, and
:class:`~illuknit.knit.options.KnitOptions`). The commands ``illuknit single``, ``double``,
``headon`` and ``solve``, the app and the benchmark call these stages and only write what they
return, so a script calling them reproduces the commands' files (``docs/library.md``).
"""

from __future__ import annotations

import functools
import math
import os
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.errors import ImageInputError, OptionError, YarnSpecError
from illuknit.core.machine import BedFitWarning, MachineSpec, resolve_machine
from illuknit.design.options import (
    ModelKind,
    PictureEdits,
    RankOptions,
    SearchOptions,
    SolveOptions,
)
from illuknit.design.tiles.perception import KnitMeasure

if TYPE_CHECKING:
    from illuknit.core.pattern import LogicalPattern, Yarn
    from illuknit.design.models.illusion_problem import IllusionProblem
    from illuknit.design.tiles.bank import TileBank, ViewPair
    from illuknit.pictures.images import QuantisedImage
    from illuknit.solvers.base import ProgressCallback, Solution
    from illuknit.solvers.model import Model

__all__ = [
    "RankedDesign",
    "SingleDesign",
    "SolvedDesign",
    "TileDesign",
    "design_double",
    "design_headon",
    "design_single",
    "design_tiles",
    "illusion_model",
    "measure_design",
    "quantise_targets",
    "retile_design",
    "solve_design",
]

#: A picture: a file path or an sRGB array of shape (H, W, 3).
Picture = str | os.PathLike[str] | ArrayLike
#: The colour of a single-view pattern's top stripe row.
Stripe = Literal["dark", "light"]
#: ``progress(fraction, message)``; whatever it raises stops the stage (a user's cancel).
Progress = Callable[[float, str], None]


@dataclass(frozen=True, eq=False)
class RankedDesign:
    """One design of a ranking: its pattern, its measures and why it ranks where it does.

    Attributes
    ----------
    rank : int
        1 for the best.
    pattern : LogicalPattern
    measures : Mapping or CandidateMeasures
        How it reads (tile designs: :class:`~illuknit.design.tiles.perception.CandidateMeasures`;
        single view: the mismatch of each view).
    rank_key : tuple of float
        The ascending key the ranking sorted by; ``rank_fields`` names its entries (a name
        starting with ``-`` is a measure where higher is better, negated).
    rank_fields : tuple of str
    assignment : TileAssignment or None
        The tile assignment it compiles (tile designs), its ``rank`` set to ``rank``.
    report : object
        The compiler's report (tile designs: the tiles report).
    score_rank : int or None
        Its place by the assignment's own score (tile designs).
    label : str
        A short description.
    legibility : Legibility or None
        Whether each side reads, by a reader (:mod:`illuknit.design.legibility`); None when
        not read (``RankOptions.read`` off, or not a double view).
    """

    rank: int
    pattern: LogicalPattern
    measures: Any
    rank_key: tuple[float, ...]
    rank_fields: tuple[str, ...]
    assignment: Any = None
    report: Any = None
    score_rank: int | None = None
    label: str = ""
    legibility: Any = None

    def why(self) -> str:
        """The rank and its key, one line: ``"rank 1 by -perceptual score -0.712, ..."``; a
        field not measured (a knitting time when the ranking did not knit) says so."""
        parts = [
            f"{n} {v:.4g}" if math.isfinite(v) else f"{n} not measured"
            for n, v in zip(self.rank_fields, self.rank_key, strict=True)
        ]
        return f"rank {self.rank} by " + ", ".join(parts)


@dataclass(frozen=True, eq=False)
class TileDesign:
    """What :func:`design_double`, :func:`design_headon` and :func:`design_tiles` return.

    Attributes
    ----------
    mode : {"double", "headon"}
    yarns : tuple of Yarn
        The yarns the bank is made of.
    quantised : mapping
        ``{"A": QuantisedImage, "B": QuantisedImage}`` (no ``"B"`` for a head-on design
        without a side picture): the pictures as designed against.
    views : pair of str
        ``("A", "B")`` or ``("headon", "side")``: the views the assignments are made for.
    bank : TileBank
    targets : tuple of ndarray
        What each view should show (:func:`~illuknit.design.tiles.perception.seen_targets`).
    designs : tuple of RankedDesign
        The best ``search.candidates`` of the designs searched, best first.
    searched : int
        How many designs were searched and ranked.
    edits : tuple
        The simplifying edits measured (``search.edits``), as
        :class:`~illuknit.design.tiles.simplify.EditResult`.
    search, ranking
        The options the design was made with.
    pictures : tuple of ndarray
        The sized pictures (sRGB floats), before quantisation.
    seconds : mapping
        Wall time of the stage's steps: ``"search"`` (the edits and the tile assignments) and
        ``"rank"`` (compiling, measuring and ranking them).
    notes : tuple of str
        What the designer should know about the machine: the grid fits no bed of it, or only a
        generic bed (:meth:`~illuknit.core.machine.MachineSpec.fit_note`); also issued as a
        :class:`~illuknit.core.machine.BedFitWarning`.
    """

    mode: Literal["double", "headon"]
    yarns: tuple[Yarn, ...]
    quantised: Mapping[str, QuantisedImage]
    views: tuple[str, str]
    bank: TileBank
    targets: tuple[NDArray[np.uint8], ...]
    designs: tuple[RankedDesign, ...]
    searched: int
    edits: tuple[Any, ...]
    search: SearchOptions
    ranking: RankOptions
    pictures: tuple[NDArray[np.float64], ...] = ()
    seconds: Mapping[str, float] = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    @property
    def best(self) -> RankedDesign:
        """The first-ranked design."""
        return self.designs[0]


@dataclass(frozen=True, eq=False)
class SingleDesign:
    """What :func:`design_single` returns: the picture as quantised and a design per stripe
    order, ranked by the worse view's mismatch (the stripe order asked for first on a tie);
    ``notes`` as :attr:`TileDesign.notes`."""

    quantised: QuantisedImage
    designs: tuple[RankedDesign, ...]
    notes: tuple[str, ...] = ()

    @property
    def best(self) -> RankedDesign:
        """The first-ranked design."""
        return self.designs[0]

    def first(self, stripe: Stripe) -> RankedDesign:
        """The design whose top stripe row is ``stripe``."""
        return next(d for d in self.designs if d.measures["first"] == stripe)


@dataclass(frozen=True, eq=False)
class SolvedDesign:
    """What :func:`solve_design` returns.

    Attributes
    ----------
    pattern : LogicalPattern
    solution : Solution
        The solver's answer (status, objective, bound, gap, who found it).
    problem : IllusionProblem
    report : mapping
        :func:`~illuknit.design.models.illusion_models.report_pattern`, with the sources and the legend.
    quantised : tuple
        The target pictures as quantised (one for the single-view model).
    options : SolveOptions
    notes : tuple of str
        As :attr:`TileDesign.notes`.
    """

    pattern: LogicalPattern
    solution: Solution
    problem: IllusionProblem
    report: Mapping[str, Any]
    quantised: tuple[QuantisedImage, ...]
    options: SolveOptions = field(default_factory=SolveOptions)
    notes: tuple[str, ...] = ()


# -- shared steps ---------------------------------------------------------------------------


def _knit_measure(ranking: RankOptions) -> KnitMeasure | None:
    """What knitting a design costs on ``ranking.machine``, when the ranking needs it (knitting
    time asked for, or the order is by knitting time)."""
    from illuknit.design.options import RankBy
    from illuknit.knitting.stats import knit_stats

    if not (ranking.knit_time or ranking.rank_by is RankBy.KNIT_TIME):
        return None
    return functools.partial(knit_stats, machine=ranking.machine)


def _reader(
    mode: str, targets: Sequence[Any], ranking: RankOptions, gauge: float, params: Any
) -> Any:
    """The reader's verdict on designs of this pair (:func:`~illuknit.design.legibility.read_designs`
    bound to its pictures and viewpoint), when the ranking asks for it; None otherwise."""
    from illuknit.design.legibility import read_designs, reader_available, words_of
    from illuknit.design.options import RankBy

    legible = ranking.rank_by is RankBy.LEGIBILITY
    if mode != "double":
        if legible:
            raise OptionError("ranking by legibility judges double-view designs (two pictures)")
        return None
    if not (ranking.read or legible):
        return None
    if not reader_available():
        from illuknit.core.errors import BackendUnavailableError

        raise BackendUnavailableError(
            "reading the sides needs the tesseract OCR program (apt-get install tesseract-ocr); "
            "rank by perception to design without it"
        )
    words = words_of(targets)

    def read(patterns: Sequence[Any], measures: Sequence[Any]) -> list[Any]:
        return read_designs(
            patterns, targets, correlations=[m.readability for m in measures], words=words,
            angle=ranking.angle, distance=ranking.distance, gauge=gauge, params=params,
        )  # fmt: skip

    return read


def _fit_machine(knit_on: str | MachineSpec | None) -> MachineSpec | None:
    from illuknit.core.arguments import check_instance

    if knit_on is None:
        return None
    what = "a machine name or a MachineSpec"
    return resolve_machine(check_instance(knit_on, (str, MachineSpec), "knit_on", what=what))


def _fit_notes(machine: str | MachineSpec | None, units: int) -> tuple[str, ...]:
    """The design-time note on a grid ``units`` wide for ``machine`` (None: the default), as a
    :class:`~illuknit.core.machine.BedFitWarning` too (the CLI prints it as one line)."""
    note = resolve_machine(machine).fit_note(int(units))
    if note is None:
        return ()
    warnings.warn(note, BedFitWarning, stacklevel=3)
    return (note,)


def _check_fits(machine: MachineSpec | None, units: int | None) -> None:
    """Refuse a pattern ``units`` wide that ``machine``'s bed cannot hold, before design work."""
    if machine is not None and units is not None:
        machine.check_units(units)


def _source_name(p: Any) -> str | None:
    """How a picture is named in reports: its path, or None for an array."""
    if isinstance(p, (str, bytes)) or hasattr(p, "__fspath__"):
        return str(p)
    return None


def _check_picture(value: Any, name: str, *, optional: bool = False) -> None:
    """A picture argument: a file path or an sRGB array (None only when ``optional``)."""
    from illuknit.core.arguments import check_array, check_path, got

    if value is None:
        if optional:
            return
        raise ImageInputError(f"`{name}` must be a picture (a file path or an RGB array), got None")
    if isinstance(value, (str, os.PathLike)):
        check_path(value, name)
    elif not hasattr(value, "indices"):  # a QuantisedImage is checked where it is taken
        try:
            check_array(value, name, ndim=(2, 3))
        except ImageInputError:
            raise ImageInputError(
                f"`{name}` must be a picture (a file path or an RGB array), got {got(value)}"
            ) from None


def _check_sizes(**sizes: Any) -> None:
    """Grid sizes in units (``width``, ``height``: 1-1000) and ``width_cm`` (> 0), or None."""
    from illuknit.core.arguments import check_int, check_number

    for name, value in sizes.items():
        if value is None:
            continue
        if name == "width_cm":
            check_number(value, name, min=0, min_open=True)
        elif name == "gauge":  # stitches per inch: the finest machines knit about 20
            check_number(value, name, min=0, max=100, min_open=True)
        else:
            check_int(value, name, min=1, max=1000)


def _check_yarns(yarns: Any, *, count_ok: bool) -> None:
    """``yarns``: None, a sequence of Yarn, or (``count_ok``) how many to choose (1-8)."""
    from illuknit.core.arguments import check_int, got
    from illuknit.core.pattern import Yarn

    if yarns is None:
        return
    if count_ok and isinstance(yarns, int) and not isinstance(yarns, bool):
        check_int(yarns, "yarns", min=1, max=8, error=YarnSpecError)
        return
    if not isinstance(yarns, (list, tuple)) or not yarns:
        what = "a number of yarns or a sequence of Yarn" if count_ok else "a sequence of Yarn"
        raise YarnSpecError(f"`yarns` must be {what}, got {got(yarns)}")
    if not all(isinstance(y, Yarn) for y in yarns):
        raise YarnSpecError(f"`yarns` must hold Yarn objects, got {got(yarns)}")


def _check_bank(bank: Any) -> None:
    from illuknit.core.arguments import got
    from illuknit.design.tiles.bank import TileBank

    if bank is not None and not isinstance(bank, (TileBank, str, os.PathLike)):
        raise OptionError(f"`bank` must be a TileBank or a bank file, got {got(bank)}")


def _tile_yarns(yarns: Sequence[Yarn] | int | None, n_colors: int, pictures: list[Any]) -> Any:
    """The bank's yarns: given, or ``yarns`` (default ``n_colors``) chosen from the pictures."""
    if yarns is not None and not isinstance(yarns, int):
        from illuknit.core.pattern import Yarn

        ys = tuple(yarns)
        if not ys or not all(isinstance(y, Yarn) for y in ys):
            raise YarnSpecError("`yarns` must be a number of yarns or a sequence of Yarn")
        return ys
    n = n_colors if yarns is None else yarns
    if isinstance(n, bool) or not 1 <= n <= 8:
        raise YarnSpecError(f"`yarns` must be between 1 and 8 yarns, got {n}")
    from illuknit.design.tiles.yarn_choice import choose_yarns

    return choose_yarns(pictures, n)


# -- tile designs (double view, head-on) ----------------------------------------------------


def design_double(
    picture_a: Picture,
    picture_b: Picture,
    *,
    n_colors: int = 2,
    yarns: Sequence[Yarn] | int | None = None,
    width: int | None = None,
    stretch: bool = False,
    unit_aspect: float | None = None,
    bank: TileBank | str | os.PathLike[str] | None = None,
    search: SearchOptions | None = None,
    ranking: RankOptions | None = None,
    knit_on: str | MachineSpec | None = None,
    progress: Progress | None = None,
) -> TileDesign:
    """Ranked double-view tile designs: ``picture_a`` seen from above, ``picture_b`` from below.

    The pictures are sized to one unit grid (:func:`~illuknit.pictures.sizing.size_pair`: ``width``
    units, at most 80 by default; ``stretch`` a B of another shape onto A's), each quantised to
    ``n_colors`` colours; the bank (default: the canonical bank) is made of ``yarns`` (a
    sequence of Yarn, or how many to choose from the pictures; default ``n_colors``). Tile
    assignments are searched (``search``) and ranked (``ranking``). With ``knit_on`` (a machine
    name or spec) a pattern wider than its bed is refused before any design work.

    Raises
    ------
    TileAssignmentError
        No assignment exists (the message says which overlap pairs cannot be realised).
    SchedulingError
        The pattern is wider than ``knit_on``'s bed.
    """
    return _design_pictures(
        "double", picture_a, picture_b, n_colors, yarns, width, stretch, bank, search, ranking,
        knit_on, progress, unit_aspect=unit_aspect,
    )  # fmt: skip


def design_headon(
    front: Picture,
    side: Picture | None = None,
    *,
    n_colors: int = 2,
    yarns: Sequence[Yarn] | int | None = None,
    width: int | None = None,
    stretch: bool = False,
    unit_aspect: float | None = None,
    bank: TileBank | str | os.PathLike[str] | None = None,
    search: SearchOptions | None = None,
    ranking: RankOptions | None = None,
    knit_on: str | MachineSpec | None = None,
    progress: Progress | None = None,
) -> TileDesign:
    """Ranked head-on tile designs: ``front`` seen looking straight at the fabric, ``side`` (or
    a plain field when None) at an angle from either end. Options as :func:`design_double`."""
    return _design_pictures(
        "headon", front, side, n_colors, yarns, width, stretch, bank, search, ranking, knit_on,
        progress, unit_aspect=unit_aspect,
    )  # fmt: skip


def _aspect(unit_aspect: float | None) -> float:
    """``unit_aspect`` for the sizing functions, checked; None is a stocking-stitch unit (the
    finished piece keeps the picture's proportions)."""
    from illuknit.core.arguments import check_unit_aspect
    from illuknit.core.gauge import STOCKINETTE_COURSE_ASPECT

    if unit_aspect is None:
        return STOCKINETTE_COURSE_ASPECT
    return check_unit_aspect(unit_aspect)


def _design_pictures(
    mode: Literal["double", "headon"],
    picture_a: Picture,
    picture_b: Picture | None,
    n_colors: int,
    yarns: Sequence[Yarn] | int | None,
    width: int | None,
    stretch: bool,
    bank: TileBank | str | os.PathLike[str] | None,
    search: SearchOptions | None,
    ranking: RankOptions | None,
    knit_on: str | MachineSpec | None,
    progress: Progress | None,
    *,
    unit_aspect: float | None = None,
) -> TileDesign:
    """Size, quantise and choose the yarns, then :func:`design_tiles`."""
    from illuknit.core.arguments import check_bool, check_callable, check_int
    from illuknit.pictures.images import quantise_image
    from illuknit.pictures.sizing import size_pair

    check_callable(progress, "progress")
    names = ("picture_a", "picture_b") if mode == "double" else ("front", "side")
    _check_picture(picture_a, names[0])
    _check_picture(picture_b, names[1], optional=mode == "headon")
    check_int(n_colors, "n_colors", min=1, max=8)
    _check_yarns(yarns, count_ok=True)
    _check_sizes(width=width)
    check_bool(stretch, "stretch")
    _check_bank(bank)
    machine = _fit_machine(knit_on)
    _check_fits(machine, width)
    pair = size_pair(
        picture_a, picture_b, width=width, stretch=stretch, unit_aspect=_aspect(unit_aspect)
    )
    a, b = pair.a, pair.b
    _check_fits(machine, a.shape[1])
    pictures = [a] if b is None else [a, b]
    ys = _tile_yarns(yarns, n_colors, pictures)
    qa = quantise_image(a, n_colors=n_colors)
    qb = quantise_image(b, n_colors=n_colors) if b is not None else None
    design = design_tiles(
        qa,
        qb,
        mode=mode,
        yarns=ys,
        bank=bank,
        search=search,
        ranking=ranking,
        sources=(a, b) if b is not None else None,
        edit_colors=min(4, max(n_colors, len(ys))),
        progress=progress,
    )
    notes = _fit_notes(knit_on if knit_on is not None else design.ranking.machine, a.shape[1])
    return replace(_with_pictures(design, tuple(pictures)), notes=notes)


def _with_pictures(design: TileDesign, pictures: tuple[Any, ...]) -> TileDesign:
    return replace(design, pictures=pictures)


def design_tiles(
    qa: QuantisedImage,
    qb: QuantisedImage | None = None,
    *,
    mode: Literal["double", "headon"] = "double",
    yarns: Sequence[Yarn] | None = None,
    bank: TileBank | str | os.PathLike[str] | None = None,
    search: SearchOptions | None = None,
    ranking: RankOptions | None = None,
    sources: tuple[ArrayLike, ArrayLike] | None = None,
    edit_colors: int | None = None,
    progress: Progress | None = None,
) -> TileDesign:
    """Ranked tile designs of pictures already quantised (:func:`~illuknit.pictures.images.quantise_image`).

    ``mode="double"``: ``qa`` from above, ``qb`` from below; ``"headon"``: ``qa`` head-on,
    ``qb`` (or a plain field when None) at an angle. ``bank`` is a TileBank, a bank file
    (:func:`~illuknit.design.tiles.bank.load_bank`, read with ``yarns``) or None: the canonical bank of
    ``yarns`` (default: the pictures' yarns) for those views. Simplifying edits
    (``search.edits``) need the unquantised ``sources`` and re-quantise to at most
    ``edit_colors`` colours (default: the number of yarns, at most 4).
    """
    from illuknit.core.arguments import check_callable, check_choice, check_int
    from illuknit.design.tiles.bank import canonical_bank, load_bank
    from illuknit.design.tiles.headon import HEADON_VIEWS
    from illuknit.pictures.images import QuantisedImage

    search = SearchOptions() if search is None else search
    ranking = RankOptions() if ranking is None else ranking
    _check_type("search", search, SearchOptions)
    _check_type("ranking", ranking, RankOptions)
    check_choice(mode, "mode", ("double", "headon"))
    check_callable(progress, "progress")
    for name, q in (("qa", qa), ("qb", qb)):
        if (q is not None or name == "qa") and not isinstance(q, QuantisedImage):
            raise ImageInputError(f"`{name}` must be a QuantisedImage, got {type(q).__name__}")
    _check_yarns(yarns, count_ok=False)
    _check_bank(bank)
    if sources is not None and not (isinstance(sources, (tuple, list)) and len(sources) == 2):
        raise ImageInputError("`sources` must be the two unquantised pictures (A, B)")
    if edit_colors is not None:
        check_int(edit_colors, "edit_colors", min=1, max=8)
    if mode == "double" and qb is None:
        raise ImageInputError("`qb` is needed: a double-view design has two pictures (A and B)")
    say = progress or (lambda _f, _m: None)
    views: Any = ("A", "B") if mode == "double" else HEADON_VIEWS
    ys = tuple(yarns) if yarns is not None else _picture_yarns(qa, qb)
    say(0.05, "building the tile bank")
    if bank is not None and search.split_bumps:
        raise OptionError(
            "split bumps extend the canonical bank; a bank of your own lists its tiles "
            "(write a split bump as 1^0: yarn 1, then yarn 0)"
        )
    if bank is None:
        bank = canonical_bank(
            ys,
            views=views,
            one_sided_stripes=search.one_sided,
            split_bumps=search.split_bumps,
            split_share=search.split_share,
        )
    elif isinstance(bank, (str, os.PathLike)):
        bank = load_bank(bank, yarns=ys)
    t0 = time.perf_counter()
    found, edits = _search(qa, qb, mode, views, bank, search, sources, edit_colors or len(ys), say)
    t1 = time.perf_counter()
    design = _rank(qa, qb, mode, views, ys, bank, found, edits, search, ranking, say)
    seconds = {"search": t1 - t0, "rank": time.perf_counter() - t1}
    return replace(design, seconds=MappingProxyType(seconds))


def _check_type(name: str, value: Any, cls: type) -> None:
    if not isinstance(value, cls):
        raise OptionError(f"`{name}` must be a {cls.__name__}, got {type(value).__name__}")


def _picture_yarns(qa: Any, qb: Any) -> tuple[Yarn, ...]:
    ys = dict.fromkeys((*qa.yarns, *(qb.yarns if qb is not None else ())))
    return tuple(ys)


def _search(
    qa: Any,
    qb: Any,
    mode: str,
    views: ViewPair,
    bank: TileBank,
    search: SearchOptions,
    sources: Any,
    edit_colors: int,
    say: Progress,
) -> tuple[list[Any], list[Any]]:
    """The tile assignments (by score), after the simplifying edits (and those edits)."""
    from illuknit.design.tiles.assign import assign_tiles
    from illuknit.design.tiles.headon import uniform_side
    from illuknit.design.tiles.simplify import review_edits

    kw = {"bank": bank, **search.assign_kwargs()}
    first: Any = qa
    second: Any = qb if qb is not None else uniform_side(qa)
    edits: list[Any] = []
    if search.edits is not PictureEdits.NONE:
        if mode != "double" or sources is None:
            raise OptionError(
                "picture edits work on double-view designs of two pictures (give `sources`)"
            )
        review = review_edits(
            qa,
            qb,
            apply=search.edits is PictureEdits.APPLY,
            targets=[qa.rgb(), qb.rgb()],
            sources=list(sources),
            max_colors=edit_colors,
            **kw,
        )
        first, second, edits = review.a, review.b, list(review.results)
    what = "head-on" if mode == "headon" else f"{len(bank)} tiles in the bank"
    say(0.1, f"finding tile mappings ({what})")
    found = assign_tiles(
        first,
        second,
        bank=bank,
        views=views,
        candidates=search.candidates,
        pool=search.pool,
        pool_seconds=search.pool_seconds,
        solver=search.solver,
        brightness=search.brightness.value,
        time_limit=search.solve_seconds,
    )
    return found, edits


def _rank(
    qa: Any,
    qb: Any,
    mode: Literal["double", "headon"],
    views: tuple[str, str],
    ys: tuple[Yarn, ...],
    bank: TileBank,
    found: list[Any],
    edits: list[Any],
    search: SearchOptions,
    ranking: RankOptions,
    say: Progress,
) -> TileDesign:
    """Compile, measure and rank the assignments into a :class:`TileDesign`."""
    from illuknit.design.tiles.perception import rank_designs, rank_key, seen_blur, seen_targets

    targets = seen_targets(qa, qb)
    gauge = resolve_machine(ranking.machine).gauge
    ranked = rank_designs(
        found,
        targets,
        views=("A", "B") if mode == "double" else ("headon", "side"),
        overrides=ranking.override_map,
        rank_by=ranking.rank_by.value,
        knit_time=_knit_measure(ranking),
        keep=search.candidates,
        progress=lambda f, message: say(0.4 + 0.6 * f, message),
        angle=ranking.angle,
        blur=seen_blur(ranking.distance, gauge=gauge),
        params=_split_params(search),
        read=_reader(mode, targets, ranking, gauge, _split_params(search)),
        made_for=ranking.made_for.value,
    )
    by = ranking.rank_by
    hands = ranking.made_for.value == "hands"
    designs = tuple(
        RankedDesign(
            rank=k + 1,
            pattern=rc.pattern,
            measures=rc.measures,
            rank_key=tuple(
                float(v) for v in rank_key(rc.measures, rc.assignment.score, by.value, hands=hands)
            ),
            rank_fields=ranking.key_fields,
            assignment=rc.assignment,
            report=rc.report,
            score_rank=rc.score_rank,
            label=_assignment_label(rc.assignment),
            legibility=rc.legibility,
        )
        for k, rc in enumerate(ranked)
    )
    quantised = {"A": qa} if qb is None else {"A": qa, "B": qb}
    return TileDesign(
        mode=mode,
        yarns=ys,
        quantised=MappingProxyType(quantised),
        views=views,
        bank=bank,
        targets=tuple(targets),
        designs=designs,
        searched=len(found),
        edits=tuple(edits),
        search=search,
        ranking=ranking,
    )


def _split_params(search: SearchOptions) -> Any:
    """The renderer's parameters the designs are measured with: the default ones, with the
    search's split share when split bumps are on (None: the defaults)."""
    if not search.split_bumps:
        return None
    from illuknit.design.render.params import RenderParams

    return RenderParams(split_share=search.split_share)


def _assignment_label(assignment: Any) -> str:
    kinds = [f.kind for f in (*assignment.fills_a, *assignment.fills_b) if f is not None]
    stripes = sum(k != "solid" for k in kinds)
    return (
        "all solid fills" if not stripes else f"{stripes} striped fill{'s' if stripes > 1 else ''}"
    )


def measure_design(
    pattern: LogicalPattern,
    mode: Literal["double", "headon", "single"],
    picture_a: QuantisedImage,
    picture_b: QuantisedImage | None = None,
    *,
    ranking: RankOptions | None = None,
    params: Any = None,
) -> Any:
    """How one pattern reads, measured as the ranking of the tile stages measures its designs.

    The measures (:class:`~illuknit.design.tiles.perception.CandidateMeasures`) are taken at
    ``ranking.angle`` and ``ranking.distance`` against what each view should show: a double
    view side A ``picture_a`` and side B ``picture_b``, ghosting measured; a head-on design the
    front ``picture_a`` head-on and at an angle ``picture_b`` (or the plain field standing for
    it); a single view ``picture_a`` from both sides, nothing to ghost. With
    ``ranking.knit_time`` the machine's knitting time and passes on ``ranking.machine`` too.
    A user interface measuring a design edited by hand (a tile override) calls this.
    ``params`` (:class:`~illuknit.design.render.params.RenderParams`) are the renderer's, as a
    split-bump search measures its designs with its split share (default: the calibrated ones).
    """
    from illuknit.core.pattern import check_pattern
    from illuknit.design.tiles.perception import measure_candidate, seen_blur, seen_targets
    from illuknit.pictures.images import QuantisedImage

    check_pattern(pattern)
    ranking = RankOptions() if ranking is None else ranking
    _check_type("ranking", ranking, RankOptions)
    if not isinstance(mode, str) or mode not in ("double", "headon", "single"):
        raise OptionError(f"`mode` must be double, headon or single, got {mode!r}")
    for name, q in (("picture_a", picture_a), ("picture_b", picture_b)):
        if (q is not None or name == "picture_a") and not isinstance(q, QuantisedImage):
            raise ImageInputError(f"`{name}` must be a QuantisedImage, got {type(q).__name__}")
        if q is not None and q.shape != pattern.shape:
            raise ImageInputError(
                f"`{name}` is {q.shape[0]} x {q.shape[1]} units, the pattern {pattern.shape}"
            )
    if mode == "double" and picture_b is None:
        raise ImageInputError("`picture_b`: a double-view design is measured against two pictures")
    views: tuple[str, ...] = ("A", "B")
    if mode == "double":
        pictures = [picture_a.rgb(), picture_b.rgb()]  # type: ignore[union-attr]
    elif mode == "headon":
        pictures, views = seen_targets(picture_a, picture_b), ("headon", "side")
    else:
        pictures = [picture_a.rgb(), picture_a.rgb()]
    return measure_candidate(
        pattern,
        pictures,
        views=views,
        ghost=mode != "single",
        knit_time=_knit_measure(ranking),
        angle=ranking.angle,
        blur=seen_blur(ranking.distance, gauge=resolve_machine(ranking.machine).gauge),
        params=params,
    )


def retile_design(
    assignment: Any, overrides: Mapping[tuple[int, int], Any]
) -> tuple[LogicalPattern, Any]:
    """A tile design compiled again with per-pair tile overrides: ``{(colour of A, colour of B):
    tile}``, a tile being a :class:`~illuknit.design.tiles.tile.Tile` or its rows (``"0/1/0^"``).

    Returns the pattern and the compiler's report (which says whether each override keeps the
    fills assigned to its pair).

    Raises
    ------
    UnknownNameError
        An override names a pair that never occurs in the pictures.
    TileBankError
        An override's rows are not a tile.
    """
    from illuknit.core.arguments import check_mapping
    from illuknit.design.tiles.assignment import TileAssignment
    from illuknit.design.tiles.compile import compile_tiles
    from illuknit.design.tiles.tile import Tile

    _check_type("assignment", assignment, TileAssignment)
    chosen = {}
    for pair, tile in check_mapping(overrides, "overrides").items():
        if not (
            isinstance(pair, tuple)
            and len(pair) == 2
            and all(isinstance(v, int) and not isinstance(v, bool) for v in pair)
        ):
            raise OptionError(f"`overrides` keys are (colour of A, colour of B), got {pair!r}")
        if not isinstance(tile, Tile | str):
            raise OptionError(f"`overrides` tiles are Tiles or rows like '0/1^', got {tile!r}")
        if pair not in assignment.tiles:
            from illuknit.core.errors import UnknownNameError

            raise UnknownNameError(
                "overlap pair (colour of A / colour of B) in these pictures",
                f"{pair[0]}/{pair[1]}",
                [f"{a}/{b}" for a, b in assignment.pairs],
            )
        chosen[pair] = tile if isinstance(tile, Tile) else Tile.from_rows(tile.split("/"))
    return compile_tiles(assignment, overrides=chosen)


# -- single view ----------------------------------------------------------------------------


def design_single(
    picture: Picture | QuantisedImage,
    *,
    width: int | None = None,
    height: int | None = None,
    width_cm: float | None = None,
    gauge: float | None = None,
    unit_aspect: float | None = None,
    yarns: Sequence[Yarn] | None = None,
    n_colors: int | None = None,
    quantise: bool = True,
    first: Stripe = "dark",
    knit_on: str | MachineSpec | None = None,
    machine: str | MachineSpec | None = None,
) -> SingleDesign:
    """The single-view pattern of a 2- or 3-colour picture for each stripe order, ranked.

    ``picture`` is a file, an sRGB array (sized by ``width``/``height``/``width_cm`` at
    ``gauge``, default the machine's, and quantised to ``n_colors`` or onto ``yarns``) or a
    :class:`~illuknit.pictures.images.QuantisedImage` used as it is. The designs are ranked by the worse
    view's mismatch (:func:`~illuknit.design.single_view.single_view_errors`), the stripe order
    ``first`` first on a tie. With ``knit_on`` a picture wider than its bed is refused first.
    ``notes`` say when the grid fits no bed of ``machine`` (default ``knit_on``, else the
    default machine), or only a generic one.
    """
    from illuknit.core.arguments import check_bool, check_choice, check_int
    from illuknit.design.single_view import compile_single_view, prepare_single_view_image
    from illuknit.pictures.images import QuantisedImage

    meant_for = knit_on if machine is None else resolve_machine(machine)  # checked first
    check_choice(first, "first", ("dark", "light"))
    if n_colors is not None:  # the 2 or 3 a single-view illusion shows: prepare_single_view_image
        check_int(n_colors, "n_colors", min=1, max=8)
    _check_picture(picture, "picture")
    _check_sizes(width=width, height=height, width_cm=width_cm, gauge=gauge)
    _check_yarns(yarns, count_ok=False)
    check_bool(quantise, "quantise")
    machine = _fit_machine(knit_on)
    if isinstance(picture, QuantisedImage):
        q = picture
    else:
        q = prepare_single_view_image(
            picture,
            width=width,
            height=height,
            width_cm=width_cm,
            gauge=gauge if gauge is not None else (machine or resolve_machine(None)).gauge,
            n_colors=n_colors,
            yarns=None if yarns is None else tuple(yarns),
            allow_quantise=quantise,
            unit_aspect=_aspect(unit_aspect),
        )
    _check_fits(machine, q.indices.shape[1])
    orders: tuple[Stripe, Stripe] = (first, "light" if first == "dark" else "dark")
    made = [(o, compile_single_view(q, first=o)) for o in orders]
    notes = _fit_notes(meant_for, q.indices.shape[1])
    return SingleDesign(q, _rank_single(q, made), notes)


def _rank_single(q: Any, made: Sequence[tuple[str, Any]]) -> tuple[RankedDesign, ...]:
    from illuknit.design.single_view import single_view_errors

    scored = []
    for k, (order, pattern) in enumerate(made):
        err = single_view_errors(q, pattern)
        key = (max(err), float(k))
        measures = {"first": order, "mismatch_A": err[0], "mismatch_B": err[1]}
        scored.append((key, order, pattern, measures))
    scored.sort(key=lambda s: s[0])
    fields = ("worse view's mismatch", "stripe order (0: the one asked for)")
    return tuple(
        RankedDesign(
            rank=r + 1,
            pattern=pattern,
            measures=MappingProxyType(measures),
            rank_key=key,
            rank_fields=fields,
            label=f"{order} stripe first",
        )
        for r, (key, order, pattern, measures) in enumerate(scored)
    )


# -- constraint models ----------------------------------------------------------------------


def solve_design(
    picture_a: Picture,
    picture_b: Picture | None = None,
    *,
    options: SolveOptions | None = None,
    n_colors: int | None = None,
    yarns: Sequence[Yarn] | None = None,
    width: int | None = None,
    stretch: bool = False,
    unit_aspect: float | None = None,
    quantise: bool = True,
    knit_on: str | MachineSpec | None = None,
    progress: ProgressCallback | None = None,
    machine: str | MachineSpec | None = None,
) -> SolvedDesign:
    """The pattern a constraint model and a solver find for one or two target pictures.

    The pictures are sized to one grid and quantised jointly to ``n_colors`` yarns (or onto
    ``yarns``; :func:`quantise_targets`), so a colour means the same yarn in both; the model
    (``options.model``: two pictures for ``logical`` and ``knit-aware``, one for ``single``) is
    solved by :func:`~illuknit.design.models.illusion_models.solve_illusion`. ``progress`` receives the
    solver's improvements. With ``knit_on`` a pattern wider than its bed is refused first;
    ``notes`` as :func:`design_single`'s, for ``machine``.

    Raises
    ------
    InfeasibleError, SolverError
        As :func:`~illuknit.design.models.illusion_models.solve_illusion`.
    """
    from illuknit.core.arguments import check_callable
    from illuknit.design.models.illusion_models import solve_illusion

    options = SolveOptions() if options is None else options
    _check_type("options", options, SolveOptions)
    check_callable(progress, "progress")
    machine = None if machine is None else resolve_machine(machine)
    qa, qb = _solve_targets(picture_a, picture_b, options, n_colors, yarns, width, stretch,
                            quantise, knit_on, unit_aspect)  # fmt: skip
    result = solve_illusion(
        qa.indices,
        None if qb is None else qb.indices,
        model=options.model.value,
        solver=options.solver,
        warm_start=options.warm_start.value,
        weights=options.weights,
        yarns=qa.yarns,
        n_yarns=len(qa.yarns),
        alternate_rows=options.alternate_rows,
        split_bumps=options.split_bumps,
        time_limit=options.time_limit,
        seed=options.seed,
        progress=progress,
    )
    pattern = result.pattern
    assert pattern is not None  # solve_illusion raises when the solver found none
    sources = [_source_name(picture_a), _source_name(picture_b)]
    pattern = _with_meta(pattern, {"sources": sources})
    report = dict(result.report)
    report["sources"] = {"A": sources[0], "B": sources[1]}
    report["legend"] = qa.legend()
    if result.solution.stats.get("interrupted"):
        report["note"] = "interrupted with Ctrl-C: the best pattern found so far"
    quantised = (qa,) if qb is None else (qa, qb)
    notes = _fit_notes(knit_on if machine is None else machine, pattern.shape[1])  # checked above
    return SolvedDesign(
        pattern,
        result.solution,
        result.problem,
        MappingProxyType(report),
        quantised,
        options,
        notes,
    )


def illusion_model(
    picture_a: Picture,
    picture_b: Picture | None = None,
    *,
    options: SolveOptions | None = None,
    n_colors: int | None = None,
    yarns: Sequence[Yarn] | None = None,
    width: int | None = None,
    stretch: bool = False,
    unit_aspect: float | None = None,
    quantise: bool = True,
    knit_on: str | MachineSpec | None = None,
) -> Model:
    """The constraint model :func:`solve_design` solves for the same arguments, unsolved (to
    export it, ``model.to_wcnf()``, or to hand it to :func:`illuknit.solvers.solve`)."""
    from illuknit.design.models.illusion_models import build_model, make_problem

    options = SolveOptions() if options is None else options
    _check_type("options", options, SolveOptions)
    qa, qb = _solve_targets(picture_a, picture_b, options, n_colors, yarns, width, stretch,
                            quantise, knit_on, unit_aspect)  # fmt: skip
    problem = make_problem(
        qa.indices,
        None if qb is None else qb.indices,
        n_yarns=len(qa.yarns),
        kind=options.model.value,
        weights=options.weights,
        alternate_rows=options.alternate_rows,
        split_bumps=options.split_bumps,
    )
    return build_model(problem)


def _with_meta(pattern: LogicalPattern, meta: Mapping[str, Any]) -> LogicalPattern:
    return replace(pattern, meta={**pattern.meta, **meta})


def _solve_targets(
    picture_a: Picture,
    picture_b: Picture | None,
    options: SolveOptions,
    n_colors: int | None,
    yarns: Sequence[Yarn] | None,
    width: int | None,
    stretch: bool,
    quantise: bool,
    knit_on: str | MachineSpec | None,
    unit_aspect: float | None = None,
) -> tuple[Any, Any]:
    """Check the pictures against the model and the bed, then :func:`quantise_targets`."""
    from illuknit.core.arguments import check_bool, check_int

    single = options.model is ModelKind.SINGLE
    _check_picture(picture_a, "picture_a")
    _check_picture(picture_b, "picture_b", optional=True)
    if n_colors is not None:
        check_int(n_colors, "n_colors", min=1, max=8)
    _check_yarns(yarns, count_ok=False)
    _check_sizes(width=width)
    check_bool(stretch, "stretch")
    check_bool(quantise, "quantise")
    if single and picture_b is not None:
        raise ImageInputError("the single model takes one picture (it is seen from both sides)")
    if not single and picture_b is None:
        raise ImageInputError(
            f"`picture_b` is needed: the {options.model.value} model takes two pictures A and B "
            "(or use the single model)"
        )
    if (yarns is not None and len(yarns) < 2) or n_colors == 1:
        # One yarn knits a plain piece: no picture can appear from any side.
        raise YarnSpecError("an illusion needs at least 2 yarns, got 1")
    machine = _fit_machine(knit_on)
    _check_fits(machine, width)
    qa, qb = quantise_targets(
        picture_a, picture_b, width=width, stretch=stretch, n_colors=n_colors, yarns=yarns,
        quantise=quantise, unit_aspect=unit_aspect,
    )  # fmt: skip
    _check_fits(machine, qa.indices.shape[1])
    return qa, qb


def quantise_targets(
    picture_a: Picture,
    picture_b: Picture | None = None,
    *,
    width: int | None = None,
    stretch: bool = False,
    unit_aspect: float | None = None,
    n_colors: int | None = None,
    yarns: Sequence[Yarn] | None = None,
    quantise: bool = True,
) -> tuple[QuantisedImage, QuantisedImage | None]:
    """Size (:func:`~illuknit.pictures.sizing.size_pair`) and jointly quantise the target picture(s).

    Returns the QuantisedImage of A and of B (or None), sharing one yarn list.

    Raises
    ------
    PictureSizeMismatchError
        The pictures do not cover the same piece (unless ``stretch``).
    """
    from illuknit.core.arguments import check_bool, check_int
    from illuknit.pictures.images import QuantisedImage, quantise_image
    from illuknit.pictures.sizing import size_pair

    _check_picture(picture_a, "picture_a")
    _check_picture(picture_b, "picture_b", optional=True)
    if n_colors is not None:
        check_int(n_colors, "n_colors", min=1, max=8)
    _check_yarns(yarns, count_ok=False)
    _check_sizes(width=width)
    check_bool(stretch, "stretch")
    check_bool(quantise, "quantise")
    pair = size_pair(
        picture_a, picture_b, width=width, stretch=stretch, unit_aspect=_aspect(unit_aspect)
    )
    a, b = pair.a, pair.b
    both = a if b is None else np.concatenate([a, b], axis=0)
    q = quantise_image(both, n_colors=n_colors, yarns=yarns, allow_quantise=quantise)
    n = a.shape[0]
    qa = QuantisedImage(q.indices[:n], q.yarns, q.colors)
    qb = None if b is None else QuantisedImage(q.indices[n:], q.yarns, q.colors)
    return qa, qb
