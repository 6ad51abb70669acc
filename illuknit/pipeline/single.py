"""The single-view stage (paper section 5): the pattern of a 2- or 3-colour picture for each
stripe order, ranked by how well each shows the picture."""

from __future__ import annotations

from collections.abc import Sequence
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, cast

from illuknit.core.machine import MachineSpec, resolve_machine
from illuknit.pipeline.designs import Picture, RankedDesign, SingleDesign, Stripe
from illuknit.pipeline.inputs import (
    PictureOptions,
    check_fits,
    check_picture,
    check_sizes,
    check_yarns,
    fit_machine,
    fit_notes,
    picture_options,
    unit_aspect_or_default,
)

if TYPE_CHECKING:
    from illuknit.core.pattern import LogicalPattern, Yarn
    from illuknit.pictures.images import QuantisedImage

__all__ = ["SINGLE_PICTURE_OPTIONS", "design_single"]

#: What the single-view stage reads of :class:`~illuknit.pipeline.inputs.PictureOptions`.
SINGLE_PICTURE_OPTIONS = (
    "width", "height", "width_cm", "gauge", "unit_aspect", "n_colors", "yarns", "quantise",
)  # fmt: skip


def design_single(
    picture: Picture | QuantisedImage,
    *,
    pictures: PictureOptions | None = None,
    first: Stripe = "dark",
    knit_on: str | MachineSpec | None = None,
    machine: str | MachineSpec | None = None,
    **knobs: Any,
) -> SingleDesign:
    """The single-view pattern of a 2- or 3-colour picture for each stripe order, ranked.

    ``picture`` is a file, an sRGB array (sized by ``width``/``height``/``width_cm`` at
    ``gauge``, default the machine's, with units ``unit_aspect`` high, and quantised to
    ``n_colors`` or onto ``yarns``, unless ``quantise`` is off: the fields of ``pictures``,
    :class:`~illuknit.pipeline.inputs.PictureOptions`, also taken as keywords) or a
    :class:`~illuknit.pictures.images.QuantisedImage` used as it is. The designs are ranked by the worse
    view's mismatch (:func:`~illuknit.design.single_view.single_view_errors`), the stripe order
    ``first`` first on a tie. With ``knit_on`` a picture wider than its bed is refused first.
    ``notes`` say when the grid fits no bed of ``machine`` (default ``knit_on``, else the
    default machine), or only a generic one.
    """
    from illuknit.core.arguments import check_bool, check_choice, check_int
    from illuknit.design.single_view import compile_single_view, prepare_single_view_image
    from illuknit.pictures.images import QuantisedImage

    meant_for = knit_on if machine is None else resolve_machine(machine)  # checked first
    opts = picture_options(pictures, knobs, takes=SINGLE_PICTURE_OPTIONS)
    width, height, width_cm, gauge = opts.width, opts.height, opts.width_cm, opts.gauge
    n_colors, quantise = opts.n_colors, opts.quantise
    yarns = cast("Sequence[Yarn] | None", opts.yarns)  # a count is refused below
    check_choice(first, "first", ("dark", "light"))
    if n_colors is not None:  # the 2 or 3 a single-view illusion shows: prepare_single_view_image
        check_int(n_colors, "n_colors", min=1, max=8)
    check_picture(picture, "picture")
    check_sizes(width=width, height=height, width_cm=width_cm, gauge=gauge)
    check_yarns(yarns, count_ok=False)
    check_bool(quantise, "quantise")
    machine = fit_machine(knit_on)
    if isinstance(picture, QuantisedImage):
        q = picture
    else:
        q = prepare_single_view_image(
            picture,
            width=width,
            height=height,
            width_cm=width_cm,
            gauge=gauge if gauge is not None else (machine or resolve_machine(None)).gauge,
            n_colors=n_colors,
            yarns=None if yarns is None else tuple(yarns),
            allow_quantise=quantise,
            unit_aspect=unit_aspect_or_default(opts.unit_aspect),
        )
    check_fits(machine, q.indices.shape[1])
    orders: tuple[Stripe, Stripe] = (first, "light" if first == "dark" else "dark")
    made = [(o, compile_single_view(q, first=o)) for o in orders]
    notes = fit_notes(meant_for, q.indices.shape[1])
    return SingleDesign(q, _rank_single(q, made), notes)


def _rank_single(
    q: QuantisedImage, made: Sequence[tuple[Stripe, LogicalPattern]]
) -> tuple[RankedDesign, ...]:
    from illuknit.design.single_view import single_view_errors

    scored = []
    for k, (order, pattern) in enumerate(made):
        err = single_view_errors(q, pattern)
        key = (max(err), float(k))
        measures = {"first": order, "mismatch_A": err[0], "mismatch_B": err[1]}
        scored.append((key, order, pattern, measures))
    scored.sort(key=lambda s: s[0])
    fields = ("worse view's mismatch", "stripe order (0: the one asked for)")
    return tuple(
        RankedDesign(
            rank=r + 1,
            pattern=pattern,
            measures=MappingProxyType(measures),
            rank_key=key,
            rank_fields=fields,
            label=f"{order} stripe first",
        )
        for r, (key, order, pattern, measures) in enumerate(scored)
    )
