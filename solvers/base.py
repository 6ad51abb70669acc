"""The contract every solver backend implements: ``Status``, ``Solution``, ``Backend``.

A backend takes an :class:`illuknit.solvers.model.Model` (solver-neutral data) and returns a frozen
:class:`Solution`:

* ``status`` — :class:`Status`: ``optimal`` (proven), ``feasible`` (an assignment, optimality not
  proven, e.g. interrupted by Ctrl-C), ``timeout`` (time limit reached; ``values`` holds the best
  assignment found if any, ``bound`` the best proven lower bound), ``infeasible`` (the hard
  constraints cannot hold; ``stats["infeasible_families"]`` may name the conflicting families),
  ``error`` (the backend failed; ``stats["message"]`` says why).
* ``values`` — bool ndarray indexed by variable id (index 0 unused, length ``pool.top + 1``), or
  ``None`` when nothing was found. ``solution.value(key)`` and ``solution.block(name)`` read it
  through the model's pool.
* ``objective`` — total weight of violated soft clauses (+ ``model.offset``) of ``values``.
* ``bound`` — proven lower bound on the optimum (equals ``objective`` when optimal).
* ``wall_time`` (seconds) and backend-specific ``stats``.
* ``found_by`` — who produced ``values``: the backend's name, or the warm start (``dp``,
  ``descent``) when the backend came back with nothing better; ``found_at`` — seconds after the
  start of the solve (warm start included) at which that assignment was found;
  ``finished_at`` — the UTC time the solve ended (ISO 8601).
* ``trace`` — the anytime trace: ``(seconds, objective, bound)`` for every improvement reported.

Backends must honour ``time_limit`` (seconds, ``None`` = no limit) and return the best assignment
found when it expires — never nothing when something was found — and should catch
``KeyboardInterrupt`` the same way (status ``feasible``/``timeout``, ``stats["interrupted"]``).
``progress``, when given, is called with a :class:`ProgressEvent` whenever the objective or bound
improves.
"""

from __future__ import annotations

import importlib.util
import time
from collections.abc import Callable, Hashable, Mapping
from dataclasses import dataclass, field
from datetime import UTC, datetime
from enum import StrEnum
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Protocol, Self, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from illuknit.core.errors import UnknownNameError
from illuknit.solvers.stats import SolveStats

if TYPE_CHECKING:
    from illuknit.solvers.model import Model
    from illuknit.solvers.var_pool import VarPool

__all__ = [
    "ORACLES",
    "Backend",
    "BackendBase",
    "BackendKind",
    "OracleBackendBase",
    "ProgressCallback",
    "ProgressEvent",
    "Solution",
    "Status",
    "TracePoint",
    "assignment_from_lits",
    "check_oracle",
    "fallback_assignment",
    "interrupt_types",
]


class Status(StrEnum):
    """Outcome of a solve."""

    OPTIMAL = "optimal"
    FEASIBLE = "feasible"
    TIMEOUT = "timeout"
    INFEASIBLE = "infeasible"
    ERROR = "error"


class BackendKind(StrEnum):
    """How a backend searches: what :func:`illuknit.solvers.describe_backends` lists it as."""

    #: a MaxSAT solver on the model's clauses (complete, or anytime when not ``exact``)
    MAXSAT = "maxsat"
    #: a constraint-programming solver on the model's native constraints
    CP = "cp"
    #: a local search (no proof of optimality)
    LOCAL_SEARCH = "local search"
    #: an algorithm of the domain that built the model, reading its payload
    #: (:class:`illuknit.solvers.model.DomainPayload`)
    DOMAIN = "domain"


@dataclass(frozen=True)
class ProgressEvent:
    """A progress report: elapsed seconds, best objective so far, best lower bound so far."""

    elapsed: float
    objective: float | None = None
    bound: float | None = None
    message: str = ""


ProgressCallback = Callable[[ProgressEvent], None]

#: One point of an anytime trace: (seconds since the start, objective or None, bound or None).
TracePoint = tuple[float, float | None, float | None]


def utc_now() -> str:
    """The current UTC time, ISO 8601 to the second."""
    return datetime.now(UTC).isoformat(timespec="seconds")


