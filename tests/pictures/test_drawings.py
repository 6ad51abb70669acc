"""Code-drawn inputs: shapes, sizes, symmetry, no network for bundled pictures."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.core.errors import ImageInputError, UnknownNameError
from illuknit.pictures.drawings import (
    BUNDLED_IMAGES,
    DRAWINGS,
    draw_circle,
    draw_ecg,
    draw_heart,
    draw_plus,
    draw_shape,
    draw_text,
    layer_masks,
    skimage_image,
    to_index_image,
)

shapes = st.tuples(st.integers(6, 60), st.integers(6, 60))


@settings(max_examples=25, deadline=None)
@given(shape=shapes, name=st.sampled_from(sorted(DRAWINGS)))
def test_drawn_shapes_have_the_requested_shape_and_both_colors(shape, name):
    m = draw_shape(name, shape)
    assert m.shape == shape and m.dtype == bool
    assert m.any() and not m.all()


@settings(max_examples=15, deadline=None)
@given(shape=shapes)
def test_plus_and_circle_are_mirror_symmetric(shape):
    p = draw_plus(shape)
    assert np.array_equal(p, p[::-1]) and np.array_equal(p, p[:, ::-1])
    c = draw_circle(shape)
    assert np.array_equal(c, c[::-1]) and np.array_equal(c, c[:, ::-1])


def test_heart_is_left_right_symmetric_and_points_down():
    h = draw_heart((40, 40))
    assert np.array_equal(h, h[:, ::-1])
    rows = np.nonzero(h.any(axis=1))[0]
    top, bottom = h[rows[0]], h[rows[-1]]
    # two lobes at the top (a gap in the middle), one narrow tip at the bottom
    assert not top[20] and top.sum() > bottom.sum()


def test_circle_area_matches_pi_r_squared():
    c = draw_circle((100, 100), radius=0.3)
    assert abs(c.sum() - np.pi * 30**2) < 0.02 * np.pi * 30**2


def test_ring_is_hollow():
    r = draw_circle((40, 40), radius=0.4, ring=0.1)
    assert not r[20, 20] and r.sum() > 0


def test_plus_bars_cross_at_the_centre():
    p = draw_plus((21, 21), arm=1 / 3, margin=0.0)
    assert p[10].all() and p[:, 10].all()
    assert not p[0, 0] and not p[-1, -1]


def test_ecg_line_spans_the_width_and_has_a_peak():
    e = draw_ecg((30, 90))
    cols = np.nonzero(e.any(axis=0))[0]
    assert cols[0] < 10 and cols[-1] > 80
    # every drawn column holds the line: it never breaks
    assert e[:, cols[0] : cols[-1] + 1].any(axis=0).all()
    # the R peak reaches well above the baseline
    assert np.nonzero(e.any(axis=1))[0][0] < 8


def test_ecg_is_thick_enough_to_read():
    e = draw_ecg((40, 80))
    baseline_col = e[:, 8:14]  # flat part of the trace
    assert (baseline_col.sum(axis=0) >= 3).all()


def test_text_is_centred_and_fills_the_shape():
    m = draw_text("ILLUSION", shape=(20, 80), margin=0.1)
    rows = np.nonzero(m.any(axis=1))[0]
    cols = np.nonzero(m.any(axis=0))[0]
    assert rows[0] >= 1 and rows[-1] <= 18
    assert cols[0] <= 10 and cols[-1] >= 69
    assert abs((cols[0] + cols[-1]) / 2 - 39.5) <= 2


def test_text_keep_aspect_leaves_space_on_a_square():
    m = draw_text("KNITTING", shape=(40, 40), keep_aspect=True)
    rows = np.nonzero(m.any(axis=1))[0]
    assert rows[-1] - rows[0] < 20


def test_different_words_differ():
    a = draw_text("ILLUSION", shape=(16, 64))
    b = draw_text("KNITTING", shape=(16, 64))
    assert (a != b).sum() > 50


@pytest.mark.parametrize("bad", [(0, 10), (10, -1), (1, 1), "ab", (5000, 10)])
def test_bad_shapes_are_rejected(bad):
    with pytest.raises(ImageInputError, match="shape"):
        draw_heart(bad)


def test_empty_text_and_bad_options_are_rejected():
    with pytest.raises(ImageInputError, match="text"):
        draw_text("  ", shape=(10, 10))
    with pytest.raises(ImageInputError, match="margin"):
        draw_text("A", shape=(10, 10), margin=0.6)
    with pytest.raises(ImageInputError, match="arm"):
        draw_plus((10, 10), arm=1.5)
    with pytest.raises(UnknownNameError, match="heart"):
        draw_shape("star", (10, 10))


@pytest.mark.parametrize("name", ["astronaut", "coffee", "chelsea", "camera"])
def test_bundled_pictures_load_offline_as_float_rgb(name, monkeypatch):
    import socket

    def no_network(*a, **k):  # pragma: no cover - reaching this is the failure
        raise AssertionError("tried to use the network")

    monkeypatch.setattr(socket, "socket", no_network)
    img = skimage_image(name, (20, 30))
    assert img.shape == (20, 30, 3) and img.dtype == np.float64
    assert img.min() >= 0.0 and img.max() <= 1.0 and img.std() > 0.01


def test_all_bundled_names_exist_in_this_install(monkeypatch):
    import skimage.transform

    # Shrinking retina (1411 px) to 8 px anti-aliases with a Gaussian of sigma ~88 px: seconds
    # per picture, and not what this test checks (the tests above exercise anti-aliasing).
    resize = skimage.transform.resize

    def fast(*args, **kwargs):
        return resize(*args, **{**kwargs, "anti_aliasing": False})

    monkeypatch.setattr(skimage.transform, "resize", fast)
    for name in BUNDLED_IMAGES:
        assert skimage_image(name, (8, 8)).shape == (8, 8, 3)


def test_camera_is_grey():
    img = skimage_image("camera", (16, 16))
    assert np.allclose(img[..., 0], img[..., 1]) and np.allclose(img[..., 1], img[..., 2])


def test_unknown_picture_lists_valid_names():
    with pytest.raises(UnknownNameError, match="astronaut"):
        skimage_image("data_that_needs_download", (10, 10))


def test_index_images():
    m = np.array([[True, False], [False, True]])
    assert to_index_image(m).tolist() == [[0, 1], [1, 0]]
    assert to_index_image(m, invert=True).tolist() == [[1, 0], [0, 1]]
    assert to_index_image(m, ink=3, paper=2).dtype == np.int16
    lay = layer_masks([m, np.array([[True, True], [False, False]])])
    assert lay.tolist() == [[2, 2], [0, 1]]
    with pytest.raises(ImageInputError, match="masks"):
        layer_masks([m, np.ones((3, 3), bool)])
