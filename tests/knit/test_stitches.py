"""Lowering a logical pattern to stitches: 2 x 2 stitches per unit, bottom row knitted first."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.core.errors import OptionError, PatternValidationError, SchedulingError
from illuknit.core.machine import MachineSpec
from illuknit.core.pattern import LogicalPattern, Yarn
from illuknit.knit import KNIT, PURL, StitchPattern, lower_to_stitches

YARNS = (Yarn("dark", (20, 20, 20)), Yarn("light", (240, 240, 240)), Yarn("mid", (128, 0, 0)))


@st.composite
def patterns(draw, max_rows=6, max_cols=6, n_yarns=3):
    n = draw(st.integers(1, max_rows))
    m = draw(st.integers(1, max_cols))
    yarn = np.array(draw(st.lists(st.integers(0, n_yarns - 1), min_size=n * m, max_size=n * m)))
    raised = np.array(draw(st.lists(st.booleans(), min_size=n * m, max_size=n * m)))
    return LogicalPattern(yarn.reshape(n, m), raised.reshape(n, m), YARNS[:n_yarns])


@settings(max_examples=60, deadline=None)
@given(patterns())
def test_each_unit_becomes_its_two_by_two_block(p):
    s = lower_to_stitches(p)
    n, m = p.shape
    assert s.shape == (2 * n, 2 * m)
    # Brute force against the documented mapping: course c -> row N-1-c//2, wale w -> col w//2.
    for c in range(2 * n):
        for w in range(2 * m):
            i, j = n - 1 - c // 2, w // 2
            assert s.yarn[c, w] == p.yarn[i, j]
            second = c % 2 == 1
            expected = PURL if (second and p.raised[i, j]) else KNIT
            assert s.kind[c, w] == expected


def test_bump_is_a_knit_with_a_purl_child():
    p = LogicalPattern(np.array([[0, 1]]), np.array([[True, False]]), YARNS[:2])
    s = lower_to_stitches(p)
    assert s.kind.tolist() == [[KNIT, KNIT, KNIT, KNIT], [PURL, PURL, KNIT, KNIT]]
    assert s.yarn.tolist() == [[0, 0, 1, 1], [0, 0, 1, 1]]


def test_physical_size_follows_the_gauge():
    p = LogicalPattern(np.zeros((5, 7), int), np.zeros((5, 7), bool), YARNS[:1])
    s7 = lower_to_stitches(p, machine=MachineSpec(gauge=7))
    s14 = lower_to_stitches(p, machine=MachineSpec(gauge=14))
    assert s7.size_cm[0] == pytest.approx(14 * 2.54 / 7)
    assert s7.size_cm[1] == pytest.approx(10 * 2.54 / 7 * 0.7)
    assert s14.size_cm[0] == pytest.approx(s7.size_cm[0] / 2)


def test_pattern_wider_than_the_bed_is_refused():
    p = LogicalPattern(np.zeros((2, 30), int), np.zeros((2, 30), bool), YARNS[:1])
    with pytest.raises(SchedulingError, match="machine-width"):
        lower_to_stitches(p, machine=MachineSpec(needles=60))
    # exactly fitting: 60 wales + parking room 2 * 2 + 1
    assert lower_to_stitches(p, machine=MachineSpec(needles=65)).wales == 60


def test_stitch_pattern_validates_its_arrays():
    with pytest.raises(PatternValidationError, match="kind"):
        StitchPattern(np.full((2, 2), 3), np.zeros((2, 2), int), YARNS[:1])
    with pytest.raises(PatternValidationError, match="yarn"):
        StitchPattern(np.zeros((2, 2)), np.zeros((2, 3), int), YARNS[:1])
    with pytest.raises(PatternValidationError, match=r"0\.\.0"):
        StitchPattern(np.zeros((2, 2)), np.ones((2, 2), int), YARNS[:1])
    with pytest.raises(PatternValidationError, match="cast_on_courses"):
        StitchPattern(np.zeros((2, 2)), np.zeros((2, 2), int), YARNS[:1], cast_on_courses=-1)


def test_mixed_courses_are_found():
    p = LogicalPattern(np.array([[0, 1], [1, 1]]), np.zeros((2, 2), bool), YARNS[:2])
    s = lower_to_stitches(p)
    assert s.mixed_courses().tolist() == [2, 3]
    assert s.course_yarns(2) == (0, 1)
    assert s.used_yarns() == (0, 1)


def test_machine_spec_rejects_nonsense():
    with pytest.raises(OptionError, match="needles"):
        MachineSpec(needles=0)
    with pytest.raises(OptionError, match="carriers"):
        MachineSpec(carriers=("1", "1"))
    with pytest.raises(OptionError, match="position"):
        MachineSpec(position="Middle")
    assert MachineSpec().carriers == tuple(str(i) for i in range(1, 11))
