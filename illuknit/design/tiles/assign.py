"""Tile assignment: repaint each input colour with a fill the tile bank can realise (section 6.2).

:func:`assign_tiles` builds the model of :mod:`illuknit.design.tiles.assign_model` (its variables,
constraints and objective are described there), solves it with any backend (CP-SAT by default,
MaxSAT ``rc2`` selectable) for the top-N distinct candidates -- after each optimum a blocking
clause forbids exactly that choice of fills -- aligns stripe phases
(:mod:`illuknit.design.tiles.phases`) and, when nothing fits, explains why
(:mod:`illuknit.design.tiles.explain`). :func:`brute_force_assignments` enumerates every choice for the
tests. The IR lives in :mod:`illuknit.design.tiles.assignment` and is re-exported here.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any, Literal

import numpy as np

from illuknit.core.arguments import (
    MAX_SECONDS,
    check_bool,
    check_instance,
    check_int,
    check_number,
    check_seconds,
    check_str,
    check_views,
    with_knobs,
)
from illuknit.core.errors import ImageInputError, TileAssignmentError, TileBankError
from illuknit.core.pattern import Yarn, check_yarns
from illuknit.design.tiles.assign_model import (
    _build_problem,
    _cost,
    _encode,
    _make_assignment,
    _Problem,
)
from illuknit.design.tiles.assignment import (
    SCALE,
    AssignmentWeights,
    Regions,
    TileAssignment,
    overlap_pairs,
    regions_of,
)
from illuknit.design.tiles.bank import TileBank, ViewPair, canonical_bank
from illuknit.design.tiles.explain import explain_infeasible
from illuknit.design.tiles.phases import align_phases
from illuknit.design.tiles.tile import Fill

__all__ = [
    "AssignOptions",
    "AssignmentWeights",
    "TileAssignment",
    "align_phases",
    "assign_tiles",
    "brute_force_assignments",
    "explain_infeasible",
    "overlap_pairs",
    "regions_of",
    "with_candidates",
]


#: The most assignments one search keeps or looks for.
MAX_ASSIGNMENTS = 1000


def _check_inputs(ra: Regions, rb: Regions, bank: TileBank, views: ViewPair) -> None:
    if ra.indices.shape != rb.indices.shape:
        raise ImageInputError(
            f"the two inputs must have the same size in units, got {ra.indices.shape[1]} x {ra.indices.shape[0]} "
            f"and {rb.indices.shape[1]} x {rb.indices.shape[0]} (resize one, or use --resize)"
        )
    for name, r, view in (("A", ra, views[0]), ("B", rb, views[1])):
        used = np.unique(r.indices)
        levels = {round(f.brightness, 9) for f in bank.view_fills(view, views=views)}
        if len(used) > len(levels):
            raise TileAssignmentError(
                f"input {name} has {len(used)} colours, but the tile bank shows only {len(levels)} "
                f"distinct brightness level(s) from view {view}: use fewer colours (--colors) or more yarns"
            )


@dataclass(frozen=True)
class AssignOptions:
    """How :func:`assign_tiles` searches: how many assignments, with which backend, how long.

    Parameters
    ----------
    candidates : int
        How many distinct assignments to return (fewer when fewer exist; 1 to 1000).
    pool : int, optional
        Search on past ``candidates`` for up to this many, to rank them by something the score
        does not see (:func:`illuknit.design.tiles.perception.rank_designs` ``keep=candidates``).
    pool_seconds : float, optional
        The assignments past ``candidates`` are sought only while the whole search has taken
        less than this many seconds (each solve may take up to ``time_limit``).
    brightness : {"hard", "soft"}
        Keep each input's brightness order strictly, or only prefer to.
    solver : str
        A backend name of :mod:`illuknit.solvers` ("cpsat", "rc2", ...).
    time_limit : float, optional
        Seconds per solve.

    The design stages' :class:`~illuknit.design.options.SearchOptions` give theirs as
    ``AssignOptions(**search.assign_kwargs())``.
    """

    candidates: int = 5
    pool: int | None = None
    pool_seconds: float | None = None
    brightness: Literal["hard", "soft"] = "hard"
    solver: str = "cpsat"
    time_limit: float | None = 10.0

    def __post_init__(self) -> None:
        err = TileAssignmentError
        check_int(self.candidates, "candidates", min=1, max=MAX_ASSIGNMENTS, error=err)
        if self.pool is not None:
            check_int(self.pool, "pool", min=1, max=MAX_ASSIGNMENTS, error=err)
        if self.pool_seconds is not None:
            check_number(self.pool_seconds, "pool_seconds", min=0, max=MAX_SECONDS, error=err)
        check_str(self.brightness, "brightness")
        check_str(self.solver, "solver")
        check_seconds(self.time_limit, "time_limit")
        if self.brightness not in ("hard", "soft"):
            raise err(f"`brightness` must be 'hard' or 'soft', got {self.brightness!r}")


def assign_tiles(
    qa: Any,
    qb: Any,
    *,
    bank: TileBank | None = None,
    yarns: Sequence[Yarn] | None = None,
    options: AssignOptions | None = None,
    weights: AssignmentWeights | None = None,
    views: ViewPair = ("A", "B"),
    explain: bool = True,
    **knobs: Any,
) -> list[TileAssignment]:
    """The top ``candidates`` (up to ``pool``) tile assignments for a pair of quantised inputs,
    best score first.

    Parameters
    ----------
    qa, qb : QuantisedImage or (indices (N, M), colors (K, 3))
        The inputs seen from ``views[0]`` and ``views[1]`` (A from above, B from below).
    bank : TileBank, optional
        Defaults to :func:`canonical_bank` of ``yarns`` (or of ``qa.yarns`` + ``qb.yarns``).
    options : AssignOptions, optional
        How to search (``candidates``, ``pool``, ``pool_seconds``, ``brightness``, ``solver``,
        ``time_limit``; defaults: ``AssignOptions()``).
    weights : AssignmentWeights, optional
    views : pair of str
        ``("A", "B")`` for double view; ``("headon", "side")`` for the head-on variant.
    explain : bool
        When nothing fits, say which overlap pairs cannot be realised (one more solve each).
    **knobs
        Shorthand for fields of ``options`` (``assign_tiles(qa, qb, candidates=3)`` is
        ``assign_tiles(qa, qb, options=AssignOptions(candidates=3))``); they replace those
        fields of ``options`` when both are given.

    Returns
    -------
    list of TileAssignment
        Ranked by score (rank 1 first).

    Raises
    ------
    ImageInputError
        The inputs have different sizes.
    TileAssignmentError
        An input has more colours than the bank can serve, or no assignment exists (the message
        explains which overlap pairs cannot be realised and what would fix it).
    """
    if bank is not None:
        check_instance(bank, TileBank, "bank", error=TileBankError)
    if yarns is not None:
        check_yarns(yarns)
    opts = with_knobs(AssignOptions, options, knobs, what="assignment")
    if weights is not None:
        check_instance(weights, AssignmentWeights, "weights")
    check_views(views)
    check_bool(explain, "explain")
    ra, rb = regions_of(qa, name="qa"), regions_of(qb, name="qb")
    if bank is None:
        bank = canonical_bank(_default_yarns(qa, qb, yarns), views=views)
    _check_inputs(ra, rb, bank, views)
    prob = _build_problem(ra, rb, bank, views, opts.brightness, weights or AssignmentWeights())
    return _solve_candidates(
        prob,
        opts.candidates,
        opts.solver,
        opts.time_limit,
        explain=explain,
        pool=max(opts.candidates, opts.pool or 0),
        pool_seconds=opts.pool_seconds,
    )


def with_candidates(
    found: Sequence[TileAssignment], more: Sequence[TileAssignment]
) -> list[TileAssignment]:
    """The assignments of the ordinary search, then those another search (another bank: the
    shared stripes, :mod:`illuknit.design.tiles.stripes`) found that it did not (the same fills
    of one bank once), ranked on: a design made for hands is chosen from both, never from fewer
    than a machine design is."""
    seen = {(a.bank.name, a.fills_a, a.fills_b) for a in found}
    new = [a for a in more if (a.bank.name, a.fills_a, a.fills_b) not in seen]
    return [*found, *(replace(a, rank=len(found) + k + 1) for k, a in enumerate(new))]


def _yarns_of(*inputs: Any) -> tuple[Yarn, ...]:
    """The yarns the inputs carry (``.yarns`` of a QuantisedImage), each colour once, in order."""
    found: list[Yarn] = []
    for q in inputs:
        for y in getattr(q, "yarns", ()):
            if all(y.rgb != z.rgb for z in found):
                found.append(y)
    return tuple(found)


def _default_yarns(qa: Any, qb: Any, yarns: Sequence[Yarn] | None) -> tuple[Yarn, ...]:
    if yarns is not None:
        return tuple(yarns)
    found = _yarns_of(qa, qb)
    if not found:
        raise TileAssignmentError("pass `bank` or `yarns` (the inputs carry no yarns)")
    return found


def _solve_candidates(
    prob: _Problem,
    candidates: int,
    solver: str,
    time_limit: float | None,
    *,
    explain: bool,
    pool: int = 0,
    pool_seconds: float | None = None,
) -> list[TileAssignment]:
    import time

    from illuknit.solvers import Status, solve

    out: list[TileAssignment] = []
    blocked: list[tuple[dict[int, int], dict[int, int]]] = []
    m, decode, block = _encode(prob)
    start = time.perf_counter()
    for rank in range(1, max(candidates, pool) + 1):
        if (
            rank > candidates
            and pool_seconds is not None
            and time.perf_counter() - start >= pool_seconds
        ):
            break
        if blocked:
            block(*blocked[-1])
        sol = solve(m, solver=solver, time_limit=time_limit)
        if sol.status is Status.INFEASIBLE or not sol.has_values:
            break
        if sol.status is Status.ERROR:  # pragma: no cover - backend failure
            from illuknit.core.errors import SolverError

            raise SolverError(f"solver {solver!r} failed: {sol.stats.get('message', '')}")
        ca, cb = decode(sol)
        blocked.append((ca, cb))
        out.append(_make_assignment(prob, ca, cb, rank, sol.backend or solver))
    if not out:
        msg = "no tile assignment exists for these inputs"
        if explain:
            msg = explain_infeasible(prob, solver=solver)
        raise TileAssignmentError(msg)
    # Solves are exact, but a timed-out solve may come back out of order: rank by score.
    out.sort(key=lambda t: t.score)
    return [replace(t, rank=k + 1) for k, t in enumerate(out)]


# -- brute force (tests, tiny problems) --------------------------------------------------------


def brute_force_assignments(
    qa: Any,
    qb: Any,
    *,
    bank: TileBank,
    brightness: Literal["hard", "soft"] = "hard",
    weights: AssignmentWeights | None = None,
    views: ViewPair = ("A", "B"),
) -> list[tuple[float, tuple[Fill | None, ...], tuple[Fill | None, ...]]]:
    """Every feasible choice of fills with its score, best first, by plain enumeration.

    Exponential: for checking the model on a handful of colours and fills only.
    """
    ra, rb = regions_of(qa, name="qa"), regions_of(qb, name="qb")
    prob = _build_problem(ra, rb, bank, views, brightness, weights or AssignmentWeights())
    out = []
    for choice_a in itertools.product(range(len(prob.fa)), repeat=len(prob.cols_a)):
        ca = dict(zip(prob.cols_a, choice_a, strict=True))
        for choice_b in itertools.product(range(len(prob.fb)), repeat=len(prob.cols_b)):
            cb = dict(zip(prob.cols_b, choice_b, strict=True))
            parts = _cost(prob, ca, cb)
            if parts is None:
                continue
            fa = tuple(prob.fa[ca[a]] if a in ca else None for a in range(len(ra.colors)))
            fb = tuple(prob.fb[cb[b]] if b in cb else None for b in range(len(rb.colors)))
            out.append((sum(parts.values()) / SCALE, fa, fb))
    out.sort(key=lambda t: t[0])
    return out
