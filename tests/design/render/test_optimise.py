"""Gradient-descent design through the renderer."""

from __future__ import annotations

import numpy as np
import pytest

from illuknit.core.errors import ImageInputError, OptionError, YarnSpecError
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.core.views import can_see, logical_error
from illuknit.design.render.optimise import DesignStep, optimise_design, targets_to_indices
from illuknit.design.render.params import RenderParams
from illuknit.pictures.drawings import draw_text

YARNS = parse_yarns("white,black")


def _texts(shape=(12, 16)):
    return draw_text("HI", shape=shape).astype(int), draw_text("OK", shape=shape).astype(int)


def test_optimiser_lowers_the_loss_on_a_text_pair():
    ta, tb = _texts()
    params = RenderParams()
    steps: list[DesignStep] = []
    res = optimise_design(
        ta, tb, YARNS, params=params.with_angle(params.exact_angle), steps=80, callback=steps.append
    )
    assert len(steps) == 80 == len(res.history)
    assert res.history[-1] < 0.6 * res.history[0]
    assert isinstance(res.pattern, LogicalPattern) and res.pattern.shape == ta.shape
    after = res.report["after"]
    # The reported logical error is can_see's, and beats a blank pattern (all white, flat).
    ea = logical_error(can_see(res.pattern, "A"), ta)
    eb = logical_error(can_see(res.pattern, "B"), tb)
    assert after["logical_error"] == pytest.approx((ea + eb) / 2)
    blank = (ta.mean() + tb.mean()) / 2
    assert after["logical_error"] < 0.7 * blank
    for part in ("before", "after"):
        assert set(res.report[part]) >= {"loss", "render_error", "logical_error"}


def test_rgb_targets_and_color_change_penalty_reduce_changes():
    ta, tb = _texts((10, 12))
    pal = np.array([y.rgb for y in YARNS], dtype=np.uint8)
    free = optimise_design(pal[ta], pal[tb], YARNS, steps=40, seed=1)
    calm = optimise_design(pal[ta], pal[tb], YARNS, steps=40, seed=1, change_weight=2.0)

    def changes(p):
        return int((p.yarn[:, 1:] != p.yarn[:, :-1]).sum())

    assert changes(calm.pattern) <= changes(free.pattern)


def test_targets_to_indices_maps_rgb_to_nearest_yarn():
    rgb = np.array([[[250, 250, 250], [10, 10, 10]]], dtype=np.uint8)
    assert targets_to_indices(rgb, YARNS).tolist() == [[0, 1]]


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"target_b": np.zeros((3, 4), int)}, ImageInputError, "same"),
        ({"target_a": np.full((4, 4), 5)}, ImageInputError, "0..1"),
        ({"target_a": np.zeros((4, 4), float)}, ImageInputError, "integers"),
        ({"target_a": np.zeros((4, 4, 4), np.uint8)}, ImageInputError, "shape"),
        ({"yarns": YARNS[:1]}, YarnSpecError, "two"),
        ({"steps": 0}, OptionError, "steps"),
        ({"learning_rate": -1.0}, OptionError, "learning_rate"),
        ({"final_temperature": 0.0}, OptionError, "final_temperature"),
    ],
)
def test_bad_design_input(kwargs, error, message):
    args = {"target_a": np.zeros((4, 4), int), "target_b": np.zeros((4, 4), int), "yarns": YARNS}
    args.update(kwargs)
    with pytest.raises(error, match=message):
        optimise_design(
            args.pop("target_a"),
            args.pop("target_b"),
            args.pop("yarns"),
            steps=args.pop("steps", 2),
            **args,
        )


def test_objective_gradient_matches_finite_differences():
    """The whole design objective (renders at +-theta, penalties, sigmoid/softmax) by FD."""
    from illuknit.design.render.optimise import _Objective

    rng = np.random.default_rng(4)
    n, m, k = 5, 4, 3
    pal = rng.random((k, 3))
    obj = _Objective(
        rng.random((n, m, 3)),
        rng.random((n, m, 3)),
        pal,
        RenderParams(theta=35, shading=0.7),
        0.3,
        0.2,
    )
    z = rng.normal(0, 1, (n, m))
    u = rng.normal(0, 1, (n, m, k))
    tau, bw = 0.7, 0.4
    _, _, gz, gu, _, _ = obj(z, u, tau, bw)
    eps = 1e-6
    for x, g, which in ((z, gz, 0), (u, gu, 1)):
        fd = np.zeros_like(x)
        for i in np.ndindex(x.shape):
            xp, xm = x.copy(), x.copy()
            xp[i] += eps
            xm[i] -= eps
            args_p = (xp, u) if which == 0 else (z, xp)
            args_m = (xm, u) if which == 0 else (z, xm)
            fd[i] = (obj(*args_p, tau, bw)[0] - obj(*args_m, tau, bw)[0]) / (2 * eps)
        np.testing.assert_allclose(g, fd, atol=1e-7, rtol=1e-5)


def test_pinned_units_keep_their_yarn_and_yarn_mix():
    ta, tb = _texts((8, 10))
    pinned = np.full(ta.shape, -1)
    pinned[::2, ::3] = 1
    res = optimise_design(ta, tb, YARNS, steps=30, mix="yarn", pinned=pinned)
    assert np.all(res.pattern.yarn[pinned >= 0] == 1)
    with pytest.raises(OptionError, match="mix"):
        optimise_design(ta, tb, YARNS, steps=2, mix="lab")
    with pytest.raises(OptionError, match="pinned"):
        optimise_design(ta, tb, YARNS, steps=2, pinned=np.full(ta.shape, 7))


def test_the_keywords_are_a_shorthand_for_gradient_options():
    """``steps=3, mix="yarn"`` is ``options=GradientOptions(steps=3, mix="yarn")``; a keyword
    replaces the field of ``options``; an unknown one is refused, named."""
    from illuknit.design.render.gradient_options import GradientOptions

    ta, tb = _texts((6, 8))
    by_keywords = optimise_design(ta, tb, YARNS, steps=3, mix="yarn")
    by_options = optimise_design(ta, tb, YARNS, options=GradientOptions(steps=3, mix="yarn"))
    overridden = optimise_design(
        ta, tb, YARNS, options=GradientOptions(steps=9), steps=3, mix="yarn"
    )
    for res in (by_options, overridden):
        assert np.array_equal(res.raised_soft, by_keywords.raised_soft)
        assert np.array_equal(res.pattern.yarn, by_keywords.pattern.yarn)
    with pytest.raises(OptionError, match="stepz"):
        optimise_design(ta, tb, YARNS, stepz=3)
    with pytest.raises(OptionError, match="`options`"):
        optimise_design(ta, tb, YARNS, options={"steps": 3})
    with pytest.raises(OptionError, match="`mix`"):
        GradientOptions(mix="cmyk")