@dataclass(frozen=True, eq=False)
class Solution:
    """The answer of one backend on one model (see the module docstring for each field)."""

    status: Status
    values: NDArray[np.bool_] | None
    objective: int | float | None
    bound: float | None
    wall_time: float
    stats: Mapping[str, Any] = field(default_factory=dict)
    backend: str = ""
    pool: VarPool | None = field(default=None, repr=False)
    found_by: str = ""
    found_at: float | None = None
    finished_at: str = ""
    trace: tuple[TracePoint, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "status", Status(self.status))
        if self.values is not None:
            if not self.found_by:
                object.__setattr__(self, "found_by", self.backend)
            if self.found_at is None:
                object.__setattr__(self, "found_at", float(self.wall_time))
        if not self.finished_at:
            object.__setattr__(self, "finished_at", utc_now())
        object.__setattr__(self, "trace", tuple(self.trace))
        if self.values is not None:
            v = np.asarray(self.values, dtype=bool)
            v.setflags(write=False)
            object.__setattr__(self, "values", v)
        if not isinstance(self.stats, SolveStats):
            object.__setattr__(self, "stats", MappingProxyType(dict(self.stats)))

    @property
    def solve_stats(self) -> SolveStats | None:
        """The typed statistics :func:`illuknit.solvers.solve` recorded in ``stats`` (None for
        the raw answer of a backend called directly)."""
        return self.stats if isinstance(self.stats, SolveStats) else None

    @property
    def has_values(self) -> bool:
        """True when an assignment was found (optimal, feasible, or timeout with a solution)."""
        return self.values is not None

    @property
    def gap(self) -> float | None:
        """Relative optimality gap ``(objective - bound) / max(1, objective)``, if both known."""
        if self.objective is None or self.bound is None:
            return None
        return max(0.0, float(self.objective) - float(self.bound)) / max(1.0, float(self.objective))

    def value(self, key: Hashable) -> bool:
        """Truth value of the variable named ``key`` (or of a literal given as an int)."""
        if self.values is None:
            raise ValueError(f"no assignment (status {self.status.value})")
        if isinstance(key, int | np.integer):
            lit = int(key)
            return bool(self.values[abs(lit)]) == (lit > 0)
        if self.pool is None:
            raise ValueError("this solution has no variable pool; look values up by id")
        vid = self.pool.get(key)
        if vid is None:
            raise KeyError(f"no variable named {key!r}")
        return bool(self.values[vid])

    def block(self, name: Hashable) -> NDArray[np.bool_]:
        """Truth values of a variable block, in the block's shape."""
        if self.values is None:
            raise ValueError(f"no assignment (status {self.status.value})")
        if self.pool is None:
            raise ValueError("this solution has no variable pool")
        return self.values[self.pool.block_ids(name)]

    def summary(self) -> dict[str, Any]:
        """JSON-ready summary (no assignment)."""
        return {
            "backend": self.backend,
            "status": self.status.value,
            "objective": self.objective,
            "bound": self.bound,
            "gap": self.gap,
            "wall_time": round(self.wall_time, 4),
            "found_by": self.found_by,
            "found_at": None if self.found_at is None else round(self.found_at, 4),
            "finished_at": self.finished_at,
            "stats": {k: v for k, v in self.stats.items() if _jsonable(v)},
        }


def _jsonable(v: Any) -> bool:
    return isinstance(v, str | int | float | bool | list | tuple | dict) or v is None


@runtime_checkable
class Backend(Protocol):
    """What every solver backend provides.

    ``extra`` names the optional dependency set (``pip install 'illuknit[EXTRA]'``) that makes an
    unavailable backend available, or ``None`` when it needs only the runtime dependencies.
    ``exact`` is True when status ``optimal`` is a proof (heuristics such as ``gradient`` set it
    False and report only ``feasible``/``timeout``); conformance suites that demand optima skip
    backends with ``exact = False``.

    Capabilities are declared flags, which :func:`illuknit.solvers.solve` dispatches on (see
    :class:`BackendBase` for each): ``kind`` (:class:`BackendKind`), ``exact``, ``proves_bound``,
    ``accepts_warm_start``, ``accepts_lower_bound`` and ``time_limited``.
    """

    name: str
    extra: str | None
    kind: BackendKind
    exact: bool
    proves_bound: bool
    accepts_warm_start: bool
    accepts_lower_bound: bool
    time_limited: bool

    def handles(self, model: Model) -> bool:
        """Whether this backend can solve ``model`` (e.g. the DP needs an illusion problem)."""
        ...

    def why_not(self, model: Model) -> str | None:
        """Why this backend cannot solve ``model``, or None when it can."""
        ...

    def is_available(self) -> bool:
        """Whether the libraries (or binaries) it needs are installed."""
        ...

    def unavailable_reason(self) -> str | None:
        """Why it is not available (what to install), or None when it is."""
        ...

    def version(self) -> str:
        """The version of the solver library or binary it runs ("" when unknown)."""
        ...

    def solve(
        self,
        model: Model,
        *,
        time_limit: float | None = None,
        seed: int = 0,
        progress: ProgressCallback | None = None,
    ) -> Solution:
        """Solve ``model``; see the module docstring for the meaning of the result."""
        ...


