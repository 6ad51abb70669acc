"""Frozen, validated options of the design stages (:mod:`illuknit.pipeline.stages`).

:class:`SearchOptions` says how tile designs are searched, :class:`RankOptions` how they are
ranked, :class:`SolveOptions` how a constraint model is solved. Choices are enums whose values
are the words the CLI takes (``RankBy("knit-time")`` reads ``--rank-by knit-time``); a string
given for an enum field is read as its member, and anything else is refused where the options
are made, with an :class:`~illuknit.core.errors.OptionError` naming the field.

Examples
--------
>>> SearchOptions(candidates=3).pool
20
>>> RankOptions(rank_by="score").rank_by
<RankBy.SCORE: 'score'>
>>> RankOptions().rank_by  # resolved when the designs are ranked (RankChoice)
<RankBy.AUTO: 'auto'>
>>> SearchOptions(brightness="firm")
Traceback (most recent call last):
...
illuknit.core.errors.OptionError: `brightness` must be one of hard, soft, got 'firm'
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum, StrEnum
from typing import Any

from illuknit.core.arguments import MAX_SECONDS, MAX_SEED
from illuknit.core.declared import accepts_old_names, check_declared_range, option
from illuknit.core.errors import OptionError
from illuknit.core.machine import MachineSpec, resolve_machine
from illuknit.core.views import DEFAULT_SPLIT_SHARE
from illuknit.design.models.illusion_problem import KnitWeights

__all__ = [
    "Brightness",
    "MadeFor",
    "ModelKind",
    "PictureEdits",
    "RankBy",
    "RankOptions",
    "SearchOptions",
    "SolveOptions",
    "WarmStart",
]

#: How many tile designs are searched by default before ranking them by how they read
#: (``illuknit double --pool``; :func:`~illuknit.design.tiles.assign.assign_tiles` ``pool=``): the
#: assignment's score does not see how a design reads, and on the bundled double-view pairs the
#: best-reading design is often past the score's fifth place.
DEFAULT_POOL = 20
#: The most of anything counted here (designs searched, courses between joins): more is a slip.
MAX_COUNT = 1000
#: Designs past the ones to be written are sought only while the search took less than this.
POOL_SECONDS = 20.0
#: Made for hands, double view: seconds the constraint model made for hands is solved for, beside
#: the tile search (``SearchOptions.hand_model_seconds``; benchmarks/hand_designs.py measures it).
HAND_MODEL_SECONDS = 20.0


# -- validators (shared with illuknit.knit.options) ----------------------------------------


def enum_option(cls: type[Enum], name: str, value: Any) -> Any:
    """``value`` as a member of ``cls`` (its value string is read as the member)."""
    if isinstance(value, cls):
        return value
    if isinstance(value, str):
        try:
            return cls(value.strip().lower())
        except ValueError:
            pass
    valid = ", ".join(str(m.value) for m in cls)
    raise OptionError(f"`{name}` must be one of {valid}, got {value!r}")


def flag_option(name: str, value: Any) -> bool:
    """``value``, refused unless it is True or False."""
    if not isinstance(value, bool):
        raise OptionError(f"`{name}` must be True or False, got {value!r}")
    return value


def count_option(name: str, value: Any, *, minimum: int, maximum: int = MAX_COUNT) -> int:
    """``value``, refused unless it is an integer in [``minimum``, ``maximum``]."""
    if not isinstance(value, int) or isinstance(value, bool) or value < minimum:
        what = "a positive integer" if minimum == 1 else f"an integer >= {minimum}"
        raise OptionError(f"`{name}` must be {what}, got {value!r}")
    if value > maximum:
        raise OptionError(f"`{name}` must be at most {maximum}, got {value!r}")
    return value


def _seconds(name: str, value: Any) -> float:
    """``value``, refused unless it is a positive, finite number of seconds."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise OptionError(f"`{name}` must be a number of seconds, got {value!r}")
    if not (math.isfinite(value) and value > 0):
        raise OptionError(f"`{name}` must be positive and finite, got {value!r}")
    if value > MAX_SECONDS:
        raise OptionError(
            f"`{name}` must be at most {MAX_SECONDS:g} seconds (a week), got {value!r}"
        )
    return float(value)


