"""The constraint-model stage (paper section 4): the pictures sized and quantised jointly
(:func:`quantise_targets`), a model built (:func:`illusion_model`) and solved
(:func:`solve_design`)."""

from __future__ import annotations

from collections.abc import Sequence
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from illuknit.core.errors import ImageInputError, YarnSpecError
from illuknit.core.machine import MachineSpec, resolve_machine
from illuknit.design.options import MadeFor, ModelKind, SolveOptions
from illuknit.pipeline.designs import Picture, SolvedDesign
from illuknit.pipeline.inputs import (
    PictureOptions,
    check_fits,
    check_picture,
    check_sizes,
    check_type,
    check_yarns,
    fit_machine,
    fit_notes,
    picture_options,
    source_name,
    unit_aspect_or_default,
    with_meta,
)

if TYPE_CHECKING:
    from illuknit.core.pattern import Yarn
    from illuknit.pictures.images import QuantisedImage
    from illuknit.solvers.base import ProgressCallback
    from illuknit.solvers.model import Model

__all__ = [
    "SOLVE_PICTURE_OPTIONS",
    "check_made_for",
    "illusion_model",
    "quantise_targets",
    "solve_design",
]

#: What the constraint-model stage reads of :class:`~illuknit.pipeline.inputs.PictureOptions`.
SOLVE_PICTURE_OPTIONS = ("width", "stretch", "unit_aspect", "n_colors", "yarns", "quantise")


def check_made_for(made_for: Any) -> MadeFor:
    """``made_for`` as a :class:`~illuknit.design.options.MadeFor` (None means the machine).

    Raises
    ------
    OptionError
        Neither ``machine`` nor ``hands``.
    """
    from illuknit.design.options import enum_option

    return MadeFor.MACHINE if made_for is None else enum_option(MadeFor, "made_for", made_for)


def solve_design(
    picture_a: Picture,
    picture_b: Picture | None = None,
    *,
    options: SolveOptions | None = None,
    pictures: PictureOptions | None = None,
    knit_on: str | MachineSpec | None = None,
    progress: ProgressCallback | None = None,
    machine: str | MachineSpec | None = None,
    **knobs: Any,
) -> SolvedDesign:
    """The pattern a constraint model and a solver find for one or two target pictures.

    The pictures are sized to one grid (``width`` units; ``stretch`` a B of another shape onto
    A's; units ``unit_aspect`` high) and quantised jointly to ``n_colors`` yarns (or onto
    ``yarns``; ``quantise`` off refuses a picture with more colours; :func:`quantise_targets`):
    the fields of ``pictures``, :class:`~illuknit.pipeline.inputs.PictureOptions`, also taken
    as keywords), so a colour means the same yarn in both; the model
    (``options.model``: two pictures for ``logical`` and ``knit-aware``, one for ``single``) is
    solved by :func:`~illuknit.design.models.illusion_models.solve_illusion`. ``progress`` receives the
    solver's improvements. With ``knit_on`` a pattern wider than its bed is refused first;
    ``notes`` as :func:`design_single`'s, for ``machine``. ``made_for="hands"`` (a keyword, or
    ``options.made_for``) makes every row knittable by hand: hard constraints of the model
    (:attr:`~illuknit.design.models.illusion_problem.IllusionProblem.for_hands`), and the report
    gains ``hand``, the pattern's :class:`~illuknit.design.hand_cost.HandCost` as measured.

    Raises
    ------
    InfeasibleError, SolverError
        As :func:`~illuknit.design.models.illusion_models.solve_illusion`.
    """
    from illuknit.core.arguments import check_callable
    from illuknit.design.models.illusion_models import solve_illusion

    made_for = knobs.pop("made_for", None)
    options = SolveOptions() if options is None else options
    check_type("options", options, SolveOptions)
    if made_for is not None:
        from dataclasses import replace

        options = replace(options, made_for=check_made_for(made_for))
    check_callable(progress, "progress")
    machine = None if machine is None else resolve_machine(machine)
    opts = picture_options(pictures, knobs, takes=SOLVE_PICTURE_OPTIONS)
    qa, qb = _solve_targets((picture_a, picture_b), options, opts, knit_on)
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
        for_hands=options.for_hands,
        time_limit=options.time_limit,
        seed=options.seed,
        progress=progress,
    )
    pattern = result.pattern
    assert pattern is not None  # solve_illusion raises when the solver found none
    sources = [source_name(picture_a), source_name(picture_b)]
    pattern = with_meta(pattern, {"sources": sources})
    report = dict(result.report)
    report["sources"] = {"A": sources[0], "B": sources[1]}
    report["legend"] = qa.legend()
    if result.solution.stats.get("interrupted"):
        report["note"] = "interrupted with Ctrl-C: the best pattern found so far"
    quantised = (qa,) if qb is None else (qa, qb)
    notes = fit_notes(knit_on if machine is None else machine, pattern.shape[1])  # checked above
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
    pictures: PictureOptions | None = None,
    knit_on: str | MachineSpec | None = None,
    **knobs: Any,
) -> Model:
    """The constraint model :func:`solve_design` solves for the same arguments, unsolved (to
    export it, ``model.to_wcnf()``, or to hand it to :func:`illuknit.solvers.solve`)."""
    from illuknit.design.models.illusion_models import build_model, make_problem

    options = SolveOptions() if options is None else options
    check_type("options", options, SolveOptions)
    opts = picture_options(pictures, knobs, takes=SOLVE_PICTURE_OPTIONS)
    qa, qb = _solve_targets((picture_a, picture_b), options, opts, knit_on)
    problem = make_problem(
        qa.indices,
        None if qb is None else qb.indices,
        n_yarns=len(qa.yarns),
        kind=options.model.value,
        weights=options.weights,
        alternate_rows=options.alternate_rows,
        split_bumps=options.split_bumps,
    )
    if options.for_hands:
        from dataclasses import replace

        problem = replace(problem, for_hands=True)
    return build_model(problem)


