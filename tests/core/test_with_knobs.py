"""The keyword shorthand of the option objects (:func:`illuknit.core.arguments.with_knobs`)."""

from __future__ import annotations

from dataclasses import dataclass

import pytest

from illuknit.core.arguments import check_int, with_knobs
from illuknit.core.errors import OptionError


@dataclass(frozen=True)
class Knobs:
    steps: int = 2
    seed: int = 0

    def __post_init__(self) -> None:
        check_int(self.steps, "steps", min=1)


def test_keywords_replace_the_fields_of_the_options_or_of_the_defaults():
    assert with_knobs(Knobs, None, {}, what="test") == Knobs()
    assert with_knobs(Knobs, None, {"steps": 5}, what="test") == Knobs(steps=5)
    assert with_knobs(Knobs, Knobs(seed=3), {"steps": 5}, what="test") == Knobs(5, 3)
    base = Knobs(seed=1)
    assert with_knobs(Knobs, base, {}, what="test") is base


def test_wrong_options_unknown_keywords_and_bad_values_are_refused_by_name():
    with pytest.raises(OptionError, match="`size` must be a Knobs, got dict"):
        with_knobs(Knobs, {"steps": 1}, {}, name="size", what="test")  # type: ignore[arg-type]
    with pytest.raises(OptionError, match="unknown test option 'stepz'; valid: steps, seed"):
        with_knobs(Knobs, None, {"stepz": 1}, what="test")
    with pytest.raises(OptionError, match="`steps`"):
        with_knobs(Knobs, None, {"steps": 0}, what="test")
