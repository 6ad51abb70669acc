"""The benchmark's limits and claims as the MaxSAT Evaluation enforces them, with fake solvers
(tests/solvers/fake/fake_maxsat.py speaks the Evaluation's output format): memory of the whole
process tree, late proofs, answers at the limit, lone liars, n/a rows, repetitions."""

from __future__ import annotations

import contextlib
import json
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import illuknit.solvers as reg
from illuknit.bench.certify import certify_claim
from illuknit.bench.instances import Instance
from illuknit.bench.solver_runs import SolverTask, run_solver_task
from illuknit.bench.solver_table import make_tasks, run_solver_table
from illuknit.bench.wcnf_files import export_wcnf_family, read_wcnf
from illuknit.core.pattern import Yarn
from illuknit.design.models.illusion_models import build_model, make_problem
from illuknit.solvers import BackendBase, ProgressEvent, Status, solve

FAKE = Path(__file__).parents[1] / "solvers" / "fake" / "fake_maxsat.py"


def fake(*flags: str) -> str:
    return f"wcnf:{sys.executable} {FAKE} {' '.join(flags)} {{}}"


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


@pytest.fixture(scope="module")
def wcnf_file(tiny, tmp_path_factory) -> tuple[str, int]:
    """The tiny instance's logical model as a plain WCNF file (no reference optimum) and its
    optimum (RC2 here, independently of the runs under test)."""
    out = tmp_path_factory.mktemp("family")
    mf = export_wcnf_family([tiny], out, models=["logical"])
    path = out / mf["files"][0]["file"]
    opt = solve(read_wcnf(path), solver="rc2").objective
    return str(path), int(opt)


def test_an_external_solver_allocating_past_the_limit_is_a_memout(tiny):
    t0 = time.perf_counter()
    row = run_solver_task(SolverTask(tiny, "logical", fake("--hog"), time_limit=30, memory_mb=300))[
        "row"
    ]
    assert row["status"] == "memout", row
    assert "memory limit" in row["reason"] and row["peak_rss_mb"] > 300
    assert time.perf_counter() - t0 < 20  # stopped at the limit, not at the time limit
    assert row["verified_cost"] is None and row["memory_mb"] == 300


def test_a_proof_after_the_limit_is_a_timeout(tiny, tmp_path):
    late = fake("--late", "60")
    table = run_solver_table(make_tasks([tiny], [late, "dp"], time_limit=2.0), tmp_path)
    row = next(r for r in table.rows if r["solver"] == late)
    assert row["claimed_status"] == "OPTIMUM FOUND"
    assert row["status"] == "timeout" and row["time_prove"] is None
    assert row["verified_cost"] == row["reference_optimum"]  # its answer is kept and verified
    assert row["wall_s"] < 15 and row["cpu_s"] is not None
    summary = {s["solver"]: s for s in table.summary}
    assert summary[late]["solved"] == 0 and summary["dp"]["solved"] == 1


class _Late(BackendBase):
    """Ignores its limit; when asked to stop, hands back the optimum claiming it proven."""

    name = "late"

    def solve(self, model, *, time_limit=None, seed=0, progress=None):
        t0 = time.perf_counter()
        with contextlib.suppress(KeyboardInterrupt):
            time.sleep(600)
        sol = solve(model, solver="rc2")
        return self.solution(model, Status.OPTIMAL, t0, sol.values, sol.objective, sol.objective)


class _Bounder(BackendBase):
    """Reports a lower bound, then hangs beyond the grace period (nothing to hand back)."""

    name = "bounder"

    def solve(self, model, *, time_limit=None, seed=0, progress=None):
        assert progress is not None
        progress(ProgressEvent(0.1, None, 3.0))
        while True:
            try:
                time.sleep(600)
            except KeyboardInterrupt:
                continue


def test_a_python_backend_proving_after_the_limit_is_a_timeout(tiny, monkeypatch):
    monkeypatch.setitem(reg._registered, "late", _Late)
    row = run_solver_task(SolverTask(tiny, "logical", "late", time_limit=1.0))["row"]
    assert row["status"] == "timeout" and "after the time limit" in row["reason"]
    assert row["verified_cost"] == row["reference_optimum"] and row["time_prove"] is None


def test_lower_bounds_reported_before_the_kill_are_kept(tiny, monkeypatch):
    monkeypatch.setitem(reg._registered, "bounder", _Bounder)
    out = run_solver_task(SolverTask(tiny, "logical", "bounder", time_limit=1.0))
    row = out["row"]
    assert row["status"] == "timeout" and row["bound"] == 3.0
    assert any(b == 3.0 for _, _, b in out["trace"])


def test_an_anytime_answer_at_the_limit_is_read_and_verified(tiny):
    row = run_solver_task(SolverTask(tiny, "logical", fake("--sleep", "60"), time_limit=2.0))["row"]
    assert row["status"] == "timeout" and row["claimed_status"] == "SATISFIABLE"
    assert row["verified_cost"] is not None and not row["flag"]


