"""The data of an illusion model: targets, palette, model kind, objective weights.

:class:`IllusionProblem` is what the encoder (:mod:`illuknit.design.models.illusion_models`) turns into a
:class:`~illuknit.solvers.model.Model` (it rides along as the model's
:class:`~illuknit.solvers.model.DomainPayload`) and what design's own backends
(:mod:`illuknit.design.models.backends`: the DP, the descent, the gradient) read directly; the objective
pieces they share with the encoder (:func:`raised_cost`) live here too, so backends and encoder
import this module and never each other.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.arguments import check_bool, check_instance, check_int
from illuknit.core.errors import ImageInputError, OptionError, SolverError, UnknownNameError
from illuknit.core.pattern import MAX_UNITS, MAX_YARNS
from illuknit.solvers.model import DomainPayload, Model

__all__ = [
    "HANDS_SOLVERS",
    "MODEL_KINDS",
    "SPLIT_BUMPS_SOLVERS",
    "IllusionProblem",
    "KnitWeights",
    "make_problem",
    "parse_weights",
    "pass_events",
    "problem_of",
    "raised_cost",
    "row_passes",
]

#: Why a heuristic backend refuses a split-bump model, and which backends solve one.
SPLIT_BUMPS_SOLVERS = (
    "split bumps are solved by the exact DP and the MaxSAT/CP backends (dp, rc2, cpsat)"
)

#: Why a backend refuses a model made for hands, and which backends solve one.
HANDS_SOLVERS = (
    "a model made for hands couples the units of every row (the hand knitter's row rule); it "
    "is solved by the MaxSAT/CP backends (cpsat, rc2), warm-started by the hand row descent"
)

ModelKind = Literal["logical", "knit-aware", "single"]
MODEL_KINDS: tuple[str, ...] = ("logical", "knit-aware", "single")
#: The largest weight of an objective term (larger ones overflow the solvers' integer sums).
MAX_WEIGHT = 1_000_000


@dataclass(frozen=True)
class KnitWeights:
    """Objective weights (positive integers, 0 switches a term off).

    By default model (b) weighs view cells against machine passes only: colour changes and
    bumps cost the machine nothing in themselves (a carrier floats across the other colours'
    stitches, one transfer pass moves every loop of a course), and weighing them anyway made
    the model trade real passes for fewer of them (docs/solvers.md, "Machine passes").

    Parameters
    ----------
    view : int
        Per view cell (A or B) that does not show its target yarn.
    color_change : int
        Per yarn change between horizontally adjacent units of a course (model (b)).
    transfer : int
        Per knit<->purl change between consecutive courses; a bump costs two (model (b)).
    max_color_changes : int or None
        Hard cap on yarn changes per course (per unit row), or None for no cap (model (b)).
    machine_pass : int
        Per machine carriage pass the pattern forces (model (b)), as the mixed-colourwork
        scheduler knits it (:func:`row_passes`). A unit row is two courses, and each course needs
        one pass per carrier that knits in it: two passes per *segment* of the row, a yarn's
        regions a float can join (one per yarn used, plus an *extra carrier* for a region more
        than ``float_gap`` units after the yarn's previous region in the row). A row with a bump
        needs loops moved between the beds (one transfer pass into the purl course, one back),
        and in its purl course every carrier but one floats across another carrier's purls,
        whose loops must be moved out of its way first (float avoidance): one transfer pass
        more per segment beyond the first. So a row costs ``2 S`` passes flat and ``3 S + 1``
        with a bump.
    float_gap : int
        Longest gap (units) a yarn floats across between its regions of one row: the machine's
        float limit in needles over the two needles of a unit (20 / 2 on the default bed).
    """

    view: int = 4
    color_change: int = 0
    transfer: int = 0
    max_color_changes: int | None = None
    machine_pass: int = 6
    float_gap: int = 10

    def __post_init__(self) -> None:
        g = self.float_gap
        if not isinstance(g, int | np.integer) or isinstance(g, bool) or not 1 <= g <= MAX_UNITS:
            raise OptionError(
                f"`float_gap` must be a whole number of units in [1, {MAX_UNITS}], got {g!r}"
            )
        for name in ("view", "color_change", "transfer", "machine_pass"):
            v = getattr(self, name)
            if (
                not isinstance(v, int | np.integer)
                or isinstance(v, bool)
                or not 0 <= v <= MAX_WEIGHT
            ):
                raise OptionError(
                    f"weight `{name}` must be an integer in [0, {MAX_WEIGHT}], got {v!r}"
                )
        if self.view == 0:
            raise OptionError("weight `view` must be positive")
        cap = self.max_color_changes
        if cap is not None and (
            not isinstance(cap, int | np.integer)
            or isinstance(cap, bool)
            or not 0 <= cap <= MAX_UNITS
        ):
            raise OptionError(
                f"`max_color_changes` must be an integer in [0, {MAX_UNITS}] or None, got {cap!r}"
            )


def parse_weights(text: str | None, *, base: KnitWeights | None = None) -> KnitWeights:
    """Parse ``"view=4,color_change=1,transfer=1,max_color_changes=6"`` (any subset).

    ``color``/``colour``/``colour_change`` and ``cap`` are accepted as aliases.
    """
    w = base or KnitWeights()
    if not text or not text.strip():
        return w
    alias = {
        "color": "color_change",
        "colour": "color_change",
        "colour_change": "color_change",
        "transfers": "transfer",
        "cap": "max_color_changes",
        "max_colour_changes": "max_color_changes",
        "passes": "machine_pass",
        "pass": "machine_pass",
    }
    valid = ("view", "color_change", "transfer", "max_color_changes", "machine_pass", "float_gap")
    changes: dict[str, Any] = {}
    for part in text.split(","):
        if not part.strip():
            continue
        key, sep, val = part.partition("=")
        key = alias.get(key.strip().replace("-", "_"), key.strip().replace("-", "_"))
        if not sep or key not in valid:
            raise UnknownNameError("weight", part.strip(), [f"{v}=N" for v in valid])
        val = val.strip()
        if key == "max_color_changes" and val.lower() in ("none", ""):
            changes[key] = None
            continue
        try:
            changes[key] = int(val)
        except ValueError:
            raise OptionError(f"weight `{key}` must be an integer, got {val!r}") from None
    return replace(w, **changes)


def _index_image(a: ArrayLike, name: str, n_yarns: int) -> NDArray[np.int16]:
    arr = np.asarray(a)
    if arr.ndim != 2 or arr.size == 0:
        raise ImageInputError(
            f"`{name}` must be a non-empty 2-D yarn-index image, got shape {arr.shape}"
        )
    if not np.issubdtype(arr.dtype, np.integer):
        raise ImageInputError(f"`{name}` must hold integer yarn indices, got dtype {arr.dtype}")
    lo, hi = int(arr.min()), int(arr.max())
    if lo < 0 or hi >= n_yarns:
        bad = lo if lo < 0 else hi
        raise ImageInputError(
            f"`{name}` holds yarn index {bad}, outside the palette of {n_yarns} yarn(s) (0..{n_yarns - 1})"
        )
    out = arr.astype(np.int16)
    out.setflags(write=False)
    return out


@dataclass(frozen=True, eq=False)
class IllusionProblem(DomainPayload):
    """Targets and settings of an illusion model (the structured payload of its ``Model``).

    Parameters
    ----------
    target_a, target_b : ndarray of shape (N, M), int
        Yarn index each view cell should show (view A from above, view B from below). For the
        single-view model both are the same target.
    n_yarns : int
        Palette size K; every target index lies in 0..K-1.
    kind : {"logical", "knit-aware", "single"}
    weights : KnitWeights
    pinned : ndarray of shape (N, M), int, optional
        Yarn fixed by the designer per unit, -1 where free.
    alternate_rows : bool
        Single-view model only: neighbouring unit rows must have different yarns.
    split_bumps : bool
        Logical model only: a raised unit may knit its second course in another yarn (a split
        bump, ``LogicalPattern.upper``), which view A sees and view B does not
        (:mod:`illuknit.core.views`).
    for_hands : bool
        Made for hands (issue #37): every row must be knittable by hand
        (:attr:`illuknit.design.hand_cost.HandRow.knittable`) -- at most
        :data:`~illuknit.design.hand_cost.MAX_HAND_BLOCKS` colour blocks (intarsia), or at most
        :data:`~illuknit.design.hand_cost.MAX_HAND_YARNS` yarns with floats of at most
        :data:`~illuknit.design.hand_cost.MAX_FLOAT` stitches (stranded). Hard constraints that
        couple the units of a row, so the per-wale DP no longer applies.
    """

    target_a: NDArray[np.int16]
    target_b: NDArray[np.int16]
    n_yarns: int
    kind: str = "logical"
    weights: KnitWeights = field(default_factory=KnitWeights)
    pinned: NDArray[np.int16] | None = None
    alternate_rows: bool = False
    split_bumps: bool = False
    for_hands: bool = False

    def __post_init__(self) -> None:
        check_instance(self.kind, str, "kind", what=f"a model kind ({', '.join(MODEL_KINDS)})")
        if self.kind not in MODEL_KINDS:
            raise UnknownNameError("model", str(self.kind), MODEL_KINDS)
        check_bool(self.split_bumps, "split_bumps")
        check_bool(self.alternate_rows, "alternate_rows")
        check_bool(self.for_hands, "for_hands")
        check_instance(self.weights, KnitWeights, "weights")
        if self.split_bumps and self.kind != "logical":
            raise OptionError(
                "split bumps are modelled in the logical model only (the knit-aware model's "
                "pass terms do not count a split bump's second yarn; the single-view model "
                f"shows one picture), not {self.kind!r}"
            )
        if self.split_bumps and self.for_hands:
            raise OptionError(
                "split bumps are not made for hands: a split bump changes yarn between the two "
                "courses of a unit, which the hand knitter's row constraints do not model"
            )
        if self.for_hands and self.kind == "single":
            raise OptionError(
                "every row of the single-view model is one yarn, knittable by hand already: "
                "`for_hands` would change nothing"
            )
        if self.alternate_rows and self.kind != "single":
            raise OptionError(
                f"`alternate_rows` applies to the single-view model only, not {self.kind!r}"
            )
        k = check_int(self.n_yarns, "n_yarns", min=1, max=MAX_YARNS)
        a = _index_image(self.target_a, "target_a", k)
        b = _index_image(self.target_b, "target_b", k)
        if a.shape != b.shape:
            raise ImageInputError(
                f"targets A and B must have the same size, got {a.shape[0]}x{a.shape[1]} and "
                f"{b.shape[0]}x{b.shape[1]} units (resize one, e.g. `illuknit solve --resize`)"
            )
        object.__setattr__(self, "target_a", a)
        object.__setattr__(self, "target_b", b)
        object.__setattr__(self, "n_yarns", k)
        if self.pinned is not None:
            p = np.asarray(self.pinned)
            if p.shape != a.shape or not np.issubdtype(p.dtype, np.integer):
                raise OptionError(f"`pinned` must be an int array of shape {a.shape}")
            if int(p.max()) >= k or int(p.min()) < -1:
                raise OptionError(f"`pinned` values must lie in -1..{k - 1}")
            p = p.astype(np.int16)
            p.setflags(write=False)
            object.__setattr__(self, "pinned", p)

    @property
    def shape(self) -> tuple[int, int]:
        return (int(self.target_a.shape[0]), int(self.target_a.shape[1]))

    @property
    def view_weight(self) -> int:
        """Weight of a mismatched view cell: 1 (count of cells) unless knit-aware."""
        return self.weights.view if self.kind == "knit-aware" else 1

    @property
    def color_weight(self) -> int:
        """Weight of colour changes (0 unless knit-aware)."""
        return self.weights.color_change if self.kind == "knit-aware" else 0

    @property
    def transfer_weight(self) -> int:
        """Weight of knit<->purl changes (0 unless knit-aware)."""
        return self.weights.transfer if self.kind == "knit-aware" else 0

    @property
    def pass_weight(self) -> int:
        """Weight of a machine pass (0 unless knit-aware)."""
        return self.weights.machine_pass if self.kind == "knit-aware" else 0

    @property
    def color_cap(self) -> int | None:
        return self.weights.max_color_changes if self.kind == "knit-aware" else None

    @property
    def rows_tied(self) -> bool:
        """True when every unit row must be knit in one yarn (the single-view model)."""
        return self.kind == "single"

    @property
    def per_wale(self) -> bool:
        """True when nothing couples different wales (then the per-wale DP is exact)."""
        return (
            self.color_weight == 0
            and self.pass_weight == 0
            and self.color_cap is None
            and not self.rows_tied
            and not self.for_hands
        )

    @property
    def separable(self) -> bool:
        """Per wale, the model falls apart into independent wales (:attr:`per_wale`)."""
        return self.per_wale


def problem_of(model: Model) -> IllusionProblem:
    """The :class:`IllusionProblem` ``model`` was built from (its payload).

    Raises
    ------
    SolverError
        ``model`` is not an illusion model.
    """
    if not isinstance(model.problem, IllusionProblem):
        raise SolverError(f"model {model.name!r} is not an illusion model")
    return model.problem


def make_problem(
    target_a: ArrayLike,
    target_b: ArrayLike | None = None,
    *,
    n_yarns: int | None = None,
    kind: str = "logical",
    weights: KnitWeights | None = None,
    pinned: ArrayLike | None = None,
    alternate_rows: bool = False,
    split_bumps: bool = False,
) -> IllusionProblem:
    """An :class:`IllusionProblem`; ``target_b`` defaults to ``target_a`` (single view).

    ``n_yarns`` defaults to ``max(target) + 1``. ``alternate_rows`` (single view only): rows
    alternate yarns. ``split_bumps`` (logical model only): bumps may be split. Made for hands:
    ``dataclasses.replace(problem, for_hands=True)`` (:attr:`IllusionProblem.for_hands`).
    """
    a = np.asarray(target_a)
    b = a if target_b is None else np.asarray(target_b)
    if kind == "single" and target_b is not None and not np.array_equal(a, b):
        raise OptionError("the single-view model takes one target (target_b must be None or equal)")
    if n_yarns is None:
        n_yarns = int(max(int(np.max(a)), int(np.max(b)))) + 1 if a.size and b.size else 1
    pin = None if pinned is None else np.asarray(pinned)
    return IllusionProblem(
        a,
        b,
        int(n_yarns),
        kind,
        weights or KnitWeights(),
        pin,
        bool(alternate_rows),
        bool(split_bumps),
    )


def raised_cost(n: int, m: int, w: int) -> NDArray[np.int64]:
    """Per-unit weight of being raised: 2 bed changes per bump, 1 in the top row."""
    c = np.full((n, m), 2 * w, dtype=np.int64)
    c[0] = w
    return c


def pass_events(
    yarn: NDArray[np.integer], raised: NDArray[np.bool_], n_yarns: int, float_gap: int
) -> tuple[NDArray[np.int64], NDArray[np.bool_], NDArray[np.int64]]:
    """What forces machine passes, per unit row (see :class:`KnitWeights`).

    Returns
    -------
    yarns_used : ndarray of shape (N,), int
        Distinct yarns in each row.
    bump_rows : ndarray of shape (N,), bool
        Rows with at least one bump.
    extra_carriers : ndarray of shape (N,), int
        Regions that start more than ``float_gap`` units after the previous region of their
        yarn in the row.
    """
    c = np.asarray(yarn, dtype=np.int64)
    r = np.asarray(raised, dtype=bool)
    n, m = c.shape
    used = np.stack([(c == k).any(axis=1) for k in range(n_yarns)], axis=1)
    extra = np.zeros(n, dtype=np.int64)
    g = int(float_gap)
    for k in range(n_yarns):
        x = c == k
        if m <= g + 2:
            continue
        # a start at j: x[j], none of x[j-g-1..j-1] (a gap of more than g units), and some x
        # before that
        seen = np.cumsum(x, axis=1) > 0  # prefix "some x at <= j"
        window = np.zeros((n, m), dtype=bool)
        for d in range(1, g + 2):
            window[:, d:] |= x[:, :-d]
        start = x & ~window
        start[:, : g + 2] = False
        start[:, g + 2 :] &= seen[:, : m - g - 2]
        extra += start.sum(axis=1)
    bump_rows: NDArray[np.bool_] = np.asarray(r.any(axis=1), dtype=bool)
    return used.sum(axis=1).astype(np.int64), bump_rows, extra


def row_passes(
    yarn: NDArray[np.integer], raised: NDArray[np.bool_], n_yarns: int, float_gap: int
) -> NDArray[np.int64]:
    """Machine passes each unit row forces, as model (b) counts them (see :class:`KnitWeights`).

    With ``S`` the row's segments (yarns used plus extra carriers, :func:`pass_events`): ``2 S``
    for a flat row, ``2 S + 1 + S`` for a row with a bump (the bed changes in and out of its
    purl course, and one float-avoidance transfer pass per segment beyond the first).

    Returns
    -------
    ndarray of shape (N,), int64

    Examples
    --------
    >>> row_passes(np.array([[0, 1], [0, 0]]), np.array([[True, False], [False, False]]), 2, 10)
    array([7, 2])
    """
    used, bump_rows, extra = pass_events(yarn, raised, n_yarns, float_gap)
    segments = used + extra
    return 2 * segments + bump_rows.astype(np.int64) * (segments + 1)
