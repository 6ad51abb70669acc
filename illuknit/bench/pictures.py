"""Bench instances made from a user's own pictures (``illuknit bench --pair A.png B.png``).

A pair of pictures is sized, quantised and modelled exactly as ``illuknit solve A.png B.png``
would (:func:`illuknit.pipeline.stages.illusion_model`: the sizing policy of
:mod:`illuknit.pictures.sizing`, the illusion model builder) -- **on the client**, once. The
instance carries the built models, so a Dask worker never needs the picture files (as a WCNF
file travels as its bytes, a picture pair travels as its built model). Where the model has an
exact optimum (the logical model: independent wales, the per-wale DP) it is the row's
``reference (dp)``, an optimum computed independently of every solver on the bench.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from illuknit.core.errors import OptionError
from illuknit.core.pattern import Yarn
from illuknit.solvers.model import Model

__all__ = ["PictureInstance", "picture_instances"]

#: Models a picture pair can be built as on the bench (a pair is a double-view target).
PICTURE_MODELS = ("logical", "knit-aware")


@dataclass(frozen=True, eq=False)
class PictureInstance:
    """A double-view bench instance from two pictures, its models built on the client.

    Attributes
    ----------
    name : str
        ``<A stem>+<B stem>`` (numbered when two pairs share it).
    size : (int, int)
        Grid rows and columns in units, as ``illuknit solve`` sizes the pair.
    n_yarns : int
        How many yarns the pictures were quantised to.
    built : mapping of model kind -> (Model, int or None)
        Each model and its exact optimum (the DP's) where the model has one.
    sources : (str, str)
        The picture files A and B.
    """

    name: str
    size: tuple[int, int]
    n_yarns: int
    built: Mapping[str, tuple[Model, int | None]]
    sources: tuple[str, str] = ("", "")
    kind: str = "double"
    tags: tuple[str, ...] = field(default=())

    def model(self, kind: str) -> tuple[Model, int | None]:
        """(the ``kind`` model, its exact optimum or None)."""
        try:
            return self.built[kind]
        except KeyError:
            raise OptionError(
                f"instance {self.name!r} was built as {', '.join(self.built)}, not {kind!r}"
            ) from None


def _pair_name(a: str, b: str, taken: set[str]) -> str:
    base = "+".join(re.sub(r"[^a-z0-9-]+", "-", Path(p).stem.lower()).strip("-") for p in (a, b))
    name, k = base, 2
    while name in taken:
        name, k = f"{base}-{k}", k + 1
    taken.add(name)
    return name


def picture_instances(
    pairs: Sequence[tuple[str, str]],
    *,
    models: Sequence[str] = ("logical",),
    n_colors: int | None = None,
    yarns: Sequence[Yarn] | None = None,
    width: int | None = None,
    stretch: bool = False,
    unit_aspect: float | None = None,
) -> list[PictureInstance]:
    """One :class:`PictureInstance` per (A, B) pair, each model built as ``illuknit solve``
    builds it for the same sizing arguments (see :func:`illuknit.pipeline.stages.illusion_model`).

    Raises
    ------
    OptionError
        A model kind a picture pair cannot be (``single``: a pair has two views).
    ImageInputError
        A picture that cannot be read or sized (the message names it).
    """
    from illuknit.design.models.backends.dp import solve_dp
    from illuknit.design.models.illusion_problem import problem_of
    from illuknit.design.options import ModelKind, SolveOptions
    from illuknit.pipeline.stages import illusion_model

    for kind in models:
        if kind not in PICTURE_MODELS:
            raise OptionError(
                f"`models`: a picture pair is built as {' or '.join(PICTURE_MODELS)}, not {kind!r}"
            )
    taken: set[str] = set()
    out = []
    for a, b in pairs:
        built: dict[str, tuple[Model, int | None]] = {}
        for kind in models:
            mdl: Any = illusion_model(
                a,
                b,
                options=SolveOptions(model=ModelKind(kind)),
                n_colors=n_colors,
                yarns=yarns,
                width=width,
                stretch=stretch,
                unit_aspect=unit_aspect,
            )
            problem = mdl.problem
            exact = problem.per_wale or problem.rows_tied
            built[kind] = (mdl, int(solve_dp(problem)[2]) if exact else None)
        problem = problem_of(next(iter(built.values()))[0])
        out.append(
            PictureInstance(
                name=_pair_name(str(a), str(b), taken),
                size=(int(problem.target_a.shape[0]), int(problem.target_a.shape[1])),
                n_yarns=int(problem.n_yarns),
                built=built,
                sources=(str(a), str(b)),
            )
        )
    return out
