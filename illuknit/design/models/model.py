"""Deprecated: moved to :mod:`illuknit.solvers.model` (the solver-neutral form lives in ``solvers/``)."""

from illuknit.solvers._moved import moved_module

__getattr__ = moved_module(__name__, "illuknit.solvers.model")
