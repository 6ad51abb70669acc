"""Constraint models of illusion patterns (paper sections 4.2 and 8.3), and their solutions.

Three models over an N x M grid of units and K yarns, built on :class:`illuknit.model.Model`:

**Variables.** ``("yarn", i, j, k)`` — unit (i, j) is knit in yarn k (one-hot over k);
``("raised", i, j)`` — unit (i, j) is a bump. Model (b) adds ``("change", i, j)`` — the yarn
changes between units (i, j) and (i, j+1) along the course.

**Hard constraints.** *one yarn per unit*: exactly one ``yarn`` variable per unit (at-least-one
clause + pairwise at-most-one). *pinned units* (optional): the designer fixed some units' yarn.
Model (b): *colour-change definition* ``yarn[i,j,k] & ~yarn[i,j+1,k] -> change[i,j]``, and the
optional *colour-change cap per course*: at most ``max_color_changes`` true ``change`` per row.
Model (c): *one yarn per course*: ``yarn[i,j,k] -> yarn[i,0,k]`` — every unit row is knit in one
yarn, so the piece is a plain stripe head-on (a single-view illusion must hide its picture there;
without this the optimum simply knits the picture, visible from every side) — and, with
``alternate_rows``, *alternating row colours*: ``~yarn[i,0,k] | ~yarn[i+1,0,k]`` (neighbouring
rows differ; with two yarns the rows alternate, as in the push-button compiler).

**Objective (soft).** (a) *logical* — the paper's model: each view cell that does not show its
target yarn costs ``weights.view``. With ``VA[i] = C[i-1] if R[i-1] else C[i]`` (row 0 always
``C[0]``), view A at (i, j) is encoded exactly by the two soft clauses
``(~R[i-1,j] | yarn[i-1,j,A]) `` and ``(R[i-1,j] | yarn[i,j,A])`` — whichever way ``R[i-1,j]``
goes, exactly one of them is live, so the violated weight equals the mismatch count. View B
mirrors it with ``R[i+1, j]``. (c) *single* — one target seen from both sides: (a) with A = B
and one yarn per course.
(b) *knit-aware* — (a) plus ``weights.color_change`` per ``change`` and ``weights.transfer`` per
knit<->purl change between consecutive courses. A bump is a knit course followed by a purl course
in the same wales, and every unit starts with a knit course, so a bump costs two bed changes (knit
-> purl inside it, purl -> knit into the unit above) — one in the top row, where the bind-off
follows.

Models (a) and (b) without colour-change terms couple only neighbouring units of one wale, so
:mod:`illuknit.solvers.dp` solves them exactly per wale; model (c) ties each row to one yarn, and
the DP solves it exactly over the row colours (a raised bit then affects two view cells whose
colours depend only on three consecutive row colours). The structured :class:`IllusionProblem`
rides along as ``model.problem`` for it. Model (b) with colour-change terms couples the wales;
:mod:`illuknit.solvers.descent` re-optimises single wales and courses exactly in turn and warm-
starts the exact backends.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.errors import (
    ImageInputError,
    InfeasibleError,
    OptionError,
    SolverError,
    UnknownNameError,
    YarnSpecError,
)
from illuknit.model import Model
from illuknit.pattern import LogicalPattern, Yarn
from illuknit.views import can_see, logical_error

if TYPE_CHECKING:
    from illuknit.solvers.base import ProgressCallback, Solution

__all__ = [
    "MODEL_KINDS",
    "IllusionProblem",
    "IllusionResult",
    "KnitWeights",
    "build_model",
    "color_changes_per_course",
    "default_yarns",
    "keep_warm_start",
    "knit_purl_changes",
    "make_problem",
    "parse_weights",
    "pattern_from_solution",
    "report_pattern",
    "solve_illusion",
    "warm_start",
]

ModelKind = Literal["logical", "knit-aware", "single"]
MODEL_KINDS: tuple[str, ...] = ("logical", "knit-aware", "single")


@dataclass(frozen=True)
class KnitWeights:
    """Objective weights (positive integers, 0 switches a term off).

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
    """

    view: int = 4
    color_change: int = 1
    transfer: int = 1
    max_color_changes: int | None = None

    def __post_init__(self) -> None:
        for name in ("view", "color_change", "transfer"):
            v = getattr(self, name)
            if not isinstance(v, int | np.integer) or isinstance(v, bool) or v < 0:
                raise OptionError(f"weight `{name}` must be an integer >= 0, got {v!r}")
        if self.view == 0:
            raise OptionError("weight `view` must be positive")
        cap = self.max_color_changes
        if cap is not None and (not isinstance(cap, int | np.integer) or cap < 0):
            raise OptionError(f"`max_color_changes` must be an integer >= 0 or None, got {cap!r}")


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
    }
    valid = ("view", "color_change", "transfer", "max_color_changes")
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
class IllusionProblem:
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
    """

    target_a: NDArray[np.int16]
    target_b: NDArray[np.int16]
    n_yarns: int
    kind: str = "logical"
    weights: KnitWeights = field(default_factory=KnitWeights)
    pinned: NDArray[np.int16] | None = None
    alternate_rows: bool = False

    def __post_init__(self) -> None:
        if self.kind not in MODEL_KINDS:
            raise UnknownNameError("model", str(self.kind), MODEL_KINDS)
        if self.alternate_rows and self.kind != "single":
            raise OptionError(
                f"`alternate_rows` applies to the single-view model only, not {self.kind!r}"
            )
        k = int(self.n_yarns)
        if k < 1:
            raise OptionError(f"`n_yarns` must be >= 1, got {self.n_yarns}")
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
    def color_cap(self) -> int | None:
        return self.weights.max_color_changes if self.kind == "knit-aware" else None

    @property
    def rows_tied(self) -> bool:
        """True when every unit row must be knit in one yarn (the single-view model)."""
        return self.kind == "single"

    @property
    def per_wale(self) -> bool:
        """True when nothing couples different wales (then the per-wale DP is exact)."""
        return self.color_weight == 0 and self.color_cap is None and not self.rows_tied


