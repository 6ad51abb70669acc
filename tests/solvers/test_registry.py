"""The backend registry: names, availability, entry points, the external-binary route."""

from __future__ import annotations

import numpy as np
import pytest

import illuknit.solvers as reg
from illuknit.core.errors import BackendUnavailableError, SolverError, UnknownNameError
from illuknit.solvers import (
    Backend,
    BackendBase,
    Solution,
    Status,
    available_backends,
    get_backend,
    solve,
)
from illuknit.solvers.model import Model


def test_unknown_name_lists_the_valid_ones():
    with pytest.raises(UnknownNameError) as e:
        get_backend("gurobi")
    msg = str(e.value)
    for name in ("dp", "cpsat", "rc2", "lsu", "wcnf:COMMAND"):
        assert name in msg


def test_builtin_backends_follow_the_protocol():
    for name in available_backends():
        b = get_backend(name)
        assert isinstance(b, Backend)
        assert b.name == name
    assert available_backends()[:2] == ["dp", "cpsat"]


class _Missing(BackendBase):
    name = "needs-gpu"
    extra = "gpu"
    requires = ("no_such_gpu_module",)

    def solve(self, model, *, time_limit=None, seed=0, progress=None):  # pragma: no cover
        raise AssertionError


def test_unavailable_backend_names_the_extra(monkeypatch):
    monkeypatch.setitem(reg._registered, "needs-gpu", _Missing)
    assert "needs-gpu" in reg.backend_names()
    assert "needs-gpu" not in available_backends()
    with pytest.raises(BackendUnavailableError, match=r"pip install 'illuknit\[gpu\]'"):
        get_backend("needs-gpu")


class _Constant(BackendBase):
    name = "constant"
    exact = False

    def solve(self, model, *, time_limit=None, seed=0, progress=None):
        v = np.zeros(model.pool.top + 1, dtype=bool)
        _, cost = model.evaluate(v)
        return Solution(Status.FEASIBLE, v, cost, None, 0.0, {}, self.name, model.pool)


class _EntryPoint:
    name = "constant"

    def load(self):
        return _Constant


def test_entry_point_backends_are_found_by_name(monkeypatch):
    monkeypatch.setattr(reg, "_entry_points", lambda: {"constant": _EntryPoint()})
    assert "constant" in reg.backend_names()
    m = Model()
    m.add_soft([m.var("a")], 2)
    sol = solve(m, solver="constant")
    assert sol.status is Status.FEASIBLE and sol.objective == 2 and sol.backend == "constant"


def test_missing_external_binary_is_a_clear_error():
    with pytest.raises(
        BackendUnavailableError, match="external solver binary '/nonexistent/maxhs' not found"
    ):
        get_backend("wcnf:/nonexistent/maxhs {}")
    with pytest.raises(BackendUnavailableError, match="no solver command"):
        get_backend("wcnf:")


def test_time_limit_must_be_positive():
    from illuknit.core.errors import OptionError

    m = Model()
    m.add_soft([m.var("a")], 1)
    with pytest.raises(OptionError, match="time_limit"):
        solve(m, solver="rc2", time_limit=0)


def test_auto_picks_the_dp_when_it_applies_and_refuses_it_otherwise():
    from illuknit.design.models.illusion_models import build_model, make_problem

    per_wale = build_model(make_problem(np.eye(3, dtype=int), np.zeros((3, 3), int)))
    assert solve(per_wale, solver="auto").backend == "dp"
    plain = Model()
    plain.add_soft([plain.var("a")], 1)
    assert solve(plain, solver="auto").backend == "cpsat"
    with pytest.raises(SolverError, match="cannot solve"):
        solve(plain, solver="dp")


def test_solution_reads_values_through_the_pool():
    m = Model()
    x = m.pool.block("x", (2, 2))
    m.add_hard([int(x[0, 1])])
    m.add_soft_block(-x.reshape(-1, 1), 1)
    sol = solve(m, solver="rc2")
    assert sol.value(("x", 0, 1)) is True
    assert sol.value(("x", 1, 1)) is False
    assert sol.value(int(x[0, 1])) is True and sol.value(-int(x[0, 1])) is False
    assert sol.block("x").tolist() == [[False, True], [False, False]]
    assert sol.gap == 0.0
    assert sol.summary()["status"] == "optimal"
    with pytest.raises(KeyError):
        sol.value("nope")


def test_sat_oracles_are_chosen_by_name():
    from illuknit.design.models.illusion_models import build_model, make_problem

    model = build_model(make_problem(np.eye(4, dtype=int), np.ones((4, 4), int)))
    want = solve(model, solver="dp").objective
    for name in ("rc2:cd19", "lsu:g3", "fm:g4"):
        sol = solve(model, solver=name)
        assert sol.backend == name and sol.status is Status.OPTIMAL and sol.objective == want
    with pytest.raises(UnknownNameError, match="SAT oracle"):
        get_backend("rc2:nosuch")
    with pytest.raises(UnknownNameError, match="rc2:ORACLE"):
        get_backend("cpsat:g3")


def test_every_backend_is_described_with_version_and_availability():
    rows = {r["name"]: r for r in reg.describe_backends()}
    assert set(reg.backend_names()) <= set(rows)
    assert rows["rc2"]["available"] == "yes" and rows["rc2"]["version"].startswith("python-sat")
    assert rows["descent"]["kind"] == "heuristic"
    for name in reg.HERMAX_NAMES:
        assert rows[name]["available"] == "yes" or "illuknit[maxsat]" in rows[name]["available"]


def test_lsu_refuses_an_oracle_it_cannot_interrupt():
    with pytest.raises(UnknownNameError, match="SAT oracle"):
        get_backend("lsu:cd19")
    assert get_backend("rc2:cd19").name == "rc2:cd19"


def test_a_solver_name_is_read_one_way():
    from illuknit.solvers import parse_solver_name

    assert parse_solver_name("rc2:cd19") == ("rc2", "cd19")
    assert parse_solver_name("rc2:cd19").oracle == "cd19"
    assert parse_solver_name("lsu").oracle == "" and parse_solver_name("lsu").argument is None
    assert parse_solver_name("cpsat:x").oracle == ""  # only oracle backends take an oracle
    ext = parse_solver_name("wcnf:maxhs {} --cpu-lim=3")
    assert ext.external and ext.argument == "maxhs {} --cpu-lim=3"
    assert not parse_solver_name("wcnf").external
