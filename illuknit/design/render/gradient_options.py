"""How the gradient design of :func:`~illuknit.design.render.optimise.optimise_design` runs.

One frozen, validated type for the schedule (steps, step size, annealing), the objective's
weights, what the renderer averages, the seed and the time limit; checked once, where it is made,
with an :class:`~illuknit.core.errors.OptionError` naming the field.

Examples
--------
>>> GradientOptions(steps=50).learning_rate
0.2
>>> GradientOptions(final_temperature=2)
Traceback (most recent call last):
...
illuknit.core.errors.OptionError: `final_temperature` must lie in (0, 1], got 2
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from illuknit.core.arguments import (
    check_int,
    check_number,
    check_seconds,
    check_seed,
    check_str,
    with_knobs,
)
from illuknit.core.errors import OptionError

__all__ = ["MIXES", "GradientOptions", "gradient_options"]

#: What the renderer averages (see :attr:`GradientOptions.mix`).
MIXES = ("rgb", "yarn")


@dataclass(frozen=True)
class GradientOptions:
    """How :func:`~illuknit.design.render.optimise.optimise_design` optimises.

    Parameters
    ----------
    steps : int
        Adam steps (1 to 100000).
    learning_rate : float
        The step size on the logits (> 0).
    binary_weight : float
        Final weight of the binariness penalty (ramped up from 0).
    change_weight, raised_weight : float
        Weights of the expected share of colour changes along courses (slow to knit) and of the
        share of raised units (each bump costs knit/purl transfers).
    final_temperature : float
        Temperature at the last step (annealed from 1), in (0, 1].
    mix : {"rgb", "yarn"}
        What the renderer averages: the yarns' linear-light colours ("rgb": the error a viewer
        sees, similar yarns count little), or the yarn probabilities themselves ("yarn": every
        wrong yarn counts the same, as in the logical models; RGB targets are first mapped to
        their nearest yarns).
    seed : int
        Seed of the small random initialisation.
    time_limit : float, optional
        Stop early after this many seconds.
    """

    steps: int = 200
    learning_rate: float = 0.2
    binary_weight: float = 0.1
    change_weight: float = 0.0
    raised_weight: float = 0.0
    final_temperature: float = 0.05
    mix: str = "rgb"
    seed: int = 0
    time_limit: float | None = None

    def __post_init__(self) -> None:
        # bounds far beyond any useful value: they only refuse slips (10**30 steps never ends)
        check_int(self.steps, "steps", min=1, max=100_000)
        check_number(self.learning_rate, "learning_rate", min=0, max=100, min_open=True)
        check_number(self.binary_weight, "binary_weight", min=0, max=1e6)
        check_number(self.change_weight, "change_weight", min=0, max=1e6)
        check_number(self.raised_weight, "raised_weight", min=0, max=1e6)
        check_number(self.final_temperature, "final_temperature", min=0, min_open=True)
        if not self.final_temperature <= 1:
            raise OptionError(
                f"`final_temperature` must lie in (0, 1], got {self.final_temperature!r}"
            )
        check_str(self.mix, "mix")
        if self.mix not in MIXES:
            raise OptionError(f"`mix` must be 'rgb' or 'yarn', got {self.mix!r}")
        check_seed(self.seed)
        check_seconds(self.time_limit, "time_limit")


def gradient_options(options: GradientOptions | None, knobs: dict[str, Any]) -> GradientOptions:
    """``options`` (default ``GradientOptions()``) with the shorthand ``knobs`` in place of its
    fields (:func:`~illuknit.core.arguments.with_knobs`)."""
    return with_knobs(GradientOptions, options, knobs, what="gradient")
