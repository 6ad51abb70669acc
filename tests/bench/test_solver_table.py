"""Solver rows of the benchmark: isolation (crash, hang, silent exit), verification (liars),
the summary and the files, WCNF export and import."""

from __future__ import annotations

import csv
import json
import os
import signal
import sys
import time
from pathlib import Path

import pytest

import illuknit.solvers as reg
from illuknit.bench.instances import Instance
from illuknit.bench.solver_runs import SolverTask, run_solver_task
from illuknit.bench.solver_table import make_tasks, run_solver_table
from illuknit.bench.wcnf_files import export_wcnf_family, read_wcnf
from illuknit.core.pattern import Yarn
from illuknit.solvers import BackendBase

FAKE = Path(__file__).parents[1] / "solvers" / "fake" / "fake_maxsat.py"


@pytest.fixture(scope="module")
def tiny() -> Instance:
    yarns = (Yarn("dark", (20, 20, 20)), Yarn("cream", (240, 236, 230)))
    return Instance(
        "tiny-plus-circle",
        "double",
        (8, 8),
        yarns,
        2.0,
        {"A": {"draw": "plus"}, "B": {"draw": "circle"}},
    )


class _Crash(BackendBase):
    name = "crash"

    def solve(self, model, *, time_limit=None, seed=0, progress=None):
        os.kill(os.getpid(), signal.SIGSEGV)


class _Hang(BackendBase):
    name = "hang"

    def solve(self, model, *, time_limit=None, seed=0, progress=None):
        time.sleep(600)  # ignores its time limit


class _Silent(BackendBase):
    name = "silent"

    def solve(self, model, *, time_limit=None, seed=0, progress=None):
        os._exit(3)


@pytest.fixture
def fakes(monkeypatch):
    for cls in (_Crash, _Hang, _Silent):
        monkeypatch.setitem(reg._registered, cls.name, cls)


def test_crashing_hanging_and_silent_backends_each_cost_one_row(tiny, fakes, tmp_path):
    tasks = make_tasks([tiny], ["crash", "hang", "silent", "rc2"], time_limit=3.0)
    t0 = time.perf_counter()
    table = run_solver_table(tasks, tmp_path)
    assert time.perf_counter() - t0 < 60  # the hang was killed, not waited for
    rows = {r["solver"]: r for r in table.rows}
    assert len(table.rows) == 4
    assert rows["crash"]["status"] == "error" and "SIGSEGV" in rows["crash"]["reason"]
    assert rows["hang"]["status"] == "timeout" and "no answer within" in rows["hang"]["reason"]
    assert rows["silent"]["status"] == "error" and "code 3" in rows["silent"]["reason"]
    assert rows["rc2"]["status"] == "optimal" and not rows["rc2"]["flag"]
    assert rows["rc2"]["verified_cost"] == rows["rc2"]["reference_optimum"]
    with open(tmp_path / "solvers.csv") as f:
        assert len(list(csv.DictReader(f))) == 4


def test_a_lying_external_solver_is_flagged(tiny, tmp_path):
    liar = f"wcnf:{sys.executable} {FAKE} --lie-feasible {{}}"
    honest = f"wcnf:{sys.executable} {FAKE} {{}}"
    table = run_solver_table(make_tasks([tiny], [liar, honest, "dp"], time_limit=20), tmp_path)
    rows = {r["solver"]: r for r in table.rows}
    lie = rows[liar]
    assert lie["claimed_status"] == "OPTIMUM FOUND" and lie["claimed_cost"] == 0
    assert lie["verified_cost"] > lie["reference_optimum"]
    assert "above the DP optimum" in lie["flag"] and "claimed cost 0" in lie["flag"]
    assert lie["time_prove"] is None
    assert not rows[honest]["flag"] and rows[honest]["verified_cost"] == lie["reference_optimum"]
    summary = {s["solver"]: s for s in table.summary}
    assert summary[liar]["flagged"] == 1 and summary[liar]["solved"] == 0
    assert summary[honest]["solved"] == 1
    md = (tmp_path / "solvers.md").read_text()
    assert "Flagged runs (1)" in md and "above the DP optimum" in md


