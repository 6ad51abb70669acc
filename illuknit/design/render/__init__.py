"""Ray-casting renderer, its gradient, gradient-based design and calibration (paper sections 5, 8.3).

* :mod:`~illuknit.design.render.params` — :class:`RenderParams` and its JSON file;
* :mod:`~illuknit.design.render.raycast` — the closed-form renderer (:func:`render_views`, ...);
* :mod:`~illuknit.design.render.grad` — its vector-Jacobian product;
* :mod:`~illuknit.design.render.optimise` — gradient-descent design of a double-view pattern;
* :mod:`~illuknit.design.render.calibrate` — the calibration swatch and the bump-height fit.
"""

from illuknit.design.render.params import RenderParams, load_params, save_params
from illuknit.design.render.raycast import render_at, render_pattern, render_soft, render_views

__all__ = [
    "RenderParams",
    "load_params",
    "render_at",
    "render_pattern",
    "render_soft",
    "render_views",
    "save_params",
]