class BackendBase:
    """The shared part of every built-in backend: availability from the modules it ``requires``,
    ``handles`` from ``why_not``, the version of its ``distribution``, and building the
    :class:`Solution`. Subclasses set the class attributes and implement ``solve``."""

    name: str = ""
    extra: str | None = None
    kind: BackendKind = BackendKind.MAXSAT
    #: True when status ``optimal`` is a proof
    exact: bool = True
    #: True when the ``bound`` it reports is a proven lower bound of the objective
    proves_bound: bool = True
    #: True when a warm start applies: :func:`illuknit.solvers.solve` runs the warm-start policy
    #: first and hands its assignment over as ``model.hint`` (False for the algorithms the warm
    #: starts themselves run)
    accepts_warm_start: bool = True
    #: True when the solver itself stops at ``time_limit`` and hands back what it has; False
    #: when only a kill from outside stops it (the benchmark then enforces the limit, and says
    #: so in ``--list-solvers``)
    time_limited: bool = True
    #: True when ``solve`` takes ``lower_bound=`` (a proven lower bound of the objective, e.g.
    #: the knit-aware model's Lagrangian bound from a warm start) and uses it in its search;
    #: :func:`illuknit.solvers.solve` hands it to such backends only
    accepts_lower_bound: bool = False
    #: importable modules the backend needs (probed with importlib.util.find_spec, not imported)
    requires: tuple[str, ...] = ()
    #: the PyPI distribution whose version :meth:`version` reports
    distribution: str | None = None

    @classmethod
    def from_name(cls, name: str, argument: str | None) -> Self | None:
        """The backend the registry makes for ``name`` (the registered name) and ``argument``
        (what followed a colon, or None), or None when it takes no such argument."""
        return cls() if argument is None else None

    def why_not(self, model: Model) -> str | None:
        return None

    def handles(self, model: Model) -> bool:
        return self.why_not(model) is None

    def unavailable_reason(self) -> str | None:
        for mod in self.requires:
            try:
                found = importlib.util.find_spec(mod) is not None
            except (ImportError, ValueError):
                found = False
            if not found:
                how = (
                    f"pip install 'illuknit[{self.extra}]'" if self.extra else "see docs/solvers.md"
                )
                return f"needs the Python module {mod!r} ({how})"
        return None

    def is_available(self) -> bool:
        return self.unavailable_reason() is None

    def version(self) -> str:
        if self.distribution is None:
            from illuknit import __version__

            return f"illuknit {__version__}"
        from importlib.metadata import PackageNotFoundError
        from importlib.metadata import version as dist_version

        try:
            return f"{self.distribution} {dist_version(self.distribution)}"
        except PackageNotFoundError:
            return ""

    def solution(
        self,
        model: Model,
        status: Status,
        t0: float,
        values: NDArray[np.bool_] | None = None,
        objective: int | float | None = None,
        bound: float | None = None,
        stats: Mapping[str, Any] | None = None,
        *,
        found_at: float | None = None,
    ) -> Solution:
        """A :class:`Solution` of this backend, timed from ``t0`` (``time.perf_counter()``)."""
        return Solution(
            status,
            values,
            objective,
            bound,
            time.perf_counter() - t0,
            stats or {},
            self.name,
            model.pool,
            found_at=found_at,
        )

    def child_failure(
        self, model: Model, res: Any, t0: float, stats: dict[str, Any]
    ) -> Solution | None:
        """The Solution of a child run (:func:`illuknit.solvers.isolate.run_in_child`) that
        returned nothing -- status ``timeout`` or ``error`` with its reason -- else None."""
        if res.status == "ok":
            return None
        stats["message"] = res.reason
        status = Status.TIMEOUT if res.status == "timeout" else Status.ERROR
        return self.solution(model, status, t0, stats=stats)

    def checked_assignment(
        self, model: Model, lits: Any, claimed: int, t0: float, stats: dict[str, Any], *, who: str
    ) -> tuple[NDArray[np.bool_], int, Solution | None]:
        """The solver's model as an assignment with its cost recomputed by ``model``; records
        the claimed cost in ``stats``. The third item is an ``error`` Solution when the
        assignment violates hard clauses (``who`` names the culprit in its message), else None."""
        values = assignment_from_lits(lits, model.pool.top)
        ok, cost = model.evaluate(values)
        stats["claimed_cost"] = claimed + int(model.offset)
        if ok:
            return values, cost, None
        stats["message"] = f"{who} assignment violates hard clauses"
        return values, cost, self.solution(model, Status.ERROR, t0, values, cost, stats=stats)


