import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from illuknit.core.errors import ImageInputError
from illuknit.core.pattern import parse_yarns
from illuknit.core.views import can_see
from illuknit.design.single_view import (
    compile_single_view,
    prepare_single_view_image,
    single_view_errors,
)
from illuknit.pictures.images import QuantisedImage

Y2 = parse_yarns("Dark=#1b1b1b,Light=#f4f0e8")
Y3 = parse_yarns("Dark=#1b1b1b,Grey=#8c8c8c,Light=#f4f0e8")


def pictures(k):
    shapes = st.tuples(st.integers(2, 14), st.integers(1, 14))
    return shapes.flatmap(lambda s: arrays(np.int16, s, elements=st.integers(0, k - 1)))


@given(pictures(2), st.sampled_from(["dark", "light"]))
def test_two_colors_seen_exactly_shifted_by_one_row(pic, first):
    p = compile_single_view(pic, yarns=Y2, first=first)
    va, vb = can_see(p, "A"), can_see(p, "B")
    # The pattern's palette is the two yarns in their given order, so indices compare directly.
    assert np.array_equal(va[1:], pic[:-1])
    assert np.array_equal(vb[:-1], pic[1:])
    # Head-on it is a plain stripe: every row one yarn, alternating.
    assert (p.yarn == p.yarn[:, :1]).all()
    assert (p.yarn[1:, 0] != p.yarn[:-1, 0]).all()
    # Boundary rows show the stripe colour.
    assert (va[0] == p.yarn[0, 0]).all() and (vb[-1] == p.yarn[-1, 0]).all()


@given(pictures(3))
def test_three_colors_within_tolerance(pic):
    p = compile_single_view(pic, yarns=Y3)
    dark, light = 0, 1  # pattern palette: Dark, Light
    outer = np.where(pic == 0, dark, np.where(pic == 2, light, -1))
    va, vb = can_see(p, "A"), can_see(p, "B")
    m_a = outer[:-1] >= 0
    assert np.array_equal(va[1:][m_a], outer[:-1][m_a])
    m_b = outer[1:] >= 0
    assert np.array_equal(vb[:-1][m_b], outer[1:][m_b])
    # A middle pixel is seen as the stripe colour of its own row ...
    mid = pic == 1
    assert np.array_equal(va[1:][mid[:-1]], p.yarn[:-1][mid[:-1]])
    assert np.array_equal(vb[:-1][mid[1:]], p.yarn[1:][mid[1:]])
    # ... so two vertically adjacent middle pixels are seen half dark, half light.
    pair = mid[:-2] & mid[1:-1]
    assert (va[1:-1][pair] != va[2:][pair]).all()
    assert len(p.yarns) == 2


def test_quantised_input_and_error_report():
    pic = np.array([[0, 1, 2], [2, 1, 0], [0, 0, 2], [1, 2, 2]])
    q = QuantisedImage(pic, Y3, np.array([y.rgb for y in Y3], np.uint8))
    p = compile_single_view(q)
    assert p.meta["middle"] == "Grey"
    assert single_view_errors(q, p) == (0.0, 0.0)


def test_wrong_color_counts():
    with pytest.raises(ImageInputError, match="2- or 3-colour"):
        compile_single_view(np.zeros((3, 3), int), yarns=parse_yarns("black"))
    with pytest.raises(ImageInputError, match="2- or 3-colour"):
        compile_single_view(np.zeros((3, 3), int), yarns=parse_yarns("black,white,red,blue"))
    with pytest.raises(ImageInputError, match=r"0\.\.1"):
        compile_single_view(np.full((3, 3), 2), yarns=Y2)


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_photo_with_two_yarns_keeps_a_middle_color(seed):
    rgb = np.random.default_rng(seed).random((12, 16, 3))
    q = prepare_single_view_image(rgb, yarns=Y2, width=16)
    assert len(q.yarns) == 3
    assert q.yarns[0] == Y2[0] and q.yarns[2] == Y2[1]
    p = compile_single_view(q)
    assert [y.name for y in p.yarns] == ["Dark", "Light"]
