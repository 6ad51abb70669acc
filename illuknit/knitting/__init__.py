"""Knitting a pattern for a machine in one call, measured on the machine that runs it."""

from illuknit.knitting.pipeline import KnitResult, knit_pattern

__all__ = ["KnitResult", "knit_pattern"]
