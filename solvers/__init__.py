"""Pluggable solver backends (installed as ``illuknit.solvers``).

One module per backend, one small contract (:mod:`illuknit.solvers.base`), and a registry in
preference order. Backends are imported only when used, so ``import illuknit.solvers`` stays light.

=========  ===============================================================  ==================
name       what                                                             handles
=========  ===============================================================  ==================
cpsat      OR-Tools CP-SAT, native cardinality/linear, 2 workers             every model
rc2        pysat RC2 core-guided MaxSAT (exact)                              every model
lsu        pysat linear SAT-UNSAT search (anytime upper bounds)              every model
fm         pysat Fu-Malik core-guided MaxSAT (exact)                         every model
wcnf:CMD   any MaxSAT solver binary via a WCNF file (``wcnf:"maxhs {}"``)    every model
=========  ===============================================================  ==================

The package knows no knitting: it solves the neutral form of :mod:`illuknit.solvers.model`. A
domain with algorithms of its own registers them (:func:`register_backend`, with their place in
the preference order) -- design registers the illusion models' exact DP (``dp``), block
descent (``descent``) and gradient design (``gradient``) from
``illuknit.design.models.backends`` when it loads -- and its warm starts
(:func:`illuknit.solvers.warm_start.register_warm_start`). Backends declare what they can do as
flags (:class:`~illuknit.solvers.base.BackendBase`), which :func:`solve` dispatches on.

Third parties add a backend through the entry-point group ``illuknit.solvers``; the entry point
loads either a Backend instance, a Backend class, or a zero-argument factory.

Examples
--------
>>> from illuknit.solvers.model import Model
>>> from illuknit.solvers import solve
>>> m = Model("tiny")
>>> a, b = m.var("a"), m.var("b")
>>> m.add_hard([a, b]); m.add_soft([-a], 1); m.add_soft([-b], 2)
>>> sol = solve(m, solver="rc2")
>>> (sol.status.value, sol.objective, sol.value("a"))
('optimal', 1, True)
"""

from __future__ import annotations

import copy
import importlib
import math
import time
from collections.abc import Callable, Mapping
from dataclasses import replace
from importlib.metadata import entry_points
from typing import TYPE_CHECKING, Any, NamedTuple

from illuknit.core.arguments import (
    check_bool,
    check_callable,
    check_choice,
    check_instance,
    check_seconds,
    check_seed,
    check_str,
)
from illuknit.core.errors import (
    BackendUnavailableError,
    SolverError,
    UnknownNameError,
)
from illuknit.solvers.base import (
    Backend,
    BackendBase,
    BackendKind,
    ProgressCallback,
    ProgressEvent,
    Solution,
    Status,
    TracePoint,
)
from illuknit.solvers.stats import SolveStats, WarmStartInfo

if TYPE_CHECKING:
    from illuknit.solvers.model import Model

__all__ = [
    "ENTRY_POINT_GROUP",
    "HERMAX_NAMES",
    "REGISTRY",
    "Backend",
    "BackendBase",
    "BackendKind",
    "ProgressEvent",
    "Solution",
    "SolveStats",
    "SolverName",
    "Status",
    "WarmStartInfo",
    "available_backends",
    "backend_names",
    "describe_backends",
    "get_backend",
    "parse_solver_name",
    "register_backend",
    "resolve_backend",
    "solve",
]

ENTRY_POINT_GROUP = "illuknit.solvers"

#: the hermax solvers (``illuknit[maxsat]``), complete then anytime; see solvers/hermax.py
HERMAX_NAMES = (
    "evalmaxsat",
    "uwrmaxsat",
    "cashwmaxsat",
    "openwbo",
    "cgss",
    "wmaxcdcl",
    "aperture",
    "coretrail",
    "loandra",
    "openwbo-inc",
    "tt-openwbo-inc",
    "nuwls-c-ibr",
    "spb-maxsat-c-fps",
)

#: backend name -> "module:attribute" (a Backend class or factory), in preference order; the
#: built-in generic backends, and the ones a domain registers (:func:`register_backend`).
REGISTRY: dict[str, str] = {
    "cpsat": "illuknit.solvers.cpsat:CPSATBackend",
    "rc2": "illuknit.solvers.rc2:RC2Backend",
    "lsu": "illuknit.solvers.lsu:LSUBackend",
    "fm": "illuknit.solvers.fm:FMBackend",
    **{name: "illuknit.solvers.hermax:HermaxBackend" for name in HERMAX_NAMES},
}

#: backends that take a SAT oracle after a colon (``rc2:cd19``); the class takes it as argument
ORACLE_BACKENDS = ("rc2", "lsu", "fm")

#: pseudo-backend prefix: ``wcnf:COMMAND`` runs an external MaxSAT binary.
EXTERNAL_PREFIX = "wcnf:"

_registered: dict[str, Callable[[], Backend] | Backend] = {}