def make_problem(
    target_a: ArrayLike,
    target_b: ArrayLike | None = None,
    *,
    n_yarns: int | None = None,
    kind: str = "logical",
    weights: KnitWeights | None = None,
    pinned: ArrayLike | None = None,
    alternate_rows: bool = False,
) -> IllusionProblem:
    """An :class:`IllusionProblem`; ``target_b`` defaults to ``target_a`` (single view).

    ``n_yarns`` defaults to ``max(target) + 1``. ``alternate_rows`` (single view only): rows
    alternate yarns.
    """
    a = np.asarray(target_a)
    b = a if target_b is None else np.asarray(target_b)
    if kind == "single" and target_b is not None and not np.array_equal(a, b):
        raise OptionError("the single-view model takes one target (target_b must be None or equal)")
    if n_yarns is None:
        n_yarns = int(max(int(np.max(a)), int(np.max(b)))) + 1 if a.size and b.size else 1
    pin = None if pinned is None else np.asarray(pinned)
    return IllusionProblem(
        a, b, int(n_yarns), kind, weights or KnitWeights(), pin, bool(alternate_rows)
    )


# -- encoding ---------------------------------------------------------------------------------


def _raised_cost(n: int, m: int, w: int) -> NDArray[np.int64]:
    """Per-unit weight of being raised: 2 bed changes per bump, 1 in the top row."""
    c = np.full((n, m), 2 * w, dtype=np.int64)
    c[0] = w
    return c


