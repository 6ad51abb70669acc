"""Every registered solver backend keeps one contract, checked through the public
``illuknit.solvers`` API only (a backend added to the registry, by ``register_backend`` or by an
entry point, is tested here without a line changed):

* it is a :class:`~illuknit.solvers.Backend` under its own name, with ``extra`` and ``exact``;
* ``solve(model, *, time_limit=None, seed=0, progress=None)`` (more keyword-only options, each
  with a default, are allowed) returns a frozen :class:`~illuknit.solvers.Solution` whose fields
  say what docs/solvers.md and ``illuknit.solvers.base`` say they do;
* a model it cannot solve is refused up front: ``why_not`` says why, and
  :func:`illuknit.solvers.solve` raises :class:`~illuknit.core.errors.SolverError` with that reason;
* an unavailable backend is refused with :class:`~illuknit.core.errors.BackendUnavailableError`.

Whether the answers are optimal is the conformance suite's job (test_conformance.py).
"""

from __future__ import annotations

import dataclasses
import inspect
import json
import sys
from collections.abc import Mapping
from datetime import datetime
from pathlib import Path

import numpy as np
import pytest

from illuknit import Model, build_model
from illuknit.core.errors import BackendUnavailableError, SolverError, UnknownNameError
from illuknit.design.models.illusion_models import KnitWeights, make_problem
from illuknit.solvers import (
    Backend,
    BackendKind,
    ProgressEvent,
    Solution,
    Status,
    available_backends,
    backend_names,
    describe_backends,
    get_backend,
    solve,
)

FAKE = Path(__file__).parent / "fake" / "fake_maxsat.py"
#: the external-binary backend, through the fake MaxSAT solver script
EXTERNAL = f"wcnf:{sys.executable} {FAKE} {{}}"
NAMES = [*backend_names(), EXTERNAL]
IDS = ["wcnf:fake" if n == EXTERNAL else n for n in NAMES]
#: what every Solution carries (illuknit.solvers.base's docstring)
FIELDS = {"status", "values", "objective", "bound", "wall_time", "stats", "backend"}
FIELDS |= {"pool", "found_by", "found_at", "finished_at", "trace"}


def _generic() -> Model:
    """A weighted model with no illusion behind it (only generic backends take it)."""
    m = Model("contract-generic")
    a, b, c = m.var("a"), m.var("b"), m.var("c")
    m.add_hard([a, b])
    m.add_hard([-a, c])
    m.add_soft([-a], 1)
    m.add_soft([-b], 2)
    m.add_soft([-c], 1)
    return m


def _per_wale() -> Model:
    """A logical illusion model, wale by wale (the DP's kind)."""
    a = np.array([[0, 1, 1], [1, 0, 1]])
    b = np.array([[1, 1, 0], [0, 0, 1]])
    return build_model(make_problem(a, b, n_yarns=2, kind="logical"))


def _capped() -> Model:
    """A knit-aware illusion model with a hard colour-change cap per course."""
    w = KnitWeights(view=2, color_change=1, transfer=1, max_color_changes=1)
    a = np.array([[0, 1, 0], [1, 1, 0]])
    return build_model(make_problem(a, a[::-1], n_yarns=2, kind="knit-aware", weights=w))


MODELS = {"generic": _generic, "per-wale": _per_wale, "capped": _capped}


def _backend(name: str) -> Backend:
    if name != EXTERNAL and name not in available_backends():
        pytest.skip(f"backend {name} is not installed")
    return get_backend(name)


def check_signature(backend: object) -> None:
    """The backend's attributes and its ``solve`` signature are the Protocol's."""
    assert isinstance(backend, Backend)
    assert isinstance(backend.name, str) and backend.name
    assert backend.extra is None or isinstance(backend.extra, str)
    assert isinstance(backend.exact, bool)
    params = list(inspect.signature(backend.solve).parameters.values())
    assert params[0].name == "model"
    assert params[0].kind in (params[0].POSITIONAL_ONLY, params[0].POSITIONAL_OR_KEYWORD)
    rest = {p.name: p for p in params[1:]}
    for p in rest.values():
        assert p.kind is p.KEYWORD_ONLY, f"solve's {p.name} must be keyword-only"
        assert p.default is not p.empty, f"solve's {p.name} must have a default"
    defaults = {n: rest[n].default for n in ("time_limit", "seed", "progress") if n in rest}
    assert defaults == {"time_limit": None, "seed": 0, "progress": None}


