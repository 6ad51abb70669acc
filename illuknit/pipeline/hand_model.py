"""The constraint model's design made for hands, ranked beside the tile designs (issue #37).

A double view made for hands (``RankOptions.made_for``) is searched twice: among the tile
designs (:mod:`illuknit.pipeline.tile_search`, the shared stripes included), and by the
constraint model whose hard constraints make every row knittable by hand
(:attr:`~illuknit.design.models.illusion_problem.IllusionProblem.for_hands`, what
``illuknit solve --for hands`` solves), on the same grid and pictures for
``SearchOptions.hand_model_seconds``. Its design is measured exactly as the tile designs are
(same views, angle, blur, reader) and ranked by the same key, so it is the default only where
that order puts it first; it has no tile assignment (``RankedDesign.assignment`` is None).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING, Any, Protocol

from illuknit.pipeline.designs import Progress, RankedDesign

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from illuknit.core.pattern import Yarn
    from illuknit.design.options import RankOptions, SearchOptions
    from illuknit.design.render.params import RenderParams
    from illuknit.pictures.images import QuantisedImage


class TileJobLike(Protocol):
    """What the constraint model reads of a tile stage's job
    (:class:`~illuknit.pipeline.tile_search.TileJob`)."""

    @property
    def qa(self) -> QuantisedImage: ...
    @property
    def qb(self) -> QuantisedImage | None: ...
    @property
    def yarns(self) -> tuple[Yarn, ...]: ...
    @property
    def search(self) -> SearchOptions: ...
    @property
    def say(self) -> Progress: ...


__all__ = ["HAND_MODEL_LABEL", "TileJobLike", "hand_model_design", "with_hand_model"]

#: The label of the constraint model's design among the tile designs.
HAND_MODEL_LABEL = "constraint model made for hands"


def hand_model_design(
    job: TileJobLike,
    targets: Sequence[NDArray[np.uint8]],
    ranking: RankOptions,
    *,
    blur: float,
    params: RenderParams | None,
    read: Callable[..., Any] | None,
) -> tuple[RankedDesign[Any, Any, Any], dict[str, Any]]:
    """Solve the constraint model made for hands on ``job``'s quantised pictures for
    ``job.search.hand_model_seconds``, measure its design as the tile designs are measured
    (``ranking``: the ranking they were ranked by, its order resolved), and return it (rank 0:
    not yet placed) with the solver's summary."""
    from illuknit.design.models.illusion_models import solve_illusion
    from illuknit.design.tiles.perception import measure_candidate, rank_key

    qa, qb = job.qa, job.qb
    assert qb is not None  # a double view (the caller checks)
    seconds = job.search.hand_model_seconds
    job.say(1.0, f"solving the constraint model made for hands (up to {seconds:g} s)")
    result = solve_illusion(
        qa.indices, qb.indices, model="logical", solver="cpsat", for_hands=True,
        yarns=job.yarns, n_yarns=len(job.yarns), time_limit=seconds,
    )  # fmt: skip
    pattern = result.pattern
    assert pattern is not None  # solve_illusion raises when it found none
    measures = measure_candidate(
        pattern, targets, views=("A", "B"), angle=ranking.angle, blur=blur, params=params
    )
    verdict = None
    if read is not None:
        (verdict,) = read([pattern], [measures])
        measures = replace(measures, sides_read=int(verdict.sides_read))
    key = rank_key(measures, math.inf, ranking.rank_by.value, hands=True)
    design: RankedDesign[Any, Any, Any] = RankedDesign(
        rank=0,
        pattern=pattern,
        measures=measures,
        rank_key=tuple(float(v) for v in key),
        rank_fields=ranking.key_fields,
        label=HAND_MODEL_LABEL,
        legibility=verdict,
    )
    summary = {"seconds": seconds, **result.solution.summary()}
    return design, summary


def with_hand_model(
    designs: Sequence[RankedDesign[Any, Any, Any]],
    extra: RankedDesign[Any, Any, Any],
    keep: int,
) -> tuple[tuple[RankedDesign[Any, Any, Any], ...], int | None]:
    """``designs`` (ranked) with ``extra`` placed by its rank key (after the designs it ties
    with), the best ``keep``, renumbered (a tile design's assignment too); and ``extra``'s rank
    there (None: not kept)."""
    merged = sorted([*designs, extra], key=lambda d: d.rank_key)[:keep]  # stable
    out = tuple(
        replace(
            d,
            rank=k + 1,
            assignment=None if d.assignment is None else replace(d.assignment, rank=k + 1),
        )
        for k, d in enumerate(merged)
    )
    place = next((k + 1 for k, d in enumerate(merged) if d is extra), None)
    return out, place
