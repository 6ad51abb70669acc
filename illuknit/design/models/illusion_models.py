"""Constraint models of illusion patterns (paper sections 4.2 and 8.3), and their solutions.

Three *illusion models* over an N x M grid of units and K yarns -- (a) ``logical``, (b)
``knit-aware``, (c) ``single``, the ``kind`` of an :class:`~illuknit.design.models.illusion_problem.IllusionProblem`
-- each encoded here into one solver-neutral *constraint model* (:class:`illuknit.solvers.model.Model`):

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
follows. And ``weights.machine_pass`` per machine carriage pass the pattern forces as the
mixed-colourwork scheduler knits it (:func:`~illuknit.design.models.illusion_problem.row_passes`): per unit row
of ``S`` *segments* (each yarn used, plus an *extra carrier* for a region more than
``weights.float_gap`` units after its yarn's previous region in the row, beyond a float's reach),
``2 S`` passes, and ``S + 1`` more for a row with a bump (its transfer passes in and out, and
one float-avoidance transfer pass per segment beyond the first) -- see :func:`_add_pass_terms`.

**Split bumps** (``problem.split_bumps``, model (a) only; :mod:`illuknit.core.views`): a block
``("upper", i, j, k)`` -- the yarn of unit (i, j)'s second course, one-hot -- with the hard
*flat units keep one yarn*: ``R[i,j] | ~yarn[i,j,k] | upper[i,j,k]`` (and the converse), and view
A's soft clauses read ``upper`` where view B's read ``yarn``: view A sees ``U[i-1] if R[i-1] else
U[i]``, and ``U == C`` wherever the unit is flat.

Models (a) and (b) without colour-change or pass terms couple only neighbouring units of one wale, so
:mod:`illuknit.design.models.backends.dp` solves them exactly per wale; model (c) ties each row to one yarn, and
the DP solves it exactly over the row colours (a raised bit then affects two view cells whose
colours depend only on three consecutive row colours). The structured :class:`IllusionProblem`
rides along as ``model.problem`` for it. Model (b) with colour-change terms couples the wales;
:mod:`illuknit.design.models.backends.descent` re-optimises single wales and courses exactly in turn and warm-
starts the exact backends.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.arguments import (
    check_array,
    check_bool,
    check_instance,
    check_int,
    check_number,
    check_str,
)
from illuknit.core.errors import (
    InfeasibleError,
    OptionError,
    SolverError,
    UnknownNameError,
    YarnSpecError,
)
from illuknit.core.pattern import Yarn, check_yarns
from illuknit.design.models.illusion_problem import (
    MODEL_KINDS,
    IllusionProblem,
    KnitWeights,
    make_problem,
    parse_weights,
    raised_cost,
)
from illuknit.design.models.illusion_report import (
    IllusionResult,
    color_changes_per_course,
    default_yarns,
    knit_purl_changes,
    pattern_from_solution,
    report_pattern,
)
from illuknit.design.options import SolveOptions
from illuknit.solvers import solve
from illuknit.solvers.base import ProgressCallback, Solution
from illuknit.solvers.model import Model

__all__ = [
    "MODEL_KINDS",
    "IllusionProblem",
    "IllusionResult",
    "KnitWeights",
    "build_model",
    "check_solution",
    "color_changes_per_course",
    "default_yarns",
    "knit_purl_changes",
    "make_problem",
    "parse_weights",
    "pattern_from_solution",
    "report_pattern",
    "solve_illusion",
]


def build_model(problem: IllusionProblem) -> Model:
    """Encode ``problem`` as a :class:`Model` (vectorised; see the module docstring).

    Returns
    -------
    Model
        With variable blocks ``"yarn"`` (N, M, K), ``"raised"`` (N, M), with split bumps
        ``"upper"`` (N, M, K), and, when knit-aware with colour terms, ``"change"`` (N, M-1);
        ``model.problem`` is ``problem``.
    """
    check_instance(problem, IllusionProblem, "problem")
    n, m = problem.shape
    k = problem.n_yarns
    wv = problem.view_weight
    hands = "-hands" if problem.for_hands else ""
    model = Model(f"illusion-{problem.kind}{hands}-{n}x{m}-k{k}", problem=problem)
    x = model.pool.block("yarn", (n, m, k))
    r = model.pool.block("raised", (n, m))
    # view A reads the second course's yarn: the same variables unless bumps may be split
    xa = model.pool.block("upper", (n, m, k)) if problem.split_bumps else x

    # one yarn per unit: at least one (width K) + pairwise at most one
    model.add_hard_block(x.reshape(-1, k), family="one yarn per unit")
    for a in range(k):
        for b in range(a + 1, k):
            model.add_hard_block(
                np.stack([-x[..., a].ravel(), -x[..., b].ravel()], axis=1),
                family="one yarn per unit",
            )
    if problem.split_bumps:
        _add_split_terms(model, x, xa, r)
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
    # view A, row 0 sees U[0] (the yarn C[0] without split bumps)
    soft.append(np.stack([xa[0, cols[0], ta[0]], np.zeros(m, np.int64)], axis=1))
    if n > 1:
        rows = np.arange(1, n)[:, None]
        # R[i-1] -> U[i-1] == A[i]     and    ~R[i-1] -> U[i] == A[i]
        soft.append(
            np.stack([-r[rows - 1, cols], xa[rows - 1, cols, ta[1:]]], axis=-1).reshape(-1, 2)
        )
        soft.append(np.stack([r[rows - 1, cols], xa[rows, cols, ta[1:]]], axis=-1).reshape(-1, 2))
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
        model.add_soft_block(-r.reshape(-1, 1), raised_cost(n, m, wt).ravel())

    wc = problem.color_weight
    cap = problem.color_cap
    if (wc or cap is not None or problem.for_hands) and m > 1:
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
        if problem.for_hands:
            _add_hand_rows(model, x, d)
    if problem.pass_weight:
        _add_pass_terms(model, problem, x, r)
    return model


def _add_hand_rows(model: Model, x: NDArray[np.int64], d: NDArray[np.int64]) -> None:
    """Every row knittable by hand (``problem.for_hands``): per unit row a variable
    ``("stranded", i)`` chooses how it is worked (:class:`~illuknit.design.hand_cost.HandRow`).

    * *intarsia* (``~stranded``): at most ``MAX_HAND_BLOCKS - 1`` colour changes, the linear
      ``sum(change[i]) + slack * ~stranded[i] <= M - 1``;
    * *stranded*: at most ``MAX_HAND_YARNS`` yarns (``yarn[i, j, c] -> used[i, c]``, then a
      linear bound), and no float longer than ``MAX_FLOAT`` stitches: with ``after[i, j, c]``
      "yarn c is used at unit j or right of it" (``yarn -> after``, ``after[j + 1] ->
      after[j]``), yarn c at unit j and again at ``j + g + 1`` or beyond must appear in units
      ``j + 1 .. j + g`` between (``g = MAX_FLOAT // 2 + 1`` units, 2 stitches a unit, is the
      shortest gap too long to float).

    A unit row is two hand rows of the same yarns (no split bumps), so the two agree.
    """
    from illuknit.design.hand_cost import MAX_FLOAT, MAX_HAND_BLOCKS, MAX_HAND_YARNS

    n, m, k = x.shape
    s = model.pool.block("stranded", (n,))
    max_changes = MAX_HAND_BLOCKS - 1
    if m - 1 > max_changes:
        slack = m - 1 - max_changes
        for i in range(n):
            model.add_linear_le(
                [*d[i].tolist(), -int(s[i])],
                [1] * (m - 1) + [slack],
                m - 1,
                family="hand rows: intarsia blocks",
            )
    if k > MAX_HAND_YARNS:
        used = model.pool.block("row yarn", (n, k))
        model.add_hard_block(
            np.stack([-x, np.broadcast_to(used[:, None, :], x.shape)], axis=-1).reshape(-1, 2),
            family="hand rows: yarns a row",
        )
        for i in range(n):
            model.add_linear_le(
                [*used[i].tolist(), int(s[i])],
                [1] * k + [k - MAX_HAND_YARNS],
                k,
                family="hand rows: stranded yarns",
            )
    g = MAX_FLOAT // 2 + 1
    if m < g + 2:
        return  # no gap this long fits between two units of a row
    after = model.pool.block("yarn after", (n, m, k))
    model.add_hard_block(
        np.stack([-x, after], axis=-1).reshape(-1, 2), family="hand rows: yarn after"
    )
    model.add_hard_block(
        np.stack([-after[:, 1:, :], after[:, :-1, :]], axis=-1).reshape(-1, 2),
        family="hand rows: yarn after",
    )
    j = np.arange(m - g - 1)
    lits = [
        np.broadcast_to(-s[:, None, None], (n, j.size, k)),
        -x[:, j, :],
        -after[:, j + g + 1, :],
        *(x[:, j + t, :] for t in range(1, g + 1)),
    ]
    model.add_hard_block(
        np.stack(lits, axis=-1).reshape(-1, g + 3), family="hand rows: stranded floats"
    )


def _add_split_terms(
    model: Model, x: NDArray[np.int64], u: NDArray[np.int64], r: NDArray[np.int64]
) -> None:
    """The ``upper`` block of split bumps: one-hot, and equal to ``yarn`` on flat units.

    ``R | ~yarn[k] | upper[k]`` for every k makes a flat unit's second course take its yarn;
    with both one-hot that is equality (the converse clauses make it explicit for propagation).
    """
    k = x.shape[2]
    model.add_hard_block(u.reshape(-1, k), family="one yarn per second course")
    for a in range(k):
        for b in range(a + 1, k):
            model.add_hard_block(
                np.stack([-u[..., a].ravel(), -u[..., b].ravel()], axis=1),
                family="one yarn per second course",
            )
    rr = np.broadcast_to(r[:, :, None], x.shape)
    model.add_hard_block(
        np.stack([rr, -x, u], axis=-1).reshape(-1, 3), family="flat units keep one yarn"
    )
    model.add_hard_block(
        np.stack([rr, x, -u], axis=-1).reshape(-1, 3), family="flat units keep one yarn"
    )


def _add_pass_terms(
    model: Model, problem: IllusionProblem, x: NDArray[np.int64], r: NDArray[np.int64]
) -> None:
    """The machine-pass terms of model (b): :func:`~illuknit.design.models.illusion_problem.row_passes` passes
    per unit row, ``p = weights.machine_pass`` each:

    * ``("yarn used", i, k)``: ``yarn[i,j,k] -> used[i,k]``, soft ``~used`` (2p) -- a carrier
      knits the row's two courses;
    * ``("yarn so far", i, j, k)``: some unit at columns <= j of row i is in yarn k
      (``yarn -> so_far``, ``so_far[j-1] -> so_far[j]``), and ``("extra carrier", i, j, k)``:
      ``yarn[i,j,k] & ~yarn[i,j-1..j-g-1,k] & so_far[i,j-g-2,k] -> extra[i,j,k]``, soft
      ``~extra`` (2p) -- a region more than ``g = float_gap`` units after the yarn's previous
      one (the scheduler's carriers float across ``2 g`` stitches, ``g`` units, at most);
    * ``("bump row", i)``: ``raised[i,j] -> bump_row[i]``, soft ``~bump_row`` (p) -- the bed
      changes around a purl course, and ``("bump segment", i, k)`` / ``("bump extra", i, j, k)``:
      ``bump_row[i] & used[i,k]`` / ``bump_row[i] & extra[i,j,k]`` imply them, soft (p each) --
      a float-avoidance transfer pass per segment of a bump row (the ``+ 1`` of ``S + 1`` is the
      bump row's own ``p`` taking the place of one of them).
    """
    n, m, k = x.shape
    p = problem.pass_weight
    used = model.pool.block("yarn used", (n, k))
    model.add_hard_block(
        np.stack([-x, np.broadcast_to(used[:, None, :], x.shape)], axis=-1).reshape(-1, 2),
        family="yarn used in a row",
    )
    model.add_soft_block(-used.reshape(-1, 1), 2 * p)
    bump_row = model.pool.block("bump row", (n,))
    model.add_hard_block(
        np.stack([-r, np.broadcast_to(bump_row[:, None], r.shape)], axis=-1).reshape(-1, 2),
        family="bump in a row",
    )
    model.add_soft_block(-bump_row.reshape(-1, 1), p)
    bump_used = model.pool.block("bump segment", (n, k))
    model.add_hard_block(
        np.stack(
            [-np.broadcast_to(bump_row[:, None], used.shape), -used, bump_used], axis=-1
        ).reshape(-1, 3),
        family="segment of a bump row",
    )
    model.add_soft_block(-bump_used.reshape(-1, 1), p)
    g = problem.weights.float_gap
    if m <= g + 2:
        return
    so_far = model.pool.block("yarn so far", (n, m, k))
    model.add_hard_block(np.stack([-x, so_far], axis=-1).reshape(-1, 2), family="yarn so far")
    model.add_hard_block(
        np.stack([-so_far[:, :-1], so_far[:, 1:]], axis=-1).reshape(-1, 2), family="yarn so far"
    )
    extra = model.pool.block("extra carrier", (n, m - g - 2, k))
    cols = np.arange(g + 2, m)
    lits = [-x[:, cols]] + [x[:, cols - d] for d in range(1, g + 2)]
    lits += [-so_far[:, cols - g - 2], extra]
    model.add_hard_block(np.stack(lits, axis=-1).reshape(-1, g + 4), family="extra carrier")
    model.add_soft_block(-extra.reshape(-1, 1), 2 * p)
    bump_extra = model.pool.block("bump extra", extra.shape)
    model.add_hard_block(
        np.stack(
            [-np.broadcast_to(bump_row[:, None, None], extra.shape), -extra, bump_extra], axis=-1
        ).reshape(-1, 3),
        family="segment of a bump row",
    )
    model.add_soft_block(-bump_extra.reshape(-1, 1), p)


#: The keywords of :func:`solve_illusion` that :class:`~illuknit.design.options.SolveOptions`
#: groups, and their defaults here (no time limit, unlike the CLI's options).
_SOLVE_KNOBS: dict[str, Any] = {
    "model": "logical",
    "solver": "auto",
    "warm_start": "auto",
    "weights": None,
    "alternate_rows": False,
    "split_bumps": False,
    "for_hands": False,
    "time_limit": None,
    "seed": 0,
}


def solve_illusion(
    target_a: ArrayLike,
    target_b: ArrayLike | None = None,
    *,
    options: SolveOptions | None = None,
    yarns: Sequence[Yarn] | None = None,
    n_yarns: int | None = None,
    pinned: ArrayLike | None = None,
    progress: ProgressCallback | None = None,
    **knobs: Any,
) -> IllusionResult:
    """Build the illusion model, solve it (:func:`illuknit.solvers.solve`), decode the pattern.

    How to solve is ``options`` (a :class:`~illuknit.design.options.SolveOptions`), or its
    fields given as keywords (``model="knit-aware", time_limit=10``; the parameters below list
    them with their defaults), which take the place of the fields of ``options``.

    Parameters
    ----------
    target_a, target_b : ndarray of shape (N, M), int
        Yarn-index targets (``target_b`` omitted for the single-view model).
    options : SolveOptions, optional
        Everything below but the yarns, the pins and ``progress``.
    model : {"logical", "knit-aware", "single"}
    solver : str
        A backend name (see :func:`illuknit.solvers.available_backends`) or "auto" (the first
        in preference order that handles the model: the exact DP when it applies).
    warm_start : {"auto", "none", "dp", "descent"}
        Warm-start policy (:mod:`illuknit.design.models.backends.warm_start`): the DP optimum, or for the
        knit-aware model a block descent taking part of ``time_limit``. The result is never worse
        than the warm start, its ``found_by`` says who found it, and its ``wall_time``
        includes the warm start.
    alternate_rows : bool
        Single-view model: neighbouring rows must have different yarns.
    split_bumps : bool
        Logical model: bumps may knit their second course in another yarn
        (``docs/split-bumps.md``); the pattern then has ``upper``.
    for_hands : bool
        Logical and knit-aware models: every row knittable by hand
        (:attr:`~illuknit.design.models.illusion_problem.IllusionProblem.for_hands`; from
        ``options.made_for``); solved by the MaxSAT/CP backends from the ``hand`` warm start.

    Raises
    ------
    InfeasibleError
        The hard constraints cannot hold; the message names the constraint families.
    SolverError
        The backend found no pattern.
    """
    knobs = _solve_knobs(options, knobs)
    model, solver, warm_start = knobs["model"], knobs["solver"], knobs["warm_start"]
    weights, time_limit, seed = knobs["weights"], knobs["time_limit"], knobs["seed"]
    alternate_rows, split_bumps = knobs["alternate_rows"], knobs["split_bumps"]
    for_hands = knobs["for_hands"]
    _check_solve_arguments((target_a, target_b, pinned), knobs, yarns, n_yarns)
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
        split_bumps=split_bumps,
    )
    if for_hands:
        prob = replace(prob, for_hands=True)
    if yarns is not None and len(yarns) < prob.n_yarns:
        raise YarnSpecError(f"`yarns` must list {prob.n_yarns} yarns, got {len(yarns)}")
    mdl = build_model(prob)
    sol = solve(
        mdl,
        solver=solver,
        warm_start=warm_start,
        time_limit=time_limit,
        seed=seed,
        progress=progress,
    )
    check_solution(sol, model)
    pat = pattern_from_solution(prob, sol, yarns=yarns)
    return IllusionResult(pat, sol, prob, report_pattern(pat, prob, sol))


def _check_solve_arguments(
    arrays: tuple[ArrayLike, ArrayLike | None, ArrayLike | None],
    knobs: dict[str, Any],
    yarns: Sequence[Yarn] | None,
    n_yarns: int | None,
) -> None:
    """:func:`solve_illusion`'s arguments checked: the targets and pins, every knob, the yarns."""
    target_a, target_b, pinned = arrays
    check_array(target_a, "target_a", ndim=2, integer=True)
    if target_b is not None:
        check_array(target_b, "target_b", ndim=2, integer=True)
    for name in ("model", "solver", "warm_start"):
        check_str(knobs[name], name)
    if knobs["weights"] is not None:
        check_instance(knobs["weights"], KnitWeights, "weights")
    if yarns is not None:
        check_yarns(yarns)
    if n_yarns is not None:
        check_int(n_yarns, "n_yarns", min=1)
    if pinned is not None:
        check_array(pinned, "pinned", ndim=2, integer=True)
    for name in ("alternate_rows", "split_bumps", "for_hands"):
        check_bool(knobs[name], name)
    if knobs["time_limit"] is not None:
        check_number(knobs["time_limit"], "time_limit", min=0, min_open=True)
    check_int(knobs["seed"], "seed", min=0)
    if knobs["model"] not in MODEL_KINDS:
        raise UnknownNameError("model", knobs["model"], MODEL_KINDS)


def _solve_knobs(options: SolveOptions | None, knobs: dict[str, Any]) -> dict[str, Any]:
    """Every keyword of :data:`_SOLVE_KNOBS`: from ``knobs``, else ``options``, else the default."""
    unknown = sorted(set(knobs) - set(_SOLVE_KNOBS))
    if unknown:
        valid = ", ".join(_SOLVE_KNOBS)
        raise OptionError(f"unknown solve option {unknown[0]!r}; valid: {valid}")
    if options is None:
        return {**_SOLVE_KNOBS, **knobs}
    check_instance(options, SolveOptions, "options")
    given = {
        "model": options.model.value,
        "solver": options.solver,
        "warm_start": options.warm_start.value,
        "weights": options.weights,
        "alternate_rows": options.alternate_rows,
        "split_bumps": options.split_bumps,
        "for_hands": options.for_hands,
        "time_limit": options.time_limit,
        "seed": options.seed,
    }
    return {**given, **knobs}


def check_solution(sol: Solution, model: str) -> None:
    """Raise the error that says why ``sol`` holds no pattern (no-op when it holds one).

    Raises
    ------
    InfeasibleError
        The hard constraints cannot hold; the message names the conflicting families.
    SolverError
        The backend found no pattern (timeout, error).
    """
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