class Brightness(StrEnum):
    """Keep each picture's brightness order strictly (``HARD``) or only prefer to (``SOFT``)."""

    HARD = "hard"
    SOFT = "soft"


class PictureEdits(StrEnum):
    """Simplifying edits of the pictures before a double-view design (:mod:`illuknit.design.tiles.simplify`).

    ``NONE``: design the pictures as given; ``SUGGEST``: also measure each edit by the best
    design it leads to, and report it; ``APPLY``: as ``SUGGEST``, and design with the edits that
    raise the worse view's readability.
    """

    NONE = "none"
    SUGGEST = "suggest"
    APPLY = "apply"


class RankBy(StrEnum):
    """The order of ranked tile designs; :attr:`key_fields` names the parts of its rank key.

    ``AUTO`` (the default) is no order of its own: where the designs are ranked it becomes
    ``LEGIBILITY`` when both pictures of a double view are words (the reader,
    :func:`~illuknit.design.legibility.words_of`, says so) and tesseract is installed, and
    ``PERCEPTION`` otherwise; the :class:`~illuknit.design.rank_choice.RankChoice` says which and why
    (:func:`~illuknit.pipeline.tile_search.choose_order`). On word pairs the correlation
    picks designs one side of which no reader reads (docs/legibility.md).
    """

    AUTO = "auto"
    PERCEPTION = "perception"
    SCORE = "score"
    READABILITY = "readability"
    CONTRAST = "contrast"
    GHOSTING = "ghosting"
    KNIT_TIME = "knit-time"
    HAND_TIME = "hand-time"
    LEGIBILITY = "legibility"

    @property
    def key_fields(self) -> tuple[str, ...]:
        """What each entry of a design's rank key is (ascending: the best design sorts first;
        a negated measure is one where higher is better). ``AUTO`` has none until resolved
        (:class:`~illuknit.design.rank_choice.RankChoice`): asking is an
        :class:`~illuknit.core.errors.OptionError`."""
        if self is RankBy.AUTO:
            raise OptionError(
                "rank_by auto has no key of its own: it is resolved to legibility or "
                "perception when the designs are ranked (TileDesign.order says which)"
            )
        return _KEY_FIELDS[self]


_KEY_FIELDS = {
    RankBy.PERCEPTION: (
        "-perceptual score",
        "worst visible ghosting",
        "knitting minutes",
        "assignment score",
    ),
    RankBy.SCORE: ("assignment score",),
    RankBy.READABILITY: ("-worse readability", "worst ghosting", "assignment score"),
    RankBy.CONTRAST: ("-worse contrast", "-worse readability", "assignment score"),
    RankBy.GHOSTING: ("worst visible ghosting", "-worse readability", "assignment score"),
    RankBy.KNIT_TIME: ("knitting minutes", "-perceptual score", "assignment score"),
    RankBy.HAND_TIME: ("hours by hand", "-perceptual score", "assignment score"),
    RankBy.LEGIBILITY: (
        "-sides that read",
        "-perceptual score",
        "worst visible ghosting",
        "knitting minutes",
        "assignment score",
    ),
}


class MadeFor(StrEnum):
    """Who knits the design: ``MACHINE`` (the default order, ``rank_by`` alone) or ``HANDS``
    (the share of rows a hand knitter can work first, :mod:`illuknit.design.hand_cost`, then
    ``rank_by``'s order)."""

    MACHINE = "machine"
    HANDS = "hands"


#: The rank key's first field when a design is made for hands.
HAND_KEY_FIELD = "-share of rows knittable by hand"


