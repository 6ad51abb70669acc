"""What the design stages return: ranked designs, with their measures and why each ranks where it
does (:class:`RankedDesign`), gathered per kind of stage (:class:`TileDesign`,
:class:`SingleDesign`, :class:`SolvedDesign`)."""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Generic, Literal, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.design.options import RankOptions, SearchOptions, SolveOptions
from illuknit.design.rank_choice import RankChoice

if TYPE_CHECKING:
    from illuknit.core.pattern import LogicalPattern, Yarn
    from illuknit.design.legibility import Legibility
    from illuknit.design.models.illusion_problem import IllusionProblem
    from illuknit.design.tiles.assignment import TileAssignment
    from illuknit.design.tiles.bank import TileBank
    from illuknit.design.tiles.compile import TileReport
    from illuknit.design.tiles.perception import CandidateMeasures
    from illuknit.design.tiles.simplify import EditResult
    from illuknit.pictures.images import QuantisedImage
    from illuknit.solvers.base import Solution

__all__ = [
    "Picture",
    "Progress",
    "RankedDesign",
    "SingleDesign",
    "SolvedDesign",
    "Stripe",
    "TileDesign",
]

#: A picture: a file path or an sRGB array of shape (H, W, 3).
Picture = str | os.PathLike[str] | ArrayLike
#: The colour of a single-view pattern's top stripe row.
Stripe = Literal["dark", "light"]
#: ``progress(fraction, message)``; whatever it raises stops the stage (a user's cancel).
Progress = Callable[[float, str], None]


#: What a ranked design's measures are (tile designs: CandidateMeasures; single view: a mapping).
M = TypeVar("M")
#: Its tile assignment (tile designs: TileAssignment; single view: None).
A = TypeVar("A")
#: Its compiler's report (tile designs: TileReport; single view: None).
R = TypeVar("R")


@dataclass(frozen=True, eq=False)
class RankedDesign(Generic[M, A, R]):
    """One design of a ranking: its pattern, its measures and why it ranks where it does.

    Generic in what its measures, its assignment and its report are: a tile design's
    designs are ``RankedDesign[CandidateMeasures, TileAssignment, TileReport]``, a
    single-view design's ``RankedDesign[Mapping[str, Any], None, None]``.

    Attributes
    ----------
    rank : int
        1 for the best.
    pattern : LogicalPattern
    measures : CandidateMeasures or Mapping
        How it reads (tile designs: :class:`~illuknit.design.tiles.perception.CandidateMeasures`;
        single view: the mismatch of each view).
    rank_key : tuple of float
        The ascending key the ranking sorted by; ``rank_fields`` names its entries (a name
        starting with ``-`` is a measure where higher is better, negated).
    rank_fields : tuple of str
    assignment : TileAssignment or None
        The tile assignment it compiles (tile designs), its ``rank`` set to ``rank``.
    report : TileReport or None
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
    measures: M
    rank_key: tuple[float, ...]
    rank_fields: tuple[str, ...]
    assignment: A = None  # type: ignore[assignment]  # None: no assignment (single view)
    report: R = None  # type: ignore[assignment]  # None: no compiler report (single view)
    score_rank: int | None = None
    label: str = ""
    legibility: Legibility | None = None

    def why(self) -> str:
        """The rank and its key, one line: ``"rank 1 by -perceptual score -0.712, ..."``; a
        field not measured (a knitting time when the ranking did not knit) says so."""
        parts = [
            f"{n} {v:.4g}" if math.isfinite(v) else f"{n} not measured"
            for n, v in zip(self.rank_fields, self.rank_key, strict=True)
        ]
        return f"rank {self.rank} by " + ", ".join(parts)


if TYPE_CHECKING:
    TileRanked = RankedDesign[CandidateMeasures, TileAssignment, TileReport]
    SingleRanked = RankedDesign[Mapping[str, Any], None, None]


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
        The options the design was made with (``ranking.rank_by`` the order used: an
        ``AUTO`` asked for is resolved, see ``order``).
    order : RankChoice or None
        The order the designs were ranked in, the order asked for and why (e.g. the reader's
        order: both pictures are words); None only for a TileDesign made by hand.
    pictures : tuple of ndarray
        The sized pictures (sRGB floats), before quantisation.
    seconds : mapping
        Wall time of the stage's steps: ``"search"`` (the edits and the tile assignments) and
        ``"rank"`` (compiling, measuring and ranking them).
    notes : tuple of str
        What the designer should know about the machine: the grid fits no bed of it, or only a
        generic bed (:meth:`~illuknit.core.machine.MachineSpec.fit_note`); also issued as a
        :class:`~illuknit.core.machine.BedFitWarning`.
    machine_first : CandidateMeasures or None
        Made for hands (``ranking.made_for``): the measures of the design the same ranking puts
        first for a machine (by perception when ranked by ``hand-time``), among every design
        searched (what the hand design is compared with); None when made for a machine.
    hand_model : mapping or None
        Made for hands, double view: the constraint model made for hands was solved too
        (:mod:`illuknit.pipeline.hand_model`): its solver's summary (status, objective,
        bound, seconds) and ``rank``, where its design ranked among ``designs`` (None: not
        kept). That design has no tile assignment. None when it was not solved.
    """

    mode: Literal["double", "headon"]
    yarns: tuple[Yarn, ...]
    quantised: Mapping[str, QuantisedImage]
    views: tuple[str, str]
    bank: TileBank
    targets: tuple[NDArray[np.uint8], ...]
    designs: tuple[TileRanked, ...]
    searched: int
    edits: tuple[EditResult, ...]
    search: SearchOptions
    ranking: RankOptions
    order: RankChoice | None = None
    pictures: tuple[NDArray[np.float64], ...] = ()
    seconds: Mapping[str, float] = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    machine_first: CandidateMeasures | None = None
    hand_model: Mapping[str, Any] | None = None

    @property
    def best(self) -> TileRanked:
        """The first-ranked design."""
        return self.designs[0]


@dataclass(frozen=True, eq=False)
class SingleDesign:
    """What :func:`design_single` returns: the picture as quantised and a design per stripe
    order, ranked by the worse view's mismatch (the stripe order asked for first on a tie);
    ``notes`` as :attr:`TileDesign.notes`."""

    quantised: QuantisedImage
    designs: tuple[SingleRanked, ...]
    notes: tuple[str, ...] = ()

    @property
    def best(self) -> SingleRanked:
        """The first-ranked design."""
        return self.designs[0]

    def first(self, stripe: Stripe) -> SingleRanked:
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
