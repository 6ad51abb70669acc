"""Decoding and reporting illusion-model solutions: the pattern of an assignment and its report
(logical error per view, colour changes per course, bumps, knit/purl changes)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from illuknit.core.arguments import check_instance, check_mapping
from illuknit.core.errors import SolverError, YarnSpecError
from illuknit.core.pattern import LogicalPattern, Yarn, check_pattern, check_yarns
from illuknit.core.views import can_see, logical_error
from illuknit.design.models.illusion_problem import IllusionProblem, pass_events, row_passes
from illuknit.solvers.base import Solution

__all__ = [
    "IllusionResult",
    "color_changes_per_course",
    "default_yarns",
    "knit_purl_changes",
    "pattern_from_solution",
    "report_pattern",
]


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
    check_instance(problem, IllusionProblem, "problem")
    check_instance(solution, Solution, "solution")
    if yarns is not None:
        check_yarns(yarns)
    if meta is not None:
        check_mapping(meta, "meta")
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
    upper = None
    if problem.split_bumps:
        upper = np.argmax(solution.block("upper"), axis=-1).astype(np.int16)
        info["split_bumps"] = True
    return LogicalPattern(yarn, r, ys, info, upper=upper)


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


def _pass_report(pattern: LogicalPattern, problem: IllusionProblem) -> dict[str, Any]:
    """What the knit-aware model's pass terms count for ``pattern`` (:func:`row_passes`)."""
    used, bump_rows, extra = pass_events(
        pattern.yarn, pattern.raised, problem.n_yarns, problem.weights.float_gap
    )
    return {
        "yarns_per_course": {"mean": float(used.mean()), "total": int(used.sum())},
        "bump_rows": int(bump_rows.sum()),
        "extra_carriers": int(extra.sum()),
        "passes": int(
            row_passes(
                pattern.yarn, pattern.raised, problem.n_yarns, problem.weights.float_gap
            ).sum()
        ),
    }


def report_pattern(
    pattern: LogicalPattern, problem: IllusionProblem, solution: Solution | None = None
) -> dict[str, Any]:
    """JSON-ready report: logical error per view, colour changes per course, raised units,
    knit/purl changes, and (with ``solution``) the solver's status, objective, bound and time."""
    check_pattern(pattern)
    check_instance(problem, IllusionProblem, "problem")
    if solution is not None:
        check_instance(solution, Solution, "solution")
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
            "machine_pass": problem.pass_weight,
            "float_gap": problem.weights.float_gap,
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
        "machine_pass_events": _pass_report(pattern, problem),
    }
    if problem.for_hands:  # what the hand knitter's row rule bought, measured on the pattern
        from illuknit.design.hand_cost import hand_cost

        rep["made_for"] = "hands"
        rep["hand"] = hand_cost(pattern).to_json()
    if solution is not None:
        rep["solver"] = solution.summary()
    return rep


@dataclass(frozen=True, eq=False)
class IllusionResult:
    """What :func:`solve_illusion` returns."""

    pattern: LogicalPattern | None
    solution: Solution
    problem: IllusionProblem
    report: Mapping[str, Any]