class SolverName(NamedTuple):
    """A solver name taken apart at its first colon: ``rc2:cd19``, ``wcnf:maxhs {}``, ``dp``."""

    base: str
    #: What follows the colon (a SAT oracle, or an external command); None without a colon.
    argument: str | None

    @property
    def oracle(self) -> str:
        """The SAT oracle named after a backend of :data:`ORACLE_BACKENDS` ("" when none)."""
        return (self.argument or "") if self.base in ORACLE_BACKENDS else ""

    @property
    def external(self) -> bool:
        """``wcnf:COMMAND``: an external MaxSAT binary."""
        return self.base == EXTERNAL_PREFIX[:-1] and self.argument is not None


def parse_solver_name(name: str) -> SolverName:
    """The one reading of a solver name (registry, benchmark rows and preloading share it).

    Examples
    --------
    >>> parse_solver_name("rc2:cd19").oracle
    'cd19'
    >>> parse_solver_name("wcnf:maxhs {}")
    SolverName(base='wcnf', argument='maxhs {}')
    """
    base, sep, arg = check_str(name, "name").partition(":")
    return SolverName(base, arg if sep else None)


def register_backend(
    name: str,
    backend: Backend | Callable[[], Backend] | str,
    *,
    before: str | None = None,
    after: str | None = None,
) -> None:
    """Register a backend under ``name``: an instance, a factory, or "module:attr" (imported
    only when used).

    A "module:attr" backend takes its place in the preference order that ``solver="auto"``
    follows: just ``before`` or ``after`` the backend named so (at the end when neither is given
    or the name is not registered). Registering a name again replaces it.

    Examples
    --------
    >>> register_backend("rc2-again", "illuknit.solvers.rc2:RC2Backend", after="rc2")
    >>> backend_names()[backend_names().index("rc2") + 1]
    'rc2-again'
    >>> del REGISTRY["rc2-again"]
    """
    check_str(name, "name")
    if not isinstance(backend, str):
        _registered[name] = backend
        return
    entries = [(n, spec) for n, spec in REGISTRY.items() if n != name]
    names = [n for n, _ in entries]
    at = len(entries)
    if before is not None and before in names:
        at = names.index(before)
    elif after is not None and after in names:
        at = names.index(after) + 1
    entries.insert(at, (name, backend))
    REGISTRY.clear()
    REGISTRY.update(entries)


def _entry_points() -> dict[str, Any]:
    try:
        return {ep.name: ep for ep in entry_points(group=ENTRY_POINT_GROUP)}
    except Exception:  # a broken third-party distribution must not break the registry
        return {}


def backend_names() -> list[str]:
    """Every known backend name (registry order, then registered, then entry points)."""
    names = list(REGISTRY) + [n for n in _registered if n not in REGISTRY]
    names += [n for n in _entry_points() if n not in names]
    return names


def _instantiate(obj: Any) -> Backend:
    if isinstance(obj, type) or (callable(obj) and not isinstance(obj, Backend)):
        obj = obj()
    return obj  # type: ignore[no-any-return,unused-ignore]


def _lookup(name: str) -> Backend:
    parsed = parse_solver_name(name)
    if parsed.external:
        from illuknit.solvers.wcnf import ExternalWCNFBackend

        return ExternalWCNFBackend(parsed.argument or "")
    if name in _registered:
        return _instantiate(_registered[name])
    base, arg = parsed
    if base in REGISTRY:
        module, _, attr = REGISTRY[base].partition(":")
        obj = getattr(importlib.import_module(module), attr)
        # a BackendBase class says itself what it makes of the name and the part after a colon
        made: Any
        if isinstance(obj, type) and issubclass(obj, BackendBase):
            made = obj.from_name(base, arg)
        else:
            made = _instantiate(obj) if arg is None else None
        if made is not None:
            return made
    eps = _entry_points()
    if name in eps:
        return _instantiate(eps[name].load())
    raise UnknownNameError(
        "solver",
        name,
        [*backend_names(), *(f"{b}:ORACLE" for b in ORACLE_BACKENDS), "wcnf:COMMAND", "auto"],
    )


def get_backend(name: str, *, check_available: bool = True) -> Backend:
    """The backend called ``name``.

    Raises
    ------
    UnknownNameError
        ``name`` is not a known backend; the message lists the valid names.
    BackendUnavailableError
        The backend's library (or binary) is missing; the message names the extra to install.
    """
    check_str(name, "name")
    check_bool(check_available, "check_available")
    backend = _lookup(name)
    if check_available:
        reason = backend.unavailable_reason()
        if reason is not None:
            raise BackendUnavailableError(f"solver {name!r} is not available: {reason}")
    return backend


def available_backends() -> list[str]:
    """Names of the backends whose dependencies are installed, in preference order."""
    out = []
    for n in backend_names():
        try:
            if _lookup(n).is_available():
                out.append(n)
        except Exception:  # an unimportable third-party backend is simply unavailable
            continue
    return out


def describe_backends() -> list[dict[str, str]]:
    """One row per known backend: name, kind (exact / anytime / heuristic), version, and
    availability ("yes" or why not) -- what ``illuknit solve --list-solvers`` prints."""
    rows = []
    for n in backend_names():
        try:
            b = _lookup(n)
            reason = b.unavailable_reason()
            version = b.version() if reason is None else ""
            kind = (
                "exact" if b.exact else ("anytime" if b.kind is BackendKind.MAXSAT else "heuristic")
            )
        except Exception as e:  # a broken third-party backend is listed with its error
            reason, version, kind = f"cannot load: {e}", "", "?"
        rows.append({"name": n, "kind": kind, "version": version, "available": reason or "yes"})
    return rows


