"""Warm starts as an explicit policy, solver-neutral: what :func:`illuknit.solvers.solve` runs
before a backend that accepts one (``Backend.accepts_warm_start``).

The policies themselves belong to the domain that built the model: a domain registers a
:class:`WarmStarter` for its :class:`~illuknit.solvers.model.DomainPayload` type
(:func:`register_warm_start`; design's illusion models register ``dp`` and ``descent`` in
:mod:`illuknit.design.models.backends.warm_start`). This module only finds the starter of a
model, and afterwards (:func:`keep_warm_start`) keeps the warm start's assignment where the
backend came back worse or with nothing, saying so: the solution's ``found_by`` then names the
warm start, not the backend.

The policy ``none`` (nothing: the backend's answer is its own) always exists; ``auto`` asks the
model's starter, and means ``none`` for a model no starter is registered for.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Protocol

import numpy as np
from numpy.typing import NDArray

from illuknit.core.errors import SolverError, UnknownNameError
from illuknit.solvers._moved import moved_module
from illuknit.solvers.base import Solution, Status
from illuknit.solvers.stats import SolveStats, WarmStartInfo

if TYPE_CHECKING:
    from illuknit.solvers.model import DomainPayload, Model

__all__ = [
    "WarmStartInfo",
    "WarmStarter",
    "keep_warm_start",
    "make_warm_start",
    "register_warm_start",
    "resolve_policy",
    "warm_start_policies",
]


class WarmStarter(Protocol):
    """The warm starts of one domain payload type."""

    @property
    def payload(self) -> type[DomainPayload]:
        """The payload type of the models it starts (``isinstance(model.problem, payload)``)."""
        ...

    @property
    def policies(self) -> tuple[str, ...]:
        """The policy names it answers to, besides ``none`` and ``auto``."""
        ...

    @property
    def needs(self) -> str:
        """What a model must be for these policies, for messages ("an illusion model")."""
        ...

    def resolve(self, policy: str, model: Model) -> str:
        """The concrete policy (``none`` or one of :attr:`policies`) ``policy`` means here."""
        ...

    def make(
        self, model: Model, policy: str, *, time_limit: float | None, seed: int
    ) -> tuple[NDArray[np.bool_], WarmStartInfo]:
        """The warm start ``policy`` of ``model``: an assignment indexed by variable id."""
        ...


_starters: list[WarmStarter] = []


def register_warm_start(starter: WarmStarter) -> None:
    """Register the warm starts of a payload type (replacing an earlier one for that type)."""
    _starters[:] = [s for s in _starters if s.payload is not starter.payload]
    _starters.append(starter)


def warm_start_policies() -> tuple[str, ...]:
    """Every policy name: ``none``, the registered starters' policies, ``auto``."""
    names = [p for s in _starters for p in s.policies]
    return ("none", *dict.fromkeys(names), "auto")


def _starter_of(model: Model) -> WarmStarter | None:
    for s in _starters:
        if isinstance(model.problem, s.payload):
            return s
    return None


def resolve_policy(policy: str, model: Model) -> str:
    """The concrete policy (``none`` or a starter's) ``policy`` means for ``model``.

    Raises
    ------
    UnknownNameError
        ``policy`` is not one of :func:`warm_start_policies`.
    SolverError
        A warm start was asked for a model its starter does not start.
    """
    policies = warm_start_policies()
    if policy not in policies:
        raise UnknownNameError("warm start", policy, policies)
    if policy == "none":
        return "none"
    starter = _starter_of(model)
    if starter is None or (policy != "auto" and policy not in starter.policies):
        if policy == "auto":
            return "none"
        needs = next(s.needs for s in _starters if policy in s.policies)
        raise SolverError(f"warm start {policy!r} needs {needs} (model {model.name!r})")
    return starter.resolve(policy, model)


def make_warm_start(
    model: Model, policy: str, *, time_limit: float | None = None, seed: int = 0
) -> tuple[NDArray[np.bool_], WarmStartInfo]:
    """The warm start ``policy`` (a concrete one, see :func:`resolve_policy`) of ``model``.

    Raises
    ------
    SolverError
        No starter of ``model`` has the policy ``policy``.
    """
    starter = _starter_of(model)
    if starter is None or policy not in starter.policies:
        raise SolverError(f"no warm start {policy!r} for model {model.name!r}")
    return starter.make(model, policy, time_limit=time_limit, seed=seed)


def keep_warm_start(model: Model, solution: Solution, info: WarmStartInfo) -> Solution:
    """``solution`` timed from before the warm start and, if the backend came back worse than
    its warm start (``model.hint``) or with nothing, the warm start's assignment instead
    (``found_by`` the warm start); the bound is the better of the backend's and the warm
    start's (``info.bound``)."""
    ws = info.seconds
    values, objective, status = solution.values, solution.objective, solution.status
    found_by, found_at = solution.found_by, solution.found_at
    found_at = None if found_at is None else found_at + ws
    kept = False
    if model.hint is not None and status in (Status.FEASIBLE, Status.TIMEOUT):
        hint = np.asarray(model.hint, dtype=bool)
        ok, cost = model.evaluate(hint)
        if ok and (objective is None or cost < objective):
            values, objective = hint, cost
            found_by, found_at = info.method, ws
            kept = True
        elif values is not None and np.array_equal(values[: hint.size], hint[: values.size]):
            # the backend handed the hint back (e.g. RC2's timeout fallback): credit the hint
            found_by, found_at = info.method, ws
            kept = True
    bound = solution.bound
    if info.bound is not None and status in (Status.FEASIBLE, Status.TIMEOUT):
        bound = max(float(info.bound), bound if bound is not None else float("-inf"))
        if objective is not None and objective <= bound:
            status = Status.OPTIMAL  # the warm start met a proven lower bound
    trace = [(t + ws, o, b) for t, o, b in solution.trace]
    if info.objective is not None:
        trace.insert(0, (ws, float(info.objective), info.bound))
    return replace(
        solution,
        status=status,
        values=values,
        objective=objective,
        bound=bound,
        wall_time=solution.wall_time + ws,
        stats=SolveStats(solution.stats, info, kept),
        found_by=found_by,
        found_at=found_at,
        trace=tuple(trace),
    )


# the illusion models' policies and constants lived here until they moved to design
__getattr__ = moved_module(__name__, "illuknit.design.models.backends.warm_start")