def test_a_lone_false_optimum_is_refuted_and_flagged(wcnf_file, tmp_path):
    path, opt = wcnf_file
    liar = fake("--lie-optimum")
    table = run_solver_table(make_tasks([], [liar], time_limit=20, wcnf_files=[path]), tmp_path)
    (row,) = table.rows
    assert row["claimed_status"] == "OPTIMUM FOUND" and row["verified_cost"] > opt
    assert row["claimed_cost"] == row["verified_cost"]  # an honest cost: only the claim is false
    assert row["reference_optimum"] is None
    # the first component where the engine does better refutes it, with that assignment's cost
    better = int(row["certificate"].removeprefix("refuted (").removesuffix(")"))
    assert opt <= better < row["verified_cost"] and "refuted" in row["flag"]
    (entry, _vbs) = table.summary
    assert entry["solved"] == 0 and entry["flagged"] == 1


def test_a_lone_false_unsatisfiable_is_refuted_and_flagged(wcnf_file, tmp_path):
    path, _ = wcnf_file
    liar = fake("--lie-unsat")
    table = run_solver_table(make_tasks([], [liar], time_limit=20, wcnf_files=[path]), tmp_path)
    (row,) = table.rows
    assert row["status"] == "infeasible" and row["certificate"].startswith("refuted (")
    assert "UNSATISFIABLE refuted" in row["flag"]


def test_a_false_unsatisfiable_is_flagged_against_another_runs_assignment(wcnf_file, tmp_path):
    path, _ = wcnf_file
    liar = fake("--lie-unsat")
    tasks = make_tasks([], [liar, "rc2"], time_limit=20, wcnf_files=[path])
    rows = {r["solver"]: r for r in run_solver_table(tasks, tmp_path, certify_time=0).rows}
    assert "claimed UNSATISFIABLE but rc2 verified" in rows[liar]["flag"]
    assert not rows["rc2"]["flag"]


def test_an_honest_lone_optimum_is_certified(wcnf_file, tmp_path):
    path, opt = wcnf_file
    table = run_solver_table(make_tasks([], [fake()], time_limit=20, wcnf_files=[path]), tmp_path)
    (row,) = table.rows
    assert row["status"] == "optimal" and row["verified_cost"] == opt
    assert row["certificate"] == "certified" and not row["flag"]
    assert table.summary[0]["solved"] == 1


def test_the_certifier_answers_each_way(wcnf_file):
    path, opt = wcnf_file
    model = read_wcnf(path)
    assert certify_claim(model, opt, time_limit=20).result == "certified"
    worse = certify_claim(model, opt + 3, time_limit=20)
    assert worse.result == "refuted" and worse.cost is not None and worse.cost <= opt + 2
    assert certify_claim(model, None, time_limit=20).result == "refuted"


def test_rows_that_do_not_apply_say_na_and_stay_out_of_the_scores(wcnf_file, tmp_path):
    path, _ = wcnf_file
    table = run_solver_table(
        make_tasks([], ["dp", "rc2"], time_limit=10, wcnf_files=[path]), tmp_path
    )
    rows = {r["solver"]: r for r in table.rows}
    assert rows["dp"]["status"] == "n/a" and rows["dp"]["reason"]
    summary = {s["solver"]: s for s in table.summary}
    assert summary["dp"]["runs"] == 0 and summary["dp"]["n/a"] == 1
    assert summary["dp"]["par2"] == 0.0 and summary["virtual best"]["runs"] == 1


def test_repetitions_give_medians_and_spread(tiny, tmp_path):
    tasks = make_tasks([tiny], ["dp", "rc2"], time_limit=10, repeat=3, seed=7)
    assert sorted({(t.run, t.seed) for t in tasks}) == [(0, 7), (1, 8), (2, 9)]
    table = run_solver_table(tasks, tmp_path)
    assert len(table.rows) == 6
    summary = {s["solver"]: s for s in table.summary}
    assert summary["rc2"]["repeats"] == 3 and summary["rc2"]["solved"] == 1  # median per rep
    assert "-" in summary["rc2"]["par2_spread"]


def test_limits_machine_and_software_are_recorded(tiny, tmp_path):
    run_solver_table(make_tasks([tiny], ["dp"], time_limit=5, memory_mb=2048), tmp_path)
    env = json.loads((tmp_path / "solvers.json").read_text())["environment"]
    assert env["limits"]["time_limit_s"] == [5] and env["limits"]["memory_mb"] == [2048]
    assert env["machine"]["cores"] >= 1 and env["machine"]["cpu"]
    assert "python-sat" in env["software"] and env["solver_versions"]["dp"]
    head = (tmp_path / "solvers.md").read_text().splitlines()[:8]
    assert any(line.startswith("- **Limits**: 5 s per run") for line in head)
    assert any(line.startswith("- **Machine**") for line in head)


