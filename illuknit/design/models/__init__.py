"""Constraint models of illusion patterns, solver-neutral, and their solutions."""
