import itertools

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from illuknit.core.errors import ImageInputError, OptionError, PatternValidationError
from illuknit.core.views import can_see, logical_error, seen_rows


def _brute(c, r, view):
    """Direct transcription of the paper's 4.2 rules, one cell at a time."""
    n, m = c.shape
    out = np.empty_like(c)
    for i, j in itertools.product(range(n), range(m)):
        if view == "A":
            out[i, j] = c[i - 1, j] if i > 0 and r[i - 1, j] else c[i, j]
        elif view == "B":
            out[i, j] = c[i + 1, j] if i < n - 1 and r[i + 1, j] else c[i, j]
        else:
            out[i, j] = c[i, j]
    return out


grids = st.tuples(st.integers(1, 9), st.integers(1, 9)).flatmap(
    lambda s: st.tuples(arrays(np.int16, s, elements=st.integers(0, 3)), arrays(np.bool_, s))
)


@given(grids, st.sampled_from(["A", "B", "headon"]))
def test_can_see_matches_cellwise_rules(cr, view):
    c, r = cr
    assert np.array_equal(can_see(c, view, r), _brute(c, r, view))
    rows = seen_rows(r, view)
    assert np.array_equal(np.take_along_axis(c, rows, axis=0), _brute(c, r, view))


@given(grids)
def test_views_are_mirror_images(cr):
    # Seen from below is seen from above with the piece turned upside down.
    c, r = cr
    assert np.array_equal(can_see(c, "B", r), can_see(c[::-1], "A", r[::-1])[::-1])


def test_flat_pattern_shows_itself_everywhere():
    c = np.arange(12).reshape(3, 4) % 3
    r = np.zeros_like(c, dtype=bool)
    for v in ("A", "B", "headon"):
        assert np.array_equal(can_see(c, v, r), c)


def test_logical_error_and_bad_views():
    assert logical_error([[0, 1]], [[0, 0]]) == 0.5
    assert logical_error([[0, 1]], [[0, 0]], normalize=False) == 1
    assert logical_error([[0, 1]], [[0, 0]], mask=[[True, False]]) == 0.0
    with pytest.raises(ImageInputError):
        logical_error([[0, 1]], [[0]])
    with pytest.raises(OptionError):
        can_see(np.zeros((2, 2), int), "side", np.zeros((2, 2), bool))  # type: ignore[arg-type]
    with pytest.raises(PatternValidationError):
        can_see(np.zeros((2, 2), int), "A", np.zeros((3, 2), bool))