def _solve_targets(
    given: tuple[Picture, Picture | None],
    options: SolveOptions,
    opts: PictureOptions,
    knit_on: str | MachineSpec | None,
) -> tuple[QuantisedImage, QuantisedImage | None]:
    """Check the pictures against the model and the bed, then :func:`quantise_targets`."""
    from illuknit.core.arguments import check_bool, check_int

    picture_a, picture_b = given
    n_colors, width = opts.n_colors, opts.width
    yarns = cast("Sequence[Yarn] | None", opts.yarns)  # a count is refused below
    single = options.model is ModelKind.SINGLE
    check_picture(picture_a, "picture_a")
    check_picture(picture_b, "picture_b", optional=True)
    if n_colors is not None:
        check_int(n_colors, "n_colors", min=1, max=8)
    check_yarns(yarns, count_ok=False)
    check_sizes(width=width)
    check_bool(opts.stretch, "stretch")
    check_bool(opts.quantise, "quantise")
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
    machine = fit_machine(knit_on)
    check_fits(machine, width)
    qa, qb = quantise_targets(
        picture_a, picture_b, width=width, stretch=opts.stretch, n_colors=n_colors, yarns=yarns,
        quantise=opts.quantise, unit_aspect=opts.unit_aspect,
    )  # fmt: skip
    check_fits(machine, qa.indices.shape[1])
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

    check_picture(picture_a, "picture_a")
    check_picture(picture_b, "picture_b", optional=True)
    if n_colors is not None:
        check_int(n_colors, "n_colors", min=1, max=8)
    check_yarns(yarns, count_ok=False)
    check_sizes(width=width)
    check_bool(stretch, "stretch")
    check_bool(quantise, "quantise")
    pair = size_pair(
        picture_a,
        picture_b,
        width=width,
        stretch=stretch,
        unit_aspect=unit_aspect_or_default(unit_aspect),
    )
    a, b = pair.a, pair.b
    both = a if b is None else np.concatenate([a, b], axis=0)
    q = quantise_image(both, n_colors=n_colors, yarns=yarns, allow_quantise=quantise)
    n = a.shape[0]
    qa = QuantisedImage(q.indices[:n], q.yarns, q.colors)
    qb = None if b is None else QuantisedImage(q.indices[n:], q.yarns, q.colors)
    return qa, qb