def assignment_from_lits(lits: Any, top: int) -> NDArray[np.bool_]:
    """Bool array (top + 1,) indexed by variable id from a DIMACS model (list of literals)."""
    v = np.zeros(top + 1, dtype=bool)
    a = np.asarray(list(lits) if lits is not None else [], dtype=np.int64)
    a = a[(a > 0) & (a <= top)]
    v[a] = True
    return v


def fallback_assignment(
    model: Model, *, budget: float = 5.0
) -> tuple[NDArray[np.bool_] | None, int | None]:
    """A feasible assignment when an optimiser found none in time: the model's hint if it is
    feasible, else one plain SAT call on the hard constraints (at most ``budget`` seconds).

    Returns (values, objective) or (None, None).
    """
    hint = model.hint
    if hint is not None:
        ok, cost = model.evaluate(hint)
        if ok:
            return np.asarray(hint, dtype=bool), cost
    from threading import Timer

    from pysat.solvers import Solver

    cs = model.to_clauses()
    with Solver(name="g4", bootstrap_with=cs.hard) as s:
        timer = Timer(max(0.1, budget), s.interrupt)
        timer.start()
        try:
            res = s.solve_limited(expect_interrupt=True)
        finally:
            timer.cancel()
        if not res:
            return None, None
        v = assignment_from_lits(s.get_model(), model.pool.top)
    ok, cost = model.evaluate(v)
    return (v, cost) if ok else (None, None)


#: SAT oracles python-sat provides by these names (``rc2:ORACLE``, ``lsu:ORACLE``).
ORACLES = ("cd15", "cd19", "g3", "g4", "g42", "lgl", "m22", "mcb", "mcm", "mgh", "mpl", "mg3")


#: Oracles python-sat cannot interrupt (CaDiCaL): no anytime search on them.
UNINTERRUPTIBLE = ("cd15", "cd19")


def check_oracle(name: str, *, interruptible: bool = False) -> str:
    """``name`` if python-sat has a SAT oracle called so (and, with ``interruptible``, one it
    can interrupt), else an error listing them."""
    valid = tuple(o for o in ORACLES if not (interruptible and o in UNINTERRUPTIBLE))
    if name not in valid:
        raise UnknownNameError("SAT oracle", name, valid)
    return name


class OracleBackendBase(BackendBase):
    """A backend that calls a python-sat SAT oracle, named ``NAME:ORACLE`` (``rc2:cd19``).

    Subclasses set ``name`` (the base name), ``default_oracle`` (the one the bare name means)
    and ``interruptible_oracle`` (whether the search needs an oracle python-sat can interrupt).
    """

    default_oracle: str = "g3"
    interruptible_oracle: bool = False

    @classmethod
    def from_name(cls, name: str, argument: str | None) -> Self | None:
        """``NAME`` (the default oracle) or ``NAME:ORACLE``."""
        return cls(argument)

    def __init__(self, oracle: str | None = None) -> None:
        oracle = self.default_oracle if oracle is None else oracle
        self.oracle = check_oracle(oracle, interruptible=self.interruptible_oracle)
        self.time_limited = oracle not in UNINTERRUPTIBLE
        base = type(self).name
        self.name = base if oracle == self.default_oracle else f"{base}:{oracle}"


def interrupt_types() -> tuple[type[BaseException], ...]:
    """Exceptions that mean "Ctrl-C during a solve": pysat's C solvers raise their own
    ``pysolvers.error("Caught keyboard interrupt")`` instead of ``KeyboardInterrupt``."""
    try:
        import pysolvers  # the C extension behind pysat.solvers
    except ImportError:
        return (KeyboardInterrupt,)
    return (KeyboardInterrupt, pysolvers.error)