class _Nothing(BackendBase):
    """Honours its limit but never finds anything (as some hermax solvers here)."""

    name = "nothing"

    def solve(self, model, *, time_limit=None, seed=0, progress=None):
        return self.solution(model, Status.TIMEOUT, time.perf_counter())


class _Unlimited(_Late):
    name = "unlimited"
    time_limited = False


def test_the_smoke_test_tells_answers_from_nothing_and_unlimited(monkeypatch):
    from illuknit.bench.smoke import smoke_test_backends

    for cls in (_Nothing, _Unlimited):
        monkeypatch.setitem(reg._registered, cls.name, cls)
    got = {
        e["name"]: e
        for e in smoke_test_backends(["rc2", "nothing", "unlimited", "dp"], time_limit=1.0)
    }
    assert got["rc2"]["smoke"].startswith("answers (6 in") and got["rc2"]["limit"] == "yes"
    assert got["nothing"]["smoke"].startswith("returns nothing in 1 s")
    assert got["unlimited"]["limit"].startswith("cannot be time-limited")
    # it proves only when asked to stop, after the limit: a timeout, answer kept
    assert got["unlimited"]["smoke"].startswith("answers (6 in")


@pytest.mark.parametrize(
    "args",
    [
        ["--solvers", "dp", "--methods", "tiles"],
        ["--wcnf", str(FAKE), "--methods", "dp"],
        ["--methods", "tiles", "--repeat", "2"],
    ],
)
def test_options_that_do_not_apply_are_one_line_errors(args, tmp_path, capsys):
    from illuknit.cli import main

    with pytest.raises(SystemExit) as e:
        main(["bench", *args, "-o", str(tmp_path / "out")])
    assert e.value.code == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "applies only" in err or "does not apply" in err
    assert not (tmp_path / "out").exists()


class _NestedLate(BackendBase):
    """Isolates a C-like solve of its own that ignores requests to stop and answers a little
    after the limit (as hermax's anytime solvers may): the answer must reach the row."""

    name = "nested-late"

    def solve(self, model, *, time_limit=None, seed=0, progress=None):
        from illuknit.solvers.isolate import run_in_child

        t0 = time.perf_counter()
        answer = solve(model, solver="dp").values
        # half a second after the benchmark's request to stop (at the limit + 1 s + 3 %)
        answer_at = t0 + time_limit + 1.0 + 0.03 * time_limit + 0.5

        def late(_p):
            time.sleep(max(0.0, answer_at - time.perf_counter()))
            return answer

        res = run_in_child(late, time_limit=time_limit, interruptible=False)
        assert res.status == "ok", res.reason
        _ok, cost = model.evaluate(res.value)
        return self.solution(model, Status.FEASIBLE, t0, res.value, cost)


def test_a_nested_isolation_hands_back_its_answer_after_the_request_to_stop(tiny, monkeypatch):
    monkeypatch.setitem(reg._registered, "nested-late", _NestedLate)
    row = run_solver_task(SolverTask(tiny, "logical", "nested-late", time_limit=2.0))["row"]
    assert row["verified_cost"] == row["reference_optimum"], row
    assert row["wall_s"] > 3.06  # it answered after the request to stop (at 2 s + 1.06 s)


def test_a_knit_aware_claim_is_settled_by_its_lagrangian_bound_first():
    """The bound certifies the true optimum of a tiny knit-aware model and its pattern refutes
    a worse claim, both without a SAT call (which settled none of the 8 x 8 to 12 x 12 photo-crop claims in 60 s)."""
    a, b = (rng.integers(0, 3, (6, 5)) for rng in (np.random.default_rng(s) for s in (1, 2)))
    model = build_model(make_problem(a, b, n_yarns=3, kind="knit-aware"))
    opt = int(solve(model, solver="cpsat", time_limit=20).objective)
    true = certify_claim(model, opt, time_limit=20)
    false = certify_claim(model, opt + 6, time_limit=20)
    assert (true.result, true.method) == ("certified", "Lagrangian lower bound")
    assert false.result == "refuted" and false.cost is not None and false.cost < opt + 6


def test_the_keywords_are_a_shorthand_for_solver_runs(tiny):
    from illuknit.bench.solver_table import SolverRuns
    from illuknit.core.errors import OptionError

    by_keywords = make_tasks([tiny], ["dp"], time_limit=5, repeat=2, seed=3)
    by_runs = make_tasks([tiny], ["dp"], runs=SolverRuns(time_limit=5, repeat=2, seed=3))
    assert by_runs == by_keywords
    with pytest.raises(OptionError, match="repeats"):
        make_tasks([tiny], ["dp"], repeats=2)
