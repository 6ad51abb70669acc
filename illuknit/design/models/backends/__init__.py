"""The illusion models' own solver backends, registered with the solver layer.

The solver layer (:mod:`illuknit.solvers`) knows no knitting: it solves a
:class:`~illuknit.solvers.model.Model` as clauses and constraints. The algorithms here read the
model's payload, an :class:`~illuknit.design.models.illusion_problem.IllusionProblem`, and
register as backends (:func:`illuknit.solvers.register_backend`) and as warm starts
(:func:`illuknit.solvers.warm_start.register_warm_start`) when the design package loads, so
``solve(model, solver="dp")`` works for every model :func:`build_model` makes:

================  ====================================================================
module            what
================  ====================================================================
``dp``            exact dynamic programming per wale (and over row yarns for model (c))
``descent``       exact-block coordinate descent, wales and courses (heuristic)
``descent_blocks``  the knit-aware objective and its exact block updates
``lagrangian``    the Lagrangian lower bound of the knit-aware model
``gradient``      descent through the differentiable renderer (heuristic, no bound)
``warm_start``    the ``dp`` and ``descent`` warm starts of exact backends
================  ====================================================================

The backends are registered by name ("module:class") and imported only when used.
"""

from __future__ import annotations

from illuknit.design.models.backends.warm_start import IllusionWarmStarter
from illuknit.solvers import register_backend
from illuknit.solvers.warm_start import register_warm_start

__all__ = ["register"]


def register() -> None:
    """Register the DP, the descent and the gradient backends and the illusion warm starts
    (again: registering replaces, so calling it twice changes nothing)."""
    # preference order: the exact DP before every generic backend (``auto`` picks it for the
    # models it solves), the heuristics after the built-in exact ones
    register_backend("dp", f"{__name__}.dp:DPBackend", before="cpsat")
    register_backend("gradient", f"{__name__}.gradient:GradientBackend", after="fm")
    register_backend("descent", f"{__name__}.descent:DescentBackend", after="gradient")
    register_warm_start(IllusionWarmStarter())


register()