def build_model(problem: IllusionProblem) -> Model:
    """Encode ``problem`` as a :class:`Model` (vectorised; see the module docstring).

    Returns
    -------
    Model
        With variable blocks ``"yarn"`` (N, M, K), ``"raised"`` (N, M) and, when knit-aware with
        colour terms, ``"change"`` (N, M-1); ``model.problem`` is ``problem``.
    """
    n, m = problem.shape
    k = problem.n_yarns
    wv = problem.view_weight
    model = Model(f"illusion-{problem.kind}-{n}x{m}-k{k}", problem=problem)
    x = model.pool.block("yarn", (n, m, k))
    r = model.pool.block("raised", (n, m))

    # one yarn per unit: at least one (width K) + pairwise at most one
    model.add_hard_block(x.reshape(-1, k), family="one yarn per unit")
    for a in range(k):
        for b in range(a + 1, k):
            model.add_hard_block(
                np.stack([-x[..., a].ravel(), -x[..., b].ravel()], axis=1),
                family="one yarn per unit",
            )
    if problem.pinned is not None:
        ii, jj = np.nonzero(problem.pinned >= 0)
        if ii.size:
            model.add_hard_block(x[ii, jj, problem.pinned[ii, jj]][:, None], family="pinned units")
    if problem.rows_tied and m > 1:
        # unit (i, j) in yarn k -> unit (i, 0) in yarn k; with one-hot units all share one yarn
        first = np.broadcast_to(x[:, :1, :], (n, m - 1, k))
        model.add_hard_block(
            np.stack([-x[:, 1:, :], first], axis=-1).reshape(-1, 2), family="one yarn per course"
        )
    if problem.alternate_rows and n > 1:
        model.add_hard_block(
            np.stack([-x[:-1, 0, :], -x[1:, 0, :]], axis=-1).reshape(-1, 2),
            family="alternating row colours",
        )

    cols = np.arange(m)[None, :]
    ta = problem.target_a.astype(np.int64)
    tb = problem.target_b.astype(np.int64)
    soft: list[NDArray[np.int64]] = []
    # view A, row 0 sees C[0]
    soft.append(np.stack([x[0, cols[0], ta[0]], np.zeros(m, np.int64)], axis=1))
    if n > 1:
        rows = np.arange(1, n)[:, None]
        # R[i-1] -> C[i-1] == A[i]     and    ~R[i-1] -> C[i] == A[i]
        soft.append(
            np.stack([-r[rows - 1, cols], x[rows - 1, cols, ta[1:]]], axis=-1).reshape(-1, 2)
        )
        soft.append(np.stack([r[rows - 1, cols], x[rows, cols, ta[1:]]], axis=-1).reshape(-1, 2))
    # view B, row N-1 sees C[N-1]
    soft.append(np.stack([x[n - 1, cols[0], tb[n - 1]], np.zeros(m, np.int64)], axis=1))
    if n > 1:
        rows = np.arange(0, n - 1)[:, None]
        soft.append(
            np.stack([-r[rows + 1, cols], x[rows + 1, cols, tb[:-1]]], axis=-1).reshape(-1, 2)
        )
        soft.append(np.stack([r[rows + 1, cols], x[rows, cols, tb[:-1]]], axis=-1).reshape(-1, 2))
    model.add_soft_block(np.concatenate(soft), wv)

    wt = problem.transfer_weight
    if wt:
        model.add_soft_block(-r.reshape(-1, 1), _raised_cost(n, m, wt).ravel())

    wc = problem.color_weight
    cap = problem.color_cap
    if (wc or cap is not None) and m > 1:
        d = model.pool.block("change", (n, m - 1))
        for c in range(k):
            model.add_hard_block(
                np.stack([-x[:, :-1, c], x[:, 1:, c], d], axis=-1).reshape(-1, 3),
                family="colour-change definition",
            )
        if wc:
            model.add_soft_block(-d.reshape(-1, 1), wc)
        if cap is not None:
            for i in range(n):
                model.add_at_most_k(d[i].tolist(), cap, family="colour-change cap per course")
    return model


# -- decoding and report ----------------------------------------------------------------------


def default_yarns(n_yarns: int) -> tuple[Yarn, ...]:
    """A readable palette of ``n_yarns`` greys from dark to light (when no yarns are given)."""
    if n_yarns == 1:
        return (Yarn("grey", (128, 128, 128)),)
    levels = np.linspace(27, 244, n_yarns).round().astype(int)
    return tuple(Yarn(f"yarn {i}", (int(v), int(v), int(v))) for i, v in enumerate(levels))


def pattern_from_solution(
    problem: IllusionProblem,
    solution: Solution,
    *,
    yarns: Sequence[Yarn] | None = None,
    meta: Mapping[str, Any] | None = None,
) -> LogicalPattern:
    """The :class:`LogicalPattern` of a solution of :func:`build_model` (``solution.pool`` set).

    Raises :class:`SolverError` when the solution holds no assignment.
    """
    if not solution.has_values:
        raise SolverError(
            f"solver {solution.backend!r} found no pattern (status {solution.status.value})"
        )
    x = solution.block("yarn")
    r = solution.block("raised")
    yarn = np.argmax(x, axis=-1).astype(np.int16)
    ys = tuple(yarns) if yarns is not None else default_yarns(problem.n_yarns)
    if len(ys) < problem.n_yarns:
        raise YarnSpecError(f"`yarns` must list {problem.n_yarns} yarns, got {len(ys)}")
    info = {
        "source": "illuknit.solve",
        "model": problem.kind,
        "solver": solution.backend,
        "status": solution.status.value,
        "objective": solution.objective,
        "bound": solution.bound,
    }
    if meta:
        info.update(meta)
    return LogicalPattern(yarn, r, ys, info)


