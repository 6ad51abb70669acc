"""Hand-written gradients of the renderer against central finite differences."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.core.errors import OptionError
from illuknit.design.render.grad import render_value_and_grad, render_vjp
from illuknit.design.render.params import RenderParams
from illuknit.design.render.raycast import render_soft


def _fd(fun, x, eps=1e-6):
    out = np.zeros_like(x)
    for i in np.ndindex(x.shape):
        xp, xm = x.copy(), x.copy()
        xp[i] += eps
        xm[i] -= eps
        out[i] = (fun(xp) - fun(xm)) / (2 * eps)
    return out


@settings(max_examples=25, deadline=None)
@given(
    st.integers(1, 6),
    st.integers(1, 3),
    st.integers(1, 3),
    st.sampled_from(["A", "B", "headon"]),
    st.floats(5.0, 85.0),
    st.floats(0.3, 1.0),
    st.integers(1, 2),
    st.integers(0, 2**32 - 1),
)
def test_gradients_match_finite_differences(n, m, k, view, theta, shading, supersample, seed):
    rng = np.random.default_rng(seed)
    p = RenderParams(theta=theta, shading=shading)
    # Generic heights (no ties between projected edges), comfortably above flat_height.
    h = p.flat_height + 0.01 + rng.random((n, m)) * 1.5
    col = rng.random((n, m, k))
    target = rng.random((n * supersample, m, k))
    kw = {"params": p, "view": view, "supersample": supersample}
    _, _, gh, gc = render_value_and_grad(h, col, target, **kw)
    fh = _fd(lambda x: render_value_and_grad(x, col, target, **kw)[0], h)
    fc = _fd(lambda x: render_value_and_grad(h, x, target, **kw)[0], col)
    np.testing.assert_allclose(gh, fh, atol=1e-7, rtol=1e-5)
    np.testing.assert_allclose(gc, fc, atol=1e-7, rtol=1e-5)


def test_vjp_is_the_transpose_of_the_linear_color_map():
    """The image is linear in the colours, so <g, J c> == <J^T g, c> exactly."""
    rng = np.random.default_rng(2)
    h = 0.1 + rng.random((8, 5))
    col = rng.random((8, 5, 3))
    img, tape = render_soft(h, col, view="B", supersample=3, return_tape=True)
    g = rng.random(img.shape)
    _, gc = render_vjp(tape, g)
    assert np.isclose((g * img).sum(), (gc * col).sum())


def test_vjp_rejects_wrong_shape():
    _, tape = render_soft(np.ones((3, 2)), np.ones((3, 2, 3)), return_tape=True)
    with pytest.raises(OptionError, match="grad_image"):
        render_vjp(tape, np.ones((2, 2, 3)))
