"""The ray-casting renderer: coverage, agreement with can_see, parameters and bad input."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.core.errors import OptionError, PatternValidationError, RenderParamsError
from illuknit.core.pattern import LogicalPattern, Yarn
from illuknit.core.views import can_see, seen_rows
from illuknit.design.render.params import (
    RenderParams,
    load_params,
    params_from_json,
    save_params,
)
from illuknit.design.render.raycast import (
    coverage,
    heights_from_pattern,
    render_at,
    render_pattern,
    render_soft,
    render_views,
)

YARNS = (Yarn("white", (244, 240, 232)), Yarn("black", (27, 27, 27)), Yarn("red", (200, 30, 40)))


def _pattern(rng: np.random.Generator, n: int, m: int, p_raised: float = 0.4) -> LogicalPattern:
    return LogicalPattern(rng.integers(0, 3, (n, m)), rng.random((n, m)) < p_raised, YARNS)


def _exact_params(theta: float, *, excess: float = 0.0, flat: float = 0.1) -> RenderParams:
    """Bump relief = L tan(theta) (1 + excess): excess 0 is exactly can_see's geometry."""
    return RenderParams(
        flat_height=flat,
        bump_height=flat + math.tan(math.radians(theta)) * (1 + excess),
        theta=theta,
    )


patterns = st.tuples(
    st.integers(1, 9), st.integers(1, 5), st.integers(0, 2**32 - 1), st.floats(0.0, 1.0)
)


@settings(max_examples=60, deadline=None)
@given(patterns, st.floats(3.0, 80.0), st.sampled_from(["A", "B"]), st.integers(1, 3))
def test_coverage_sums_to_one(pat, theta, view, supersample):
    n, m, seed, frac = pat
    rng = np.random.default_rng(seed)
    p = RenderParams(theta=theta)
    h = p.flat_height + rng.random((n, m)) * frac * 3
    cov = coverage(h, params=p, view=view, supersample=supersample)
    assert cov.shape == (n * supersample, m, n)
    assert cov.min() >= -1e-12
    np.testing.assert_allclose(cov.sum(-1), 1.0, atol=1e-9)


@settings(max_examples=60, deadline=None)
@given(patterns, st.floats(5.0, 60.0), st.sampled_from(["A", "B"]))
def test_exact_geometry_equals_can_see(pat, theta, view):
    """With bump relief L tan(theta) every pixel shows exactly the unit can_see names."""
    n, m, seed, frac = pat
    pattern = _pattern(np.random.default_rng(seed), n, m, frac)
    p = _exact_params(theta)
    cov = coverage(heights_from_pattern(pattern, p), params=p, view=view)
    np.testing.assert_allclose(cov.max(-1), 1.0, atol=1e-9)
    assert np.array_equal(cov.argmax(-1), seen_rows(pattern.raised, view))
    img = render_pattern(pattern, params=p, view=view)
    assert np.array_equal(img, pattern.palette[can_see(pattern, view)])


@settings(max_examples=60, deadline=None)
@given(patterns, st.floats(2.0, 45.0), st.floats(0.0, 0.49), st.sampled_from(["A", "B"]))
def test_tall_bumps_low_angle_agree_with_can_see(pat, theta, excess, view):
    """Taller bumps (or lower angles) than exact, up to half a unit more: the unit covering most
    of each pixel is still the one can_see names."""
    n, m, seed, frac = pat
    pattern = _pattern(np.random.default_rng(seed), n, m, frac)
    p = _exact_params(theta, excess=excess)
    cov = coverage(heights_from_pattern(pattern, p), params=p, view=view)
    assert np.array_equal(cov.argmax(-1), seen_rows(pattern.raised, view))
    assert cov.max(-1).min() > 0.5


def test_headon_shows_every_unit_and_ignores_heights():
    pattern = _pattern(np.random.default_rng(3), 6, 4)
    out = render_views(pattern)
    assert set(out) == {"A", "B", "headon"}
    assert np.array_equal(out["headon"], pattern.palette[pattern.yarn])
    for img in out.values():
        assert img.dtype == np.uint8 and img.shape == (6, 4, 3)


def test_tall_bump_hides_the_rest_of_the_wale():
    # One very tall bump in row 0: from above (A) it hides everything behind it.
    yarn = np.array([[1], [0], [0], [0]])
    raised = np.array([[True], [False], [False], [False]])
    pattern = LogicalPattern(yarn, raised, YARNS)
    p = RenderParams(flat_height=0.1, bump_height=50.0, theta=30)
    assert np.all(render_pattern(pattern, params=p, view="A") == YARNS[1].rgb)
    # From below the bump is at the far end and hides nothing.
    assert np.array_equal(render_pattern(pattern, params=p, view="B"), pattern.palette[yarn])


def test_shading_darkens_only_side_views():
    pattern = LogicalPattern(np.zeros((5, 3), int), np.ones((5, 3), bool), YARNS)
    plain = render_views(pattern, params=RenderParams(bump_height=2.0))
    shaded = render_views(pattern, params=RenderParams(bump_height=2.0, shading=0.5))
    assert np.array_equal(plain["headon"], shaded["headon"])
    assert shaded["A"].astype(int).sum() < plain["A"].astype(int).sum()


