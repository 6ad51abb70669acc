"""Candidates: the ranked designs the designer picks from.

Prepared -> make_candidates -> [Candidate]  (single view: both stripe orders; double view
                                             and head-on: the best-reading tile mappings of
                                             the pool ``illuknit double`` searches, compiled)
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from illuknit.app.controls import blame
from illuknit.app.inputs import Prepared
from illuknit.core.pattern import LogicalPattern

__all__ = ["Candidate", "Progress", "make_candidates"]


@dataclass(eq=False)
class Candidate:
    """One ranked design the designer can pick: a pattern plus what produced it.

    ``source`` is what :func:`pattern_for` needs to recompile with tile overrides (the tile
    assignment for double view; None for single view, which has no tiles).
    """

    rank: int
    label: str
    score: float | None
    pattern: LogicalPattern
    details: dict[str, Any] = field(default_factory=dict)
    source: Any = None
    #: how it reads and knits (tiles.perception.CandidateMeasures), once the measures job ran
    measured: Any = None

    def to_json(self) -> dict[str, Any]:
        n, m = self.pattern.shape
        return {
            "rank": self.rank,
            "label": self.label,
            "score": None if self.score is None else round(float(self.score), 4),
            "rows": n,
            "cols": m,
            "yarns": [{"name": y.name, "rgb": y.hex} for y in self.pattern.yarns],
            "raised": int(self.pattern.raised.sum()),
            "details": self.details,
            "measures": None if self.measured is None else self.measured.to_json(),
            "editable": self.source is not None,
        }


#: ``progress(fraction, message)``: reports a job's progress (and raises when it was cancelled).
Progress = Callable[[float, str], None]


def make_candidates(prepared: Prepared, *, count: int, progress: Progress) -> list[Candidate]:
    """Ranked candidates for the prepared inputs; ``progress(fraction, message)`` may cancel."""
    if prepared.mode == "single":
        return _single_candidates(prepared, progress)
    return _tile_candidates(prepared, count=count, progress=progress)


def _single_candidates(prepared: Prepared, progress: Progress) -> list[Candidate]:
    from illuknit.design.single_view import compile_single_view, single_view_errors

    q = prepared.quantised["a"]
    out = []
    for k, first in enumerate(("dark", "light")):
        progress(k / 2, f"compiling single view ({first} stripe first)")
        with blame("n_colors"):
            pattern = compile_single_view(q, first=first)  # type: ignore[arg-type]
        err = [round(e, 4) for e in single_view_errors(q, pattern)]
        out.append(
            Candidate(
                rank=k + 1,
                label=f"{first} stripe first",
                score=None,
                pattern=pattern,
                details={"first": first, "mismatch_A": err[0], "mismatch_B": err[1]},
            )
        )
    return out


def _tile_candidates(prepared: Prepared, *, count: int, progress: Progress) -> list[Candidate]:
    """The best-reading ``count`` of the tile designs ``illuknit double`` searches by default
    (:data:`~illuknit.design.tiles.perception.DEFAULT_POOL`), ranked as it ranks them."""
    from illuknit.design import tiles
    from illuknit.design.tiles.perception import (
        DEFAULT_POOL,
        POOL_SECONDS,
        rank_designs,
        seen_targets,
    )

    qa = prepared.quantised["a"]
    qb = prepared.quantised.get("b")
    pool = {"candidates": count, "pool": DEFAULT_POOL, "pool_seconds": POOL_SECONDS}
    progress(0.05, "building the tile bank")
    if prepared.mode == "headon":
        bank = tiles.headon_bank(prepared.yarns)
        progress(0.1, "finding tile mappings (head-on)")
        with blame("n_colors"):
            found = tiles.assign_headon(qa, qb, bank=bank, **pool)
        views = ("headon", "side")
    else:
        bank = tiles.canonical_bank(prepared.yarns)
        progress(0.1, f"finding tile mappings ({len(bank)} tiles in the bank)")
        with blame("n_colors"):
            found = tiles.assign_tiles(qa, qb, bank=bank, **pool)
        views = ("A", "B")
    with blame("tiles"):
        ranked = rank_designs(
            found,
            seen_targets(qa, qb),
            views=views,
            keep=count,
            progress=lambda f, message: progress(0.4 + 0.6 * f, message),
        )
    return [
        Candidate(
            rank=k + 1,
            label=_assignment_label(rc.assignment),
            score=float(rc.assignment.score),
            pattern=rc.pattern,
            details=_assignment_details(rc.assignment, rc.report),
            source=rc.assignment,
        )
        for k, rc in enumerate(ranked)
    ]


def _assignment_label(assignment: Any) -> str:
    kinds = [f.kind for f in (*assignment.fills_a, *assignment.fills_b) if f is not None]
    stripes = sum(k != "solid" for k in kinds)
    return (
        "all solid fills" if not stripes else f"{stripes} striped fill{'s' if stripes > 1 else ''}"
    )


def _assignment_details(assignment: Any, report: Any) -> dict[str, Any]:
    rep = report.to_json()
    return {
        "views": list(assignment.views),
        "fills": assignment.describe(),
        "error_original": rep["error_original"],
        "delta_e_original": rep["delta_e_original"],
        "color_changes_per_course": rep["color_changes_per_course"],
        "cost": {k: round(float(v), 3) for k, v in assignment.cost.items()},
    }
