"""``knit_pattern``'s long-float policy: refuse by default, keep and warn on request."""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np
import pytest

from illuknit.core.errors import LongFloatError, SchedulingError
from illuknit.core.machine import MachineSpec
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.knitting import knit_pattern
from illuknit.knitting.pipeline import LongFloatWarning

# Three yarns on three carriers with a float limit of one needle: the first pattern row has
# seven colour regions, more than the carriers can keep apart, so one float stays long.
YARN = np.array([[1, 2, 1, 0, 0, 1, 2, 1, 0], [0, 2, 0, 2, 0, 2, 0, 1, 1]], np.int16)
TIGHT = replace(MachineSpec(), float_limit=1, carriers=("1", "2", "3"))


def _crowded() -> LogicalPattern:
    return LogicalPattern(YARN, np.zeros(YARN.shape, bool), parse_yarns("#1b1b1b,#f4f0e8,#cc2222"))


def test_a_float_that_stays_long_is_refused_naming_the_course_and_the_fix():
    with pytest.raises(LongFloatError) as info:
        knit_pattern(_crowded(), machine=TIGHT)
    e = info.value
    assert isinstance(e, SchedulingError)
    assert e.length > TIGHT.float_limit == e.limit and e.count >= 1
    assert e.carrier in TIGHT.carriers and e.course is not None
    assert e.where.startswith("course ") and "pattern row" in e.where
    msg = str(e)
    assert e.where in msg and f"{e.length} needles" in msg
    assert f"needles {e.from_needle} to {e.to_needle}" in msg
    assert "fewer colour regions" in msg and "--allow-long-floats" in msg
    assert "--float-limit" in msg and "float_limit" not in msg


def test_allowed_long_floats_are_kept_reported_and_warned_about():
    with pytest.warns(LongFloatWarning) as caught:
        result = knit_pattern(_crowded(), machine=TIGHT, allow_long_floats=True)
    s = result.summary()
    assert s["long_floats"] >= 1 and s["longest_float"] > TIGHT.float_limit
    (w,) = caught
    text = str(w.message)
    assert f"the longest, {s['longest_float']} needles" in text
    assert s["longest_float_at"] in text and "course" in text
    # the same float the refusal names
    with pytest.raises(LongFloatError) as info:
        knit_pattern(_crowded(), machine=TIGHT)
    assert info.value.length == s["longest_float"]


def test_no_warning_when_every_float_is_within_the_limit():
    with warnings.catch_warnings():
        warnings.simplefilter("error", LongFloatWarning)
        result = knit_pattern(_crowded(), allow_long_floats=True)  # float limit 20
    assert result.summary()["long_floats"] == 0