@accepts_old_names
@dataclass(frozen=True)
class SearchOptions:
    """How tile designs are searched (:func:`~illuknit.design.tiles.assign.assign_tiles`).

    Parameters
    ----------
    candidates : int
        How many ranked designs to keep (1-50).
    pool : int
        How many designs to search and rank (at least ``candidates`` are searched).
    pool_seconds : float
        The designs past ``candidates`` are sought only within this many seconds.
    solver : str
        The backend of each assignment solve (``"cpsat"``, ``"rc2"``, ...).
    brightness : Brightness or str
    one_sided : bool
        Only tiles that are solid from at least one side (the default bank only).
    split_bumps : bool
        The canonical bank also holds split bumps (``docs/split-bumps.md``): a bump knitted in
        two yarns, one for each side. A bank file lists its own tiles instead.
    split_share : float
        How much of a split bump's colour each side sees of its own course, in (0.5, 1]
        (``RenderParams.split_share``; the estimate 0.75 until a swatch is measured): the
        bank's fills and the renders the designs are ranked by count the rest as the other
        course.
    edits : PictureEdits or str
        Simplifying edits of the pictures (double view only).
    time_limit : float, optional
        Time limit of each assignment solve in seconds (None: no limit); formerly
        ``solve_seconds`` (still taken, with a :class:`DeprecationWarning`, for one release).
    hand_model_seconds : float
        Made for hands, double view: also solve the constraint model made for hands (every
        row knittable by hand a hard constraint, :func:`~illuknit.pipeline.solve.solve_design`
        with ``made_for="hands"``) for this many seconds on the same grid, and rank its design
        with the tile designs; 0 leaves it out.
    """

    candidates: int = option(5, help="How many ranked candidates to write.", ge=1, le=50)
    pool: int = option(
        DEFAULT_POOL,
        help="How many tile designs to search and rank before writing the best --candidates "
        f"(designs past --candidates only within {POOL_SECONDS:g} s).",
        ge=1,
        le=MAX_COUNT,
    )
    pool_seconds: float = option(
        POOL_SECONDS,
        help="The designs past the candidates are sought only within this many seconds.",
        gt=0,
        le=MAX_SECONDS,
    )
    solver: str = option("cpsat", help="Solver backend: cpsat, rc2, ...")
    brightness: Brightness = option(
        Brightness.HARD,
        help="Keep each picture's brightness order (hard), or only prefer to (soft).",
    )
    one_sided: bool = option(False, help="Only tiles that are solid from at least one side.")
    split_bumps: bool = option(
        False,
        help="Tiles may hold split bumps: a bump knitted in two yarns, one seen from each side "
        "(docs/split-bumps.md).",
    )
    split_share: float = option(
        DEFAULT_SPLIT_SHARE,
        help="Share of a split bump's colour each side sees of its own course, as measured on a "
        "swatch.",
        gt=0.5,
        le=1.0,
    )
    edits: PictureEdits = option(
        PictureEdits.NONE, help="Simplifying edits of the pictures (double view only)."
    )
    time_limit: float | None = option(
        10.0,
        help="Time limit of each assignment solve in seconds (none: no limit).",
        gt=0,
        le=MAX_SECONDS,
        old_names=("solve_seconds",),
    )
    hand_model_seconds: float = option(
        HAND_MODEL_SECONDS,
        help="Made for hands: also solve the constraint model made for hands (every row "
        "knittable by hand) for this many seconds and rank its design with the tile designs "
        "(0: leave it out).",
        ge=0,
        le=MAX_SECONDS,
    )

    def __post_init__(self) -> None:
        count_option("candidates", self.candidates, minimum=1)
        check_declared_range(SearchOptions, "candidates", self.candidates, OptionError)
        count_option("pool", self.pool, minimum=1)
        _seconds("pool_seconds", self.pool_seconds)
        if not isinstance(self.solver, str) or not self.solver.strip():
            raise OptionError(f"`solver` must be a backend name, got {self.solver!r}")
        if self.time_limit is not None:
            _seconds("time_limit", self.time_limit)
        seconds = self.hand_model_seconds
        if isinstance(seconds, bool) or not isinstance(seconds, int | float):
            raise OptionError(f"`hand_model_seconds` must be a number, got {seconds!r}")
        check_declared_range(SearchOptions, "hand_model_seconds", seconds, OptionError)
        flag_option("one_sided", self.one_sided)
        flag_option("split_bumps", self.split_bumps)
        share = self.split_share
        if isinstance(share, bool) or not isinstance(share, int | float):
            raise OptionError(f"`split_share` must be a number in (0.5, 1], got {share!r}")
        check_declared_range(SearchOptions, "split_share", share, OptionError)
        object.__setattr__(
            self, "brightness", enum_option(Brightness, "brightness", self.brightness)
        )
        object.__setattr__(self, "edits", enum_option(PictureEdits, "edits", self.edits))

    @property
    def solve_seconds(self) -> float | None:
        """Deprecated spelling of :attr:`time_limit` (one name for a solve's time limit, as
        :class:`SolveOptions` and :func:`~illuknit.design.tiles.assign.assign_tiles` spell it);
        reading it warns (:class:`DeprecationWarning`), for one release."""
        import warnings

        warnings.warn(
            "`SearchOptions.solve_seconds` is deprecated; read `time_limit`",
            DeprecationWarning,
            stacklevel=2,
        )
        return self.time_limit

    def assign_kwargs(self) -> dict[str, Any]:
        """The keywords of :func:`~illuknit.design.tiles.assign.assign_tiles` these options set."""
        return {
            "candidates": self.candidates,
            "pool": self.pool,
            "pool_seconds": self.pool_seconds,
            "solver": self.solver,
            "brightness": self.brightness.value,
            "time_limit": self.time_limit,
        }


