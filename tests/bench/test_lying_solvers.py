"""The lying-solver zoo (tests/bench/lying_maxsat.py): every way a solver can fail is caught,
alone and beside RC2; none is believed (issue 35)."""

from __future__ import annotations

import csv
import os
import sys
import tempfile
import time
from pathlib import Path

import pytest

import illuknit.solvers as reg
from illuknit.bench.instances import Instance
from illuknit.bench.solver_report import cost_at
from illuknit.bench.solver_runs import SolverTask, run_solver_task
from illuknit.bench.solver_table import make_tasks, run_solver_table
from illuknit.bench.wcnf_files import read_wcnf
from illuknit.core.pattern import Yarn
from illuknit.solvers import BackendBase

LIAR = Path(__file__).parent / "lying_maxsat.py"


def liar(mode: str) -> str:
    return f"wcnf:{sys.executable} {LIAR} {mode} {{}}"


@pytest.fixture
def private_tmp(tmp_path, monkeypatch) -> Path:
    """A temp folder of this test's own (the runs fork from here and inherit it)."""
    folder = tmp_path / "tmp"
    folder.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(folder))
    monkeypatch.setenv("TMPDIR", str(folder))
    return folder


@pytest.mark.parametrize("where", ["first", "middle", "last"])
def test_a_false_optimum_in_any_wale_is_refuted_alone_and_beside_rc2(wcnf_file, where, tmp_path):
    path, opt = wcnf_file
    fake = liar(f"wale-{where}")
    for solvers in ([fake], [fake, "rc2"]):
        table = run_solver_table(
            make_tasks([], solvers, time_limit=20, wcnf_files=[path]), tmp_path
        )
        row = next(r for r in table.rows if r["solver"] == fake)
        assert row["claimed_status"] == "OPTIMUM FOUND" and row["verified_cost"] > opt
        assert row["certificate"].startswith("refuted") and row["flag"], row
        assert {s["solver"]: s for s in table.summary}[fake]["solved"] == 0


def test_an_honest_optimum_is_certified_and_solved(wcnf_file, tmp_path):
    path, opt = wcnf_file
    table = run_solver_table(
        make_tasks([], [liar("honest"), "rc2"], time_limit=20, wcnf_files=[path]), tmp_path
    )
    for row in table.rows:
        assert row["verified_cost"] == opt and row["certificate"] == "certified", row
    assert all(s["solved"] == 1 for s in table.summary if s["solver"] != "virtual best")


def test_a_false_unsatisfiable_is_refuted(wcnf_file, tmp_path):
    path, opt = wcnf_file
    table = run_solver_table(
        make_tasks([], [liar("false-unsat")], time_limit=20, wcnf_files=[path]), tmp_path
    )
    (row,) = table.rows
    assert row["certificate"] == f"refuted ({opt})" and "UNSATISFIABLE refuted" in row["flag"]


@pytest.mark.parametrize(
    ("mode", "why"),
    [
        ("v-long", "values for"),
        ("v-short", "values for"),
        ("v-both", "both polarities"),
        ("v-twice", "a second 'v' line"),
        ("v-range", "out of range"),
    ],
)
def test_a_malformed_v_line_is_an_error_with_the_reason(wcnf_file, mode, why):
    path, _ = wcnf_file
    row = run_solver_task(SolverTask(None, "wcnf", liar(mode), time_limit=20, wcnf=path))["row"]
    assert row["status"] == "error" and why in row["reason"], row
    assert row["verified_cost"] is None


def test_one_big_allocation_refused_by_the_address_space_limit_is_a_memout(wcnf_file):
    path, _ = wcnf_file
    task = SolverTask(None, "wcnf", liar("big-alloc"), time_limit=20, memory_mb=1000, wcnf=path)
    row = run_solver_task(task)["row"]
    assert row["status"] == "memout" and "MemoryError" in row["reason"], row


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split()[2] != "Z"
    except OSError:
        return False