def pick_backend(model: Model) -> Backend:
    """The first available backend, in preference order, that handles ``model``."""
    for n in available_backends():
        b = _lookup(n)
        if b.handles(model):
            return b
    raise BackendUnavailableError("no installed solver backend handles this model")


def resolve_backend(model: Model, solver: str) -> Backend:
    """The backend ``solver`` names ("auto": :func:`pick_backend`), checked to handle ``model``.

    Raises
    ------
    SolverError
        The backend cannot solve ``model``; the message says why.
    """
    from illuknit.solvers.model import Model  # light: the model is already made

    check_instance(model, Model, "model")
    check_str(solver, "solver")
    backend = pick_backend(model) if solver == "auto" else get_backend(solver)
    why = backend.why_not(model)
    if why is not None:
        raise SolverError(f"solver {backend.name!r} cannot solve model {model.name!r}: {why}")
    return backend


def solve(
    model: Model,
    *,
    solver: str = "auto",
    warm_start: str = "none",
    time_limit: float | None = None,
    seed: int = 0,
    progress: ProgressCallback | None = None,
) -> Solution:
    """Solve ``model`` with the backend named ``solver`` and the warm-start policy ``warm_start``.

    The one orchestration the CLI, the benchmark, the app and :func:`solve_illusion` share:
    resolve the backend once ("auto" picks the first available that handles the model), apply
    the warm start (:mod:`illuknit.solvers.warm_start`: ``none``, ``auto`` or a policy the
    model's domain registers, e.g. ``dp`` or ``descent``; only for a backend that
    ``accepts_warm_start``) within ``time_limit``,
    solve with the rest of the time, and keep the warm start's answer only where the backend did
    worse, saying so in ``found_by``. ``model`` is not changed (the warm start reaches the
    backend on a copy of it). Every improvement the backend reports lands in
    ``solution.trace``. Infeasible models come back with ``status == "infeasible"`` and
    ``stats["infeasible_families"]`` naming the conflicting hard-constraint families.

    Raises
    ------
    OptionError
        ``time_limit`` is not positive.
    SolverError
        The backend cannot solve the model, or the warm start does not apply to it.
    """
    from illuknit.solvers import warm_start as ws_mod

    policies = ws_mod.warm_start_policies()
    if isinstance(warm_start, str) and warm_start not in policies:
        raise UnknownNameError("warm start", warm_start, policies)
    check_choice(warm_start, "warm_start", policies)
    check_seconds(time_limit, "time_limit")
    check_seed(seed)
    check_callable(progress, "progress")
    backend = resolve_backend(model, solver)
    policy = "none"
    if backend.accepts_warm_start:
        policy = ws_mod.resolve_policy(warm_start, model)
    info = None
    remaining = time_limit
    if policy != "none":
        hint, info = ws_mod.make_warm_start(model, policy, time_limit=time_limit, seed=seed)
        # the backend reads the warm start from the model's hint: give it a copy that carries
        # it, so the caller's model is left as it was given
        model = copy.copy(model)
        model.hint = hint
        if time_limit is not None:
            remaining = max(0.1 * time_limit, time_limit - info.seconds)
    trace: list[TracePoint] = []

    def record(event: ProgressEvent) -> None:
        trace.append((event.elapsed, event.objective, event.bound))
        if progress is not None:
            progress(event)

    t0 = time.perf_counter()
    extra: dict[str, Any] = {}
    if info is not None and info.bound is not None and backend.accepts_lower_bound:
        extra["lower_bound"] = math.ceil(info.bound)  # proven by the warm start
    sol = backend.solve(model, time_limit=remaining, seed=seed, progress=record, **extra)
    sol = replace(sol, trace=tuple(trace) or sol.trace, found_at=_found_at(sol, trace))
    if info is not None:
        sol = ws_mod.keep_warm_start(model, sol, info)
    else:
        sol = replace(sol, stats=SolveStats(sol.stats))
    if sol.status is Status.INFEASIBLE and "infeasible_families" not in sol.stats:
        fams = model.infeasible_families()
        sol = replace(
            sol,
            wall_time=time.perf_counter() - t0,
            stats=_with_families(sol.stats, fams),
        )
    return sol


def _with_families(stats: Mapping[str, Any], families: list[str]) -> SolveStats:
    """``stats`` (a :class:`SolveStats`) naming the conflicting constraint families too."""
    assert isinstance(stats, SolveStats)  # solve() made it so just above
    return replace(stats, infeasible_families=tuple(families))


def _found_at(sol: Solution, trace: list[TracePoint]) -> float | None:
    """When the backend first reported the objective it returned (its time to best)."""
    if sol.values is None:
        return None
    for t, obj, _ in trace:
        if obj is not None and sol.objective is not None and obj <= sol.objective:
            return min(t, sol.wall_time)
    return sol.found_at