def test_render_at_signs_and_supersample():
    pattern = _pattern(np.random.default_rng(5), 7, 3)
    p = RenderParams()
    assert np.array_equal(
        render_at(pattern, 30, params=p), render_pattern(pattern, params=p, view="A", angle=30)
    )
    assert np.array_equal(
        render_at(pattern, -30, params=p), render_pattern(pattern, params=p, view="B", angle=30)
    )
    assert np.array_equal(render_at(pattern, -90, params=p), pattern.palette[pattern.yarn])
    assert render_pattern(pattern, params=p, supersample=4).shape == (28, 3, 3)


def test_supersampled_pixels_average_to_unit_pixels():
    rng = np.random.default_rng(9)
    h = 0.1 + rng.random((6, 4))
    col = rng.random((6, 4, 3))
    one = render_soft(h, col, view="B")
    four = render_soft(h, col, view="B", supersample=4)
    np.testing.assert_allclose(four.reshape(6, 4, 4, 3).mean(1), one, atol=1e-12)


# -- parameters --------------------------------------------------------------------------------


def test_params_round_trip(tmp_path):
    p = RenderParams(flat_height=0.2, bump_height=0.9, unit_length=1.5, theta=40, shading=0.8)
    save_params(p, tmp_path / "p.json")
    assert load_params(tmp_path / "p.json") == p
    assert params_from_json({"bump_height": 2}) == RenderParams(bump_height=2.0)


@pytest.mark.parametrize(
    ("doc", "message"),
    [
        ({"colour": 1}, "unknown render parameter"),
        ({"theta": "30"}, "`theta` must be a number"),
        ({"theta": True}, "`theta` must be a number"),
        ({"theta": 0}, "(0, 90]"),
        ({"theta": 90.5}, "(0, 90]"),
        ({"theta": -30}, "(0, 90]"),
        ({"flat_height": 0}, "`flat_height` must be positive"),
        ({"bump_height": -1}, "`bump_height` must be positive"),
        ({"unit_length": 0}, "`unit_length` must be positive"),
        ({"bump_height": 0.05}, "must exceed `flat_height`"),
        ({"shading": 0}, "`shading`"),
        ({"format": "other"}, "`format`"),
        ({"version": 2}, "`version`"),
        ([1, 2], "JSON object"),
    ],
)
def test_bad_params_are_rejected(doc, message):
    with pytest.raises(RenderParamsError, match=re_escape(message)):
        params_from_json(doc)


def re_escape(s: str) -> str:
    import re

    return re.escape(s)


def test_bad_params_files(tmp_path):
    with pytest.raises(RenderParamsError, match="not found"):
        load_params(tmp_path / "missing.json")
    (tmp_path / "bad.json").write_text("{nope")
    with pytest.raises(RenderParamsError, match="not valid JSON"):
        load_params(tmp_path / "bad.json")
    (tmp_path / "unknown.json").write_text(json.dumps({"bump": 1}))
    with pytest.raises(RenderParamsError, match=r"unknown\.json.*'bump'"):
        load_params(tmp_path / "unknown.json")


def test_bad_render_input():
    pattern = _pattern(np.random.default_rng(1), 3, 3)
    with pytest.raises(RenderParamsError, match="angle"):
        render_views(pattern, angle=0)
    with pytest.raises(RenderParamsError, match="angle"):
        render_views(pattern, angle=120)
    with pytest.raises(RenderParamsError, match="angle"):
        render_at(pattern, 0)
    with pytest.raises(OptionError, match="view"):
        render_pattern(pattern, view="C")  # type: ignore[arg-type]
    with pytest.raises(PatternValidationError, match="flat_height"):
        render_soft(np.zeros((2, 2)), np.zeros((2, 2, 3)))
    with pytest.raises(PatternValidationError, match="colors"):
        render_soft(np.ones((2, 2)), np.zeros((3, 2, 3)))
    with pytest.raises(OptionError, match="supersample"):
        render_soft(np.ones((2, 2)), np.zeros((2, 2, 3)), supersample=0)


def test_sweep_angles_walk_from_a_through_headon_to_b():
    from illuknit.design.render.raycast import render_image, sweep_angles

    angles = sweep_angles(30, 5)
    assert angles == [30.0, 60.0, 90.0, -60.0, -30.0]
    assert 90.0 in sweep_angles(20, 3) and len(sweep_angles(20, 4)) == 4
    with pytest.raises(RenderParamsError, match="frames"):
        sweep_angles(30, 1)
    with pytest.raises(RenderParamsError, match="angle"):
        sweep_angles(0, 5)
    pattern = _pattern(np.random.default_rng(2), 4, 3)
    img = render_image(pattern, -30, scale=3)
    assert img.shape == (12, 9, 3)
    assert np.array_equal(img[:, ::3][::3], render_at(pattern, -30, supersample=3)[::3])
