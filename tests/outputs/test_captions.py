"""Head-on captions measured from the renders (issue 33, item 7)."""

from __future__ import annotations

import numpy as np
import pytest

from illuknit.core.pattern import LogicalPattern, Yarn
from illuknit.design.single_view import compile_single_view
from illuknit.outputs.captions import HeadOnLikeness, headon_likeness

YARNS = (Yarn("Dark", (27, 27, 27)), Yarn("Light", (244, 240, 232)))


def test_a_single_view_is_stripes_head_on():
    picture = np.zeros((20, 16), dtype=np.int16)
    picture[5:15, 4:12] = 1
    pattern = compile_single_view(picture, yarns=YARNS)
    likeness = headon_likeness(pattern)
    assert likeness.shows == "stripes" and likeness.spread < 0.02
    assert likeness.caption() == "Head-on: stripes (no picture)"


def test_a_flat_piece_shows_the_same_picture_from_everywhere():
    yarn = np.zeros((12, 10), dtype=np.int16)
    yarn[3:9, 2:8] = 1
    likeness = headon_likeness(LogicalPattern(yarn, np.zeros(yarn.shape, bool), YARNS))
    assert likeness.shows == "same" and likeness.like_a == pytest.approx(1.0)


@pytest.mark.parametrize(
    ("a", "b", "shows"),
    [(0.8, 0.7, "both"), (0.8, 0.05, "A"), (-0.1, 0.6, "B"), (0.05, -0.3, "own")],
)
def test_each_caption_names_what_it_measured(a, b, shows):
    likeness = HeadOnLikeness(like_a=a, like_b=b, spread=0.2)
    assert likeness.shows == shows
    caption = likeness.caption()
    assert f"view A {a:.2f}" in caption and f"view B {b:.2f}" in caption
    assert "stripes" not in caption
    assert likeness.as_dict()["caption"] == caption
