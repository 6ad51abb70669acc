"""Deprecated: moved to :mod:`illuknit.design.models.backends.gradient` (design's own algorithms
register as backends; the solver layer knows no knitting)."""

from illuknit.solvers._moved import moved_module

__getattr__ = moved_module(__name__, "illuknit.design.models.backends.gradient")