def color_changes_per_course(pattern_or_yarn: LogicalPattern | ArrayLike) -> NDArray[np.int64]:
    """ndarray of shape (N,): yarn changes between adjacent units along each unit row."""
    c = (
        pattern_or_yarn.yarn
        if isinstance(pattern_or_yarn, LogicalPattern)
        else np.asarray(pattern_or_yarn)
    )
    return (c[:, 1:] != c[:, :-1]).sum(axis=1).astype(np.int64)


def knit_purl_changes(raised: ArrayLike) -> int:
    """Knit<->purl bed changes between consecutive courses: 2 per bump, 1 per top-row bump."""
    r = np.asarray(raised, dtype=bool)
    return int(2 * r[1:].sum() + r[:1].sum())


def report_pattern(
    pattern: LogicalPattern, problem: IllusionProblem, solution: Solution | None = None
) -> dict[str, Any]:
    """JSON-ready report: logical error per view, colour changes per course, raised units,
    knit/purl changes, and (with ``solution``) the solver's status, objective, bound and time."""
    va = can_see(pattern, "A")
    vb = can_see(pattern, "B")
    cc = color_changes_per_course(pattern)
    rep: dict[str, Any] = {
        "model": problem.kind,
        "size": {"rows": pattern.shape[0], "cols": pattern.shape[1], "yarns": problem.n_yarns},
        "weights": {
            "view": problem.view_weight,
            "color_change": problem.color_weight,
            "transfer": problem.transfer_weight,
            "max_color_changes": problem.color_cap,
        },
        "logical_error": {
            "A": {
                "cells": int(logical_error(va, problem.target_a, normalize=False)),
                "fraction": logical_error(va, problem.target_a),
            },
            "B": {
                "cells": int(logical_error(vb, problem.target_b, normalize=False)),
                "fraction": logical_error(vb, problem.target_b),
            },
        },
        "color_changes_per_course": {
            "mean": float(cc.mean()),
            "max": int(cc.max()),
            "total": int(cc.sum()),
        },
        "raised_units": int(np.asarray(pattern.raised).sum()),
        "rows_with_bumps": int(np.asarray(pattern.raised).any(axis=1).sum()),
        "knit_purl_changes": knit_purl_changes(pattern.raised),
    }
    if solution is not None:
        rep["solver"] = solution.summary()
    return rep


#: Share of the time limit a warm-start descent may take before an exact backend (model (b)).
#: The descent stops by itself when it stalls (seconds on small models); at paper scale it
#: improves faster than CP-SAT does from its result, so it gets half.
WARM_START_SHARE = 0.5
#: Most seconds of warm-start descent (also without a time limit).
WARM_START_SECONDS = 60.0


def warm_start(
    problem: IllusionProblem,
    model: Model,
    *,
    time_limit: float | None = None,
    seed: int = 0,
) -> tuple[NDArray[np.bool_], dict[str, Any]]:
    """A warm start (``model.hint``) for a backend solving ``model``.

    The exact DP optimum where it applies (models (a), (c), and (b) without colour terms); for
    model (b) with colour-change terms and no cap, the block descent of
    :mod:`illuknit.solvers.descent` started from that DP optimum, given ``WARM_START_SHARE`` of
    ``time_limit`` (or ``WARM_START_SECONDS``); with a cap, the DP optimum of the per-wale part
    (which may break the cap; CP-SAT repairs hints).

    Returns
    -------
    values : ndarray of bool, indexed by variable id
    info : dict
        ``{"method", "objective", "seconds"}`` for the report, and for the descent ``"bound"``:
        the DP optimum of the per-wale part, a valid lower bound of model (b).
    """
    import time

    from illuknit.solvers.dp import hint_values, values_from_pattern

    t0 = time.perf_counter()
    extra: dict[str, Any] = {}
    if problem.per_wale or problem.rows_tied or problem.color_cap is not None:
        vals = hint_values(problem, model)
        method = "dp"
    else:
        from illuknit.solvers.descent import optimise_descent

        budget = (
            WARM_START_SECONDS
            if time_limit is None
            else min(WARM_START_SECONDS, WARM_START_SHARE * time_limit)
        )
        res = optimise_descent(problem, time_limit=budget, seed=seed)
        vals = values_from_pattern(model, res.yarn, res.raised)
        method = "descent"
        extra["bound"] = res.bound
    _, cost = model.evaluate(vals)
    return vals, {
        "method": method,
        "objective": int(cost),
        "seconds": round(time.perf_counter() - t0, 3),
        **extra,
    }