def test_an_assignment_breaking_hard_clauses_is_an_error(tiny):
    liar = f"wcnf:{sys.executable} {FAKE} --lie {{}}"
    row = run_solver_task(SolverTask(tiny, "logical", liar, time_limit=20))["row"]
    assert row["status"] == "error" and "violates hard clauses" in row["flag"]


def test_summary_scores_and_traces(tiny, tmp_path):
    table = run_solver_table(make_tasks([tiny], ["dp", "lsu"], time_limit=5), tmp_path)
    summary = {s["solver"]: s for s in table.summary}
    assert summary["dp"]["solved"] == 1 and summary["dp"]["score@5s (limit)"] == 1.0
    # 60 and 300 s are the Evaluation's times; a 5 s run has no score there, only at its limit
    assert "score@60s" not in summary["dp"] and "score@300s" not in summary["dp"]
    assert summary["virtual best"]["solved"] == 1
    assert summary["dp"]["par2"] <= 5
    with open(tmp_path / "traces.csv") as f:
        trace = list(csv.DictReader(f))
    assert {t["solver"] for t in trace} >= {"lsu"}
    data = json.loads((tmp_path / "solvers.json").read_text())
    assert data["rows"][0]["found_by"] == "dp"


def test_wcnf_export_round_trips_with_its_manifest(tiny, tmp_path):
    mf = export_wcnf_family([tiny], tmp_path / "family")
    files = {e["model"]: e for e in mf["files"]}
    assert set(files) == {"logical", "knit-aware"}
    assert files["logical"]["known_optimum"] is not None
    assert files["knit-aware"]["known_optimum"] is None
    path = tmp_path / "family" / files["logical"]["file"]
    assert path.read_text().splitlines()[1].startswith("h ")
    model = read_wcnf(path)
    assert model.num_soft == files["logical"]["soft_clauses"]
    row = run_solver_task(SolverTask(None, "wcnf", "rc2", time_limit=10, wcnf=str(path)))["row"]
    assert row["status"] == "optimal"
    assert row["verified_cost"] == files["logical"]["known_optimum"]


class _Escaper(BackendBase):
    """Starts a helper in a session of its own (as hermax's workers do), then hangs."""

    name = "escaper"
    pid_file: Path | None = None

    def solve(self, model, *, time_limit=None, seed=0, progress=None):
        import subprocess

        p = subprocess.Popen(["sleep", "600"], start_new_session=True)
        assert self.pid_file is not None
        self.pid_file.write_text(str(p.pid))
        time.sleep(600)


def test_helpers_in_their_own_session_die_with_the_run(tiny, tmp_path, monkeypatch):
    monkeypatch.setattr(_Escaper, "pid_file", tmp_path / "pid")
    monkeypatch.setitem(reg._registered, "escaper", _Escaper)
    row = run_solver_task(SolverTask(tiny, "logical", "escaper", time_limit=1.0))["row"]
    assert row["status"] == "timeout"
    pid = int((tmp_path / "pid").read_text())
    for _ in range(50):
        stat = Path(f"/proc/{pid}/stat")
        if not stat.exists() or stat.read_text().split(") ")[1].startswith("Z"):
            break
        time.sleep(0.1)
    else:
        pytest.fail(f"helper {pid} outlived its run")


def test_dask_executor_runs_solver_rows(tiny, tmp_path):
    pytest.importorskip("dask.distributed", reason="needs illuknit[dask]")
    table = run_solver_table(
        make_tasks([tiny], ["dp", "rc2"], time_limit=20), tmp_path, executor="dask", jobs=1
    )
    rows = {r["solver"]: r for r in table.rows}
    assert rows["dp"]["status"] == rows["rc2"]["status"] == "optimal"
    assert rows["rc2"]["verified_cost"] == rows["dp"]["reference_optimum"]