@dataclass(frozen=True)
class RankOptions:
    """How tile designs are ranked (:func:`~illuknit.design.tiles.perception.rank_designs`).

    Parameters
    ----------
    rank_by : RankBy or str
        ``AUTO`` (default): the reader's order for two pictures of words when tesseract is
        installed, else perception (:class:`~illuknit.design.rank_choice.RankChoice`); any
        other order is used as given.
    knit_time : bool
        Also knit the designs that can matter and measure the machine's knitting time (it
        breaks ties under ``PERCEPTION``; ``KNIT_TIME`` implies it).
    machine : str or MachineSpec, optional
        The machine the knitting time is measured on (default machine when None).
    overrides : mapping or sequence of pairs
        ``{(colour of A, colour of B): "ROWS"}``: the tile of an overlap pair, as knit.
    angle : float
        The viewing angle (degrees of elevation, [3, 90]) the side views are rendered and
        measured at.
    distance : float
        The viewing distance in metres: the measures see the renders through what a 20/20 eye
        resolves from there at ``machine``'s gauge, then pooled over a fill's stripes
        (:func:`~illuknit.design.tiles.perception.seen_blur`).
    read : bool
        Also ask a reader (tesseract OCR, :mod:`illuknit.design.legibility`) whether each side
        of the kept double-view designs reads from ``distance``; ranking by ``LEGIBILITY``
        reads every design searched. Needs the ``tesseract`` program.
    made_for : MadeFor or str
        ``HANDS``: rank first by the share of rows a hand knitter can work
        (:attr:`~illuknit.design.hand_cost.HandCost.knittable_share`), then by ``rank_by``.
    """

    rank_by: RankBy = option(
        RankBy.AUTO,
        help="Order of the candidates: auto (legibility when both pictures are words and "
        "tesseract is installed, else perception; the summary says which and why), how the "
        "views read (perception: worse view's correlation, contrast floor, ghosting; "
        "legibility: designs whose both sides a reader reads first, needs tesseract), the "
        "assignment's score, or one measure.",
    )
    knit_time: bool = option(
        False,
        help="Also knit every candidate and show the machine's knitting time (ties in the "
        "ranking).",
        flag="--knit-time/--no-knit-time",
    )
    machine: str | MachineSpec | None = None
    overrides: tuple[tuple[tuple[int, int], str], ...] = ()
    angle: float = option(
        30.0,
        help="Viewing angle (degrees of elevation) the side views are judged and shown at.",
        # the renderer draws a side view in the fabric's proportions by undoing its
        # foreshortening (unit aspect / sin(angle)), which leaves its unit-aspect range
        # (0.05..20) below asin(0.7 / 20) = 2.006 degrees at stocking stitch's 0.7; from 3
        # degrees every gauge up to 1.05 (20 * sin 3 degrees) is drawn
        ge=3,
        le=90,
        title="Measured at angle",
    )
    distance: float = option(
        3.0,
        help="Viewing distance in metres: the measures see what a 20/20 eye resolves from there.",
        gt=0,
        le=1000,
        title="Measured from",
    )
    read: bool = option(
        False,
        help="Ask a reader (tesseract OCR) whether each side of the candidates reads from "
        "--distance.",
        flag="--read/--no-read",
    )
    made_for: MadeFor = option(
        MadeFor.MACHINE,
        help="Who knits it: hands ranks first the designs whose rows a hand knitter can work "
        "(2 yarns with floats of at most 7 sts, or at most 6 intarsia blocks), then by --rank-by.",
        flag="--for",
    )

    def __post_init__(self) -> None:
        object.__setattr__(self, "rank_by", enum_option(RankBy, "rank_by", self.rank_by))
        object.__setattr__(self, "made_for", enum_option(MadeFor, "made_for", self.made_for))
        flag_option("knit_time", self.knit_time)
        flag_option("read", self.read)
        for name in ("angle", "distance"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or math.isnan(v):
                raise OptionError(f"`{name}` must be a number, got {v!r}")
            check_declared_range(RankOptions, name, v, OptionError)
            object.__setattr__(self, name, float(v))
        resolve_machine(self.machine)
        if not isinstance(self.overrides, (dict, tuple, list)):
            raise OptionError(
                f"`overrides` maps (colour of A, colour of B) to tile rows, got {self.overrides!r}"
            )
        items = self.overrides.items() if isinstance(self.overrides, dict) else self.overrides
        pairs = []
        for item in items:
            try:
                (a, b), rows = item
            except (TypeError, ValueError):
                raise OptionError(
                    f"`overrides` maps (colour of A, colour of B) to tile rows, got {item!r}"
                ) from None
            if not all(isinstance(v, int) and not isinstance(v, bool) and v >= 0 for v in (a, b)):
                raise OptionError(f"`overrides` pairs are colour indices >= 0, got {(a, b)!r}")
            if not isinstance(rows, str) or not rows.strip():
                raise OptionError(f"`overrides` tiles are row strings like '0/1/0^', got {rows!r}")
            pairs.append(((a, b), rows.strip()))
        object.__setattr__(self, "overrides", tuple(sorted(dict(pairs).items())))

    @property
    def key_fields(self) -> tuple[str, ...]:
        """What each entry of a design's rank key is under these options."""
        hands = (HAND_KEY_FIELD,) if self.made_for is MadeFor.HANDS else ()
        return hands + self.rank_by.key_fields

    @property
    def override_map(self) -> dict[tuple[int, int], str]:
        """The overrides as :func:`~illuknit.design.tiles.compile.compile_tiles` takes them."""
        return dict(self.overrides)


class ModelKind(StrEnum):
    """The constraint models (:mod:`illuknit.design.models.illusion_models`, paper section 4)."""

    LOGICAL = "logical"
    KNIT_AWARE = "knit-aware"
    SINGLE = "single"


class WarmStart(StrEnum):
    """What a solver backend starts from (:mod:`illuknit.design.models.backends.warm_start`)."""

    AUTO = "auto"
    NONE = "none"
    DP = "dp"
    DESCENT = "descent"
    HAND = "hand"


@dataclass(frozen=True)
class SolveOptions:
    """How a constraint model is built and solved (:func:`~illuknit.design.models.illusion_models.solve_illusion`).

    Parameters
    ----------
    model : ModelKind or str
    solver : str
        A backend name, ``NAME:ORACLE``, ``wcnf:COMMAND`` or ``"auto"``.
    warm_start : WarmStart or str
    weights : KnitWeights, optional
        Knit-aware weights (default weights when None).
    alternate_rows : bool
        Single-view model: neighbouring rows must have different yarns.
    split_bumps : bool
        Logical model: bumps may be knitted in two yarns, one seen from each side
        (``docs/split-bumps.md``).
    time_limit : float, optional
        Seconds; the best pattern found is kept.
    seed : int
    made_for : MadeFor or str
        ``hands``: every row knittable by hand (at most 6 intarsia blocks, or 2 yarns with
        floats of at most 7 stitches; :mod:`illuknit.design.hand_cost`), hard constraints of
        the logical and knit-aware models (not the single-view model, whose rows are one yarn
        already, nor with split bumps).
    """

    model: ModelKind = option(
        ModelKind.LOGICAL,
        help="logical: fewest mismatched view cells (paper 4.2); knit-aware: also few colour "
        "changes per course and knit/purl changes; single: one picture seen from both sides, one "
        "yarn per row (a stripe head-on).",
    )
    solver: str = option(
        "auto",
        help="Backend: dp, cpsat, rc2[:ORACLE], lsu[:ORACLE], fm, the hermax solvers (uwrmaxsat, "
        "evalmaxsat, ...; see --list-solvers), descent, gradient, wcnf:COMMAND (an external "
        "MaxSAT binary; {} is the WCNF path), or auto (the exact DP when it applies, else "
        "CP-SAT).",
        metavar="NAME",
    )
    warm_start: WarmStart = option(
        WarmStart.AUTO,
        help="What the backend starts from: nothing, the DP optimum, or a block descent (part "
        "of the time limit); auto: descent for the knit-aware model, else dp. The run says which "
        "it used and who found the pattern.",
    )
    weights: KnitWeights | None = None
    alternate_rows: bool = option(
        False,
        help="Single-view model: neighbouring rows must have different yarns (like `illuknit "
        "single`).",
    )
    split_bumps: bool = option(
        False,
        help="Logical model: a bump may be knitted in two yarns, one seen from each side "
        "(docs/split-bumps.md).",
    )
    time_limit: float | None = option(
        60.0, help="Seconds; the best pattern found is kept.", gt=0, le=MAX_SECONDS
    )
    seed: int = option(0, help="Random seed of the solver backend.", ge=0, le=MAX_SEED)
    made_for: MadeFor = MadeFor.MACHINE

    def __post_init__(self) -> None:
        object.__setattr__(self, "model", enum_option(ModelKind, "model", self.model))
        object.__setattr__(self, "made_for", enum_option(MadeFor, "made_for", self.made_for))
        if self.made_for is MadeFor.HANDS and self.model is ModelKind.SINGLE:
            raise OptionError(
                "made for hands changes nothing in the single-view model: every row is one "
                "yarn, knittable by hand already"
            )
        if self.made_for is MadeFor.HANDS and self.split_bumps:
            raise OptionError(
                "split bumps are not made for hands: a split bump changes yarn inside a unit, "
                "which the hand knitter's row rule does not model"
            )
        object.__setattr__(
            self, "warm_start", enum_option(WarmStart, "warm_start", self.warm_start)
        )
        if not isinstance(self.solver, str) or not self.solver.strip():
            raise OptionError(f"`solver` must be a backend name, got {self.solver!r}")
        if self.weights is not None and not isinstance(self.weights, KnitWeights):
            raise OptionError(f"`weights` must be KnitWeights, got {type(self.weights).__name__}")
        flag_option("alternate_rows", self.alternate_rows)
        if self.alternate_rows and self.model is not ModelKind.SINGLE:
            raise OptionError("`alternate_rows` applies to the single-view model only")
        flag_option("split_bumps", self.split_bumps)
        if self.split_bumps and self.model is not ModelKind.LOGICAL:
            raise OptionError(
                "`split_bumps` applies to the logical model only (the knit-aware model does not "
                "count a split bump's second yarn; the single-view model shows one picture)"
            )
        if self.time_limit is not None:
            _seconds("time_limit", self.time_limit)
        count_option("seed", self.seed, minimum=0, maximum=MAX_SEED)

    @property
    def for_hands(self) -> bool:
        """Every row must be knittable by hand (``made_for`` is hands)."""
        return self.made_for is MadeFor.HANDS