def keep_warm_start(model: Model, solution: Solution, info: Mapping[str, Any]) -> Solution:
    """``solution`` with the warm start's time added and, if the backend came back worse than
    its warm start (``model.hint``) or with nothing, the warm start's assignment instead; the
    bound is the better of the backend's and the warm start's (``info["bound"]``)."""
    from illuknit.solvers.base import Status

    values, objective, status = solution.values, solution.objective, solution.status
    stats = {**solution.stats, "warm_start": dict(info)}
    if model.hint is not None and status in (Status.FEASIBLE, Status.TIMEOUT):
        ok, cost = model.evaluate(model.hint)
        if ok and (objective is None or cost < objective):
            values, objective = np.asarray(model.hint, dtype=bool), cost
            stats["kept_warm_start"] = True
    bound = solution.bound
    if info.get("bound") is not None and status in (Status.FEASIBLE, Status.TIMEOUT):
        bound = max(float(info["bound"]), bound if bound is not None else float("-inf"))
        if objective is not None and objective <= bound:
            status = Status.OPTIMAL  # the warm start met a proven lower bound
    return replace(
        solution,
        status=status,
        values=values,
        objective=objective,
        bound=bound,
        wall_time=solution.wall_time + float(info.get("seconds", 0.0)),
        stats=stats,
    )


@dataclass(frozen=True, eq=False)
class IllusionResult:
    """What :func:`solve_illusion` returns."""

    pattern: LogicalPattern | None
    solution: Solution
    problem: IllusionProblem
    report: Mapping[str, Any]


def solve_illusion(
    target_a: ArrayLike,
    target_b: ArrayLike | None = None,
    *,
    model: str = "logical",
    solver: str = "auto",
    weights: KnitWeights | None = None,
    yarns: Sequence[Yarn] | None = None,
    n_yarns: int | None = None,
    pinned: ArrayLike | None = None,
    alternate_rows: bool = False,
    time_limit: float | None = None,
    seed: int = 0,
    hint: bool = True,
    progress: ProgressCallback | None = None,
) -> IllusionResult:
    """Build the illusion model, solve it, and decode the pattern with its report.

    Parameters
    ----------
    target_a, target_b : ndarray of shape (N, M), int
        Yarn-index targets (``target_b`` omitted for the single-view model).
    model : {"logical", "knit-aware", "single"}
    solver : str
        A backend name (see :func:`illuknit.solvers.available_backends`) or "auto" (the first
        in preference order that handles the model: the exact DP when it applies).
    alternate_rows : bool
        Single-view model: neighbouring rows must have different yarns.
    hint : bool
        Warm-start other backends (:func:`warm_start`: the DP optimum, or for the knit-aware
        model a block descent, which takes part of ``time_limit``). The result is never worse
        than the warm start, and its ``wall_time`` includes it.

    Raises
    ------
    InfeasibleError
        The hard constraints cannot hold; the message names the constraint families.
    """
    from illuknit.solvers import solve

    if model not in MODEL_KINDS:
        raise UnknownNameError("model", model, MODEL_KINDS)
    if n_yarns is None and yarns is not None:
        n_yarns = len(yarns)
    prob = make_problem(
        target_a,
        target_b if model != "single" else None,
        n_yarns=n_yarns,
        kind=model,
        weights=weights,
        pinned=pinned,
        alternate_rows=alternate_rows,
    )
    if yarns is not None and len(yarns) < prob.n_yarns:
        raise YarnSpecError(f"`yarns` must list {prob.n_yarns} yarns, got {len(yarns)}")
    mdl = build_model(prob)
    ws: dict[str, Any] | None = None
    remaining = time_limit
    if hint and solver not in ("dp", "descent"):
        mdl.hint, ws = warm_start(prob, mdl, time_limit=time_limit, seed=seed)
        if time_limit is not None:
            remaining = max(0.1 * time_limit, time_limit - ws["seconds"])
    sol = solve(mdl, solver=solver, time_limit=remaining, seed=seed, progress=progress)
    if ws is not None:
        sol = keep_warm_start(mdl, sol, ws)
    if sol.status.value == "infeasible":
        fams = list(sol.stats.get("infeasible_families", [])) or ["(unknown)"]
        raise InfeasibleError(
            f"the hard constraints cannot all hold (model {model!r}); conflicting constraint "
            f"families: {', '.join(fams)}"
        )
    if not sol.has_values:
        msg = sol.stats.get("message", "")
        raise SolverError(
            f"solver {sol.backend!r} found no pattern (status {sol.status.value})"
            + (f": {msg}" if msg else "")
        )
    pat = pattern_from_solution(prob, sol, yarns=yarns)
    return IllusionResult(pat, sol, prob, report_pattern(pat, prob, sol))