def check_solution(sol: object, model: Model, name: str) -> None:
    """A solution of a feasible model, as the contract describes it: with an assignment, or a
    timeout without one (an anytime binary may find nothing within the limit)."""
    assert isinstance(sol, Solution)
    with pytest.raises(dataclasses.FrozenInstanceError):
        sol.objective = 0  # type: ignore[misc]
    assert isinstance(sol.status, Status)
    assert sol.status in (Status.OPTIMAL, Status.FEASIBLE, Status.TIMEOUT), sol.stats
    assert sol.backend == name
    assert sol.has_values == (sol.values is not None)
    if sol.values is None:
        assert sol.status is Status.TIMEOUT and sol.objective is None, sol
    else:
        values = sol.values
        assert isinstance(values, np.ndarray) and values.dtype == bool
        assert values.shape[0] >= model.pool.top + 1 and not values.flags.writeable
        assert model.evaluate(values) == (True, sol.objective)
        assert sol.found_by and sol.found_at is not None and sol.found_at >= 0
        if sol.bound is not None:
            assert sol.bound <= sol.objective + 1e-9
            if sol.status is Status.OPTIMAL:
                assert sol.bound == pytest.approx(sol.objective)
    assert isinstance(sol.wall_time, float) and sol.wall_time >= 0
    assert datetime.fromisoformat(sol.finished_at).tzinfo is not None
    assert isinstance(sol.trace, tuple) and all(len(point) == 3 for point in sol.trace)
    assert isinstance(sol.stats, Mapping)
    with pytest.raises(TypeError):
        sol.stats["changed"] = True  # type: ignore[index]
    json.dumps(sol.summary())


def test_a_solution_has_the_documented_fields():
    assert dataclasses.is_dataclass(Solution)
    assert {f.name for f in dataclasses.fields(Solution)} >= FIELDS
    assert Solution.__dataclass_params__.frozen  # type: ignore[attr-defined]
    assert {s.value for s in Status} == {"optimal", "feasible", "timeout", "infeasible", "error"}


@pytest.mark.parametrize("name", NAMES, ids=IDS)
def test_every_backend_has_the_contract_signature(name):
    backend = get_backend(name, check_available=False)
    check_signature(backend)
    if name != EXTERNAL:
        assert backend.name == name
    reason = backend.unavailable_reason()
    assert backend.is_available() == (reason is None)
    assert isinstance(backend.version(), str)


@pytest.mark.parametrize("name", NAMES, ids=IDS)
def test_every_backend_solves_what_it_handles_into_a_frozen_solution(name):
    backend = _backend(name)
    handled = [k for k, make in MODELS.items() if backend.handles(make())]
    assert handled, f"{name} handles none of {sorted(MODELS)}: add a model it does handle"
    model = MODELS[handled[0]]()
    events: list[object] = []
    sol = solve(model, solver=name, time_limit=5.0, seed=1, progress=events.append)
    check_solution(sol, model, backend.name)
    # what the backend reported as it went is a ProgressEvent each, and the solution's trace
    assert all(isinstance(e, ProgressEvent) and e.elapsed >= 0 for e in events), events
    if events:
        assert sol.trace == tuple((e.elapsed, e.objective, e.bound) for e in events)


def test_every_backend_refuses_a_model_it_cannot_solve_with_the_reason():
    # one test over every backend (most handle every model here), which fails when no backend
    # refused anything, so it cannot pass without checking a refusal
    refusals = 0
    for name in NAMES:
        if name != EXTERNAL and name not in available_backends():
            continue
        backend = get_backend(name)
        for kind, make in MODELS.items():
            model = make()
            if backend.handles(model):
                continue
            why = backend.why_not(model)
            assert isinstance(why, str) and why, (name, kind)
            with pytest.raises(SolverError, match="cannot solve model") as error:
                solve(model, solver=name, time_limit=5.0)
            assert why in str(error.value), (name, kind)
            refusals += 1
    assert refusals, "no backend refused any model here: add a model some backend cannot solve"


@pytest.mark.parametrize("name", backend_names())
def test_an_unavailable_backend_is_refused_by_name(name, monkeypatch):
    backend = get_backend(name, check_available=False)
    monkeypatch.setattr(type(backend), "unavailable_reason", lambda self: "needs a test's absence")
    with pytest.raises(BackendUnavailableError, match="needs a test's absence"):
        get_backend(name)
    with pytest.raises(BackendUnavailableError):
        solve(_generic(), solver=name)


def test_every_backend_is_described_and_unknown_names_are_listed():
    rows = {row["name"]: row for row in describe_backends()}
    assert list(rows) == backend_names()
    for row in rows.values():
        assert row["kind"] in ("exact", "anytime", "heuristic"), row
        assert row["available"] == "yes" or row["available"]
    with pytest.raises(UnknownNameError) as error:
        get_backend("no-such-solver")
    assert all(n in str(error.value) for n in backend_names())


class _Loose:
    """A backend that breaks the contract: its options are positional, ``seed`` has no default."""

    name, extra, exact = "loose", None, True
    kind = BackendKind.MAXSAT
    proves_bound = accepts_warm_start = accepts_lower_bound = False
    time_limited = True

    def handles(self, model):
        return True

    def why_not(self, model):
        return None

    def is_available(self):
        return True

    def unavailable_reason(self):
        return None

    def version(self):
        return ""

    def solve(self, model, time_limit=None, seed=None, progress=None):
        return None


def test_the_signature_check_catches_a_loose_backend():
    with pytest.raises(AssertionError, match="keyword-only"):
        check_signature(_Loose())
