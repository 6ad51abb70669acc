"""``NAME+split`` for every solver: the formula split into its components (found from the
clauses), the solver run on each component's own formula, costs summed, assignments spliced
and the spliced assignment verified on the whole formula (issue 35, item 5)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.bench.solver_runs import SolverTask, run_solver_task
from illuknit.bench.solver_table import make_tasks, run_solver_table
from illuknit.bench.split import component_models, solve_split
from illuknit.bench.wcnf_files import read_wcnf_text
from illuknit.solvers import solve

LIAR = Path(__file__).parent / "lying_maxsat.py"


@pytest.mark.parametrize("solver", ["cpsat+split", "lsu+split", "fm+split"])
def test_any_solver_gets_the_split_and_its_spliced_answer_is_verified(wcnf_file, solver):
    path, opt = wcnf_file
    row = run_solver_task(SolverTask(None, "wcnf", solver, time_limit=60, wcnf=path))["row"]
    assert row["status"] == "optimal" and not row["flag"], row
    assert row["verified_cost"] == row["claimed_cost"] == opt
    assert row["reason"] == "10 of 10 components solved to optimality"
    assert row["time_best"] is not None


def test_a_liar_under_the_split_is_refuted(wcnf_file, tmp_path):
    """The liar runs on each component file and lies in it: honest costs, false optima."""
    path, opt = wcnf_file
    fake = f"wcnf:{sys.executable} {LIAR} wale-last {{}}+split"
    table = run_solver_table(make_tasks([], [fake], time_limit=30, wcnf_files=[path]), tmp_path)
    (row,) = table.rows
    assert row["claimed_status"] == "OPTIMUM FOUND" and row["verified_cost"] > opt, row
    assert row["certificate"].startswith("refuted") and row["flag"]
    assert table.summary[0]["solved"] == 0


@pytest.mark.parametrize(
    ("solver", "warm", "why"),
    [
        ("dp+split", "none", "on a component of the split: the DP solves only illusion"),
        ("cpsat+split", "dp", "a warm start does not apply to the component split"),
    ],
)
def test_a_split_that_cannot_apply_is_na_with_the_reason(wcnf_file, solver, warm, why):
    path, _ = wcnf_file
    row = run_solver_task(SolverTask(None, "wcnf", solver, warm, time_limit=10, wcnf=path))["row"]
    assert row["status"] == "n/a" and row["reason"].startswith(why)


def test_an_empty_hard_clause_is_unsatisfiable_under_the_split():
    model = read_wcnf_text("h 0\n1 1 0\nh 2 3 0\n", "empty")
    out = solve_split(model, "cpsat", time_limit=10)
    assert out["status"] == "infeasible" and out["values"] is None


_clause = st.lists(
    st.integers(1, 8).flatmap(lambda v: st.sampled_from([v, -v])), min_size=1, max_size=3
)


@settings(max_examples=25, deadline=None)
@given(
    hard=st.lists(_clause, max_size=4),
    soft=st.lists(st.tuples(st.integers(1, 5), _clause), min_size=1, max_size=8),
)
def test_the_split_sum_is_the_whole_formulas_optimum(hard, soft):
    text = "".join(f"h {' '.join(map(str, c))} 0\n" for c in hard)
    text += "".join(f"{w} {' '.join(map(str, c))} 0\n" for w, c in soft)
    model = read_wcnf_text(text, "random")
    whole = solve(model, solver="cpsat", time_limit=30)
    out = solve_split(model, "lsu", time_limit=30)
    comps, _, _ = component_models(model)
    ids = np.concatenate([i for _, i in comps]) if comps else np.array([], dtype=np.int64)
    assert len(set(ids.tolist())) == ids.size  # a variable lies in one component only
    if whole.status.value == "infeasible":
        assert out["status"] == "infeasible"
        return
    assert out["status"] == "optimal"
    assert model.evaluate(out["values"]) == (True, whole.objective) == (True, out["objective"])
