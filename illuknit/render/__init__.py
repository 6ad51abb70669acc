"""Ray-casting renderer, its gradient, gradient-based design and calibration (paper sections 5, 8.3).

* :mod:`~illuknit.render.params` — :class:`RenderParams` and its JSON file;
* :mod:`~illuknit.render.raycast` — the closed-form renderer (:func:`render_views`, ...);
* :mod:`~illuknit.render.grad` — its vector-Jacobian product;
* :mod:`~illuknit.render.optimise` — gradient-descent design of a double-view pattern;
* :mod:`~illuknit.render.calibrate` — the calibration swatch and the bump-height fit.
"""

from illuknit.render.params import RenderParams, load_params, save_params
from illuknit.render.raycast import render_at, render_pattern, render_soft, render_views

__all__ = [
    "RenderParams",
    "load_params",
    "render_at",
    "render_pattern",
    "render_soft",
    "render_views",
    "save_params",
]