def test_an_escaped_helper_is_counted_killed_and_reaped(wcnf_file, private_tmp, monkeypatch):
    path, _ = wcnf_file
    pidfile = private_tmp.parent / "helper.pid"
    monkeypatch.setenv("LYING_HELPER_PIDFILE", str(pidfile))
    task = SolverTask(None, "wcnf", liar("escape"), time_limit=20, memory_mb=400, wcnf=path)
    row = run_solver_task(task)["row"]
    assert row["status"] == "memout" and row["peak_rss_mb"] > 400, row
    helper = int(pidfile.read_text())
    time.sleep(0.2)
    assert not _alive(helper) and not Path(f"/proc/{helper}").exists()  # killed and reaped


def test_no_temp_folder_outlives_a_run_even_a_killed_one(wcnf_file, private_tmp):
    path, _ = wcnf_file
    for mode, limit in (("honest", 20.0), ("early-o", 0.5)):
        run_solver_task(SolverTask(None, "wcnf", liar(mode), time_limit=limit, wcnf=path))
    assert os.listdir(private_tmp) == []


def test_an_early_cost_without_an_assignment_is_a_claim_and_never_scores(wcnf_file, tmp_path):
    path, opt = wcnf_file
    fake = liar("early-o")
    table = run_solver_table(
        make_tasks([], [fake, "rc2"], time_limit=15, wcnf_files=[path]), tmp_path
    )
    row = next(r for r in table.rows if r["solver"] == fake)
    assert row["verified_cost"] == opt and row["time_best"] >= 3.0  # when the v-line backed it
    with open(tmp_path / "traces.csv") as f:
        points = [p for p in csv.DictReader(f) if p["solver"] == fake]
    assert (points[0]["cost"], points[0]["backed"]) == ("1", "claim")
    assert cost_at(row, [], 1.0) is None and cost_at(row, [], 15.0) == opt
    summary = {s["solver"]: s for s in table.summary}
    assert set(summary[fake]) >= {"score@15s (limit)", "certified"}
    assert "score@60s" not in summary[fake]  # a 15 s run is never scored at 60 s


def test_rc2_is_plain_and_the_split_is_its_own_labelled_row(wcnf_file, monkeypatch):
    """``rc2`` hands RC2 the formula as given (one component); ``rc2+split`` splits it into
    components first; every other solver gets the same split as ``NAME+split``
    (tests/bench/test_split_rows.py)."""
    from illuknit.bench.solver_runs import _child_solve
    from illuknit.solvers.rc2 import RC2Backend

    monkeypatch.setattr(RC2Backend, "split", True)  # restored after the test
    path, opt = wcnf_file
    model = read_wcnf(path)
    for name, split in (("rc2", False), ("rc2+split", True)):
        out = _child_solve(model, SolverTask(None, "wcnf", name, time_limit=30, wcnf=path))
        assert RC2Backend.split is split and out["objective"] == opt
        assert (out["components"] > 1) is split
    row = run_solver_task(SolverTask(None, "wcnf", "rc2+split", time_limit=30, wcnf=path))["row"]
    assert row["verified_cost"] == opt and row["solver"] == "rc2+split"
    other = run_solver_task(SolverTask(None, "wcnf", "cpsat+split", time_limit=30, wcnf=path))
    assert other["row"]["verified_cost"] == opt and "components" in other["row"]["reason"]


class _Squatter(BackendBase):
    """Makes a temp folder like the external backend's, then ignores every request to stop:
    only the kill ends it, and nothing of its own cleans up."""

    name = "squatter"

    def solve(self, model, *, time_limit=None, seed=0, progress=None):
        tempfile.mkdtemp(prefix="illuknit-wcnf-")
        while True:
            try:
                time.sleep(600)
            except KeyboardInterrupt:
                continue


def test_a_killed_runs_temp_folder_is_removed(private_tmp, monkeypatch):
    monkeypatch.setitem(reg._registered, "squatter", _Squatter)
    yarns = (Yarn("dark", (20, 20, 20)), Yarn("cream", (240, 236, 230)))
    inst = Instance(
        "t", "double", (6, 6), yarns, 1.0, {"A": {"draw": "plus"}, "B": {"draw": "circle"}}
    )
    row = run_solver_task(SolverTask(inst, "logical", "squatter", time_limit=0.5))["row"]
    assert row["status"] == "timeout" and "killed" in row["reason"]
    assert os.listdir(private_tmp) == []
