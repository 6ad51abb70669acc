"""Benchmark runner: outputs, resume, versions, unavailable methods, parallel and Dask execution."""

from __future__ import annotations

import csv
import json
import sys

import numpy as np
import pytest

from illuknit import __version__
from illuknit.bench.instances import instance_targets, parse_manifest
from illuknit.bench.methods import (
    METHODS,
    Method,
    MethodUnavailable,
    NoPattern,
    register_method,
)
from illuknit.bench.results import FIELDS, load_rows
from illuknit.bench.runner import run_bench
from illuknit.core.errors import ResultsVersionError, UnknownNameError
from illuknit.core.pattern import LogicalPattern

CALLS: list[str] = []


def _copy(instance, time_limit):
    """Knit each target's own colours flat: view A is perfect, view B as good as A is like B."""
    CALLS.append(f"{instance.name}/copy")
    t = instance_targets(instance)
    return LogicalPattern(t.a, np.zeros(t.a.shape, bool), instance.yarns), {"status": "ok"}


def _stripes(instance, time_limit):
    CALLS.append(f"{instance.name}/stripes")
    n, m = instance.size
    yarn = np.repeat((np.arange(n) % 2)[:, None], m, axis=1)
    return LogicalPattern(yarn, np.zeros((n, m), bool), instance.yarns), {
        "status": "optimal",
        "objective": 3,
        "bound": 3,
        "gap": 0.0,
        "solve_s": 0.01,
    }


def _slow(instance, time_limit):
    import time

    time.sleep(0.2)
    pattern, _ = _copy(instance, time_limit)
    return pattern, {"status": "feasible", "objective": 10, "bound": 4, "gap": 0.6, "solve_s": 0.15}


def _missing(instance, time_limit):
    raise MethodUnavailable("needs the imaginary extra: pip install 'illuknit[imaginary]'")


def _broken(instance, time_limit):
    raise RuntimeError("boom")


def _nothing(instance, time_limit):
    raise NoPattern("no pattern within 1 s")


FAKES = {
    "fake-copy": _copy,
    "fake-stripes": _stripes,
    "fake-slow": _slow,
    "fake-missing": _missing,
    "fake-broken": _broken,
    "fake-nothing": _nothing,
}


@pytest.fixture(autouse=True)
def fake_methods():
    for name, fn in FAKES.items():
        register_method(Method(name, fn, "test double"), replace=True)
    register_method(Method("fake-single-only", _copy, "test double", ("single",)), replace=True)
    CALLS.clear()
    yield
    for name in [*FAKES, "fake-single-only"]:
        METHODS.pop(name, None)


def instances(**over):
    base = {
        "kind": "double",
        "size": [6, 8],
        "yarns": ["#000000", "#ffffff"],
        "time_limit": 1,
    }
    return list(
        parse_manifest(
            {
                "instance": [
                    {**base, "name": "tiny-a", "a": {"draw": "plus"}, "b": {"draw": "circle"}},
                    {**base, "name": "tiny-b", "a": {"draw": "heart"}, "b": {"text": "X"}, **over},
                ]
            }
        ).instances
    )


def test_outputs_hold_one_row_per_cell_with_version_and_machine(tmp_path):
    run = run_bench(instances(), ["fake-copy", "fake-stripes"], tmp_path / "r", progress=False)
    out = run.outdir
    assert len(run.rows) == 4 and len(run.ran) == 4 and not run.reused
    for name in (
        "results.csv",
        "results.json",
        "summary.md",
        "bench.json",
        "pareto.png",
        "pareto_ghost.png",
    ):
        assert (out / name).is_file(), name
    assert (out / "contact" / "tiny-a.png").is_file()
    with open(out / "results.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [r["method"] for r in rows] == ["fake-copy", "fake-stripes"] * 2
    assert list(rows[0]) == list(FIELDS)
    assert all(r["illuknit_version"] == __version__ and r["python"] and r["cpus"] for r in rows)
    doc = json.loads((out / "results.json").read_text())
    assert doc["illuknit_version"] == __version__ and len(doc["rows"]) == 4
    # the copy method shows target A exactly from view A
    copy_a = next(r for r in run.rows if r["method"] == "fake-copy" and r["instance"] == "tiny-a")
    assert copy_a["logical_error_a"] == 0.0 and copy_a["status"] == "ok"
    assert copy_a["render_mse_a"] >= 0 and copy_a["peak_rss_mb"] > 0
    stripes = next(r for r in run.rows if r["method"] == "fake-stripes")
    assert stripes["color_changes_mean"] == 0 and stripes["gap"] == 0.0
    # stripes of one colour per course are knittable: passes and a time estimate
    assert stripes["carriage_passes"] > 0 and stripes["knit_time_min"] > 0
    summary = (out / "summary.md").read_text()
    assert "## tiny-a" in summary and "| fake-stripes | optimal |" in summary
    cell = out / "cells" / "tiny-a" / "fake-copy"
    assert {"row.json", "pattern.json", "render_A.png", "render_B.png"} <= {
        p.name for p in cell.iterdir()
    }


def test_resume_skips_finished_cells_and_reruns_changed_ones(tmp_path):
    out = tmp_path / "r"
    run_bench(instances(), ["fake-copy"], out, progress=False, write_outputs=False)
    assert sorted(CALLS) == ["tiny-a/copy", "tiny-b/copy"]
    CALLS.clear()
    again = run_bench(
        instances(), ["fake-copy", "fake-stripes"], out, progress=False, write_outputs=False
    )
    assert sorted(CALLS) == ["tiny-a/stripes", "tiny-b/stripes"]
    assert sorted(again.reused) == ["tiny-a/fake-copy", "tiny-b/fake-copy"]
    assert len(again.rows) == 4
    # a changed instance definition (or time limit) invalidates only its cells
    CALLS.clear()
    run_bench(instances(time_limit=2), ["fake-copy"], out, progress=False, write_outputs=False)
    assert CALLS == ["tiny-b/copy"]
    CALLS.clear()
    run_bench(instances(), ["fake-copy"], out, time_limit=5, progress=False, write_outputs=False)
    assert sorted(CALLS) == ["tiny-a/copy", "tiny-b/copy"]
    # --force re-runs everything
    CALLS.clear()
    run_bench(
        instances(),
        ["fake-copy"],
        out,
        time_limit=5,
        force=True,
        progress=False,
        write_outputs=False,
    )
    assert sorted(CALLS) == ["tiny-a/copy", "tiny-b/copy"]


def test_resume_after_an_interrupted_run(tmp_path):
    out = tmp_path / "r"
    calls = 0

    def stop_after_first(row):
        nonlocal calls
        calls += 1
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_bench(instances(), ["fake-copy"], out, progress=False, on_cell=stop_after_first)
    assert len(load_rows(out)) == 1  # the finished cell was kept, outputs written for it
    assert (out / "results.csv").is_file()
    CALLS.clear()
    run = run_bench(instances(), ["fake-copy"], out, progress=False)
    assert len(CALLS) == 1 and len(run.reused) == 1 and len(run.rows) == 2


def test_unavailable_broken_and_inapplicable_methods_become_rows(tmp_path):
    run = run_bench(
        instances()[:1],
        ["fake-missing", "fake-broken", "fake-nothing", "fake-single-only"],
        tmp_path / "r",
        progress=False,
    )
    by = {r["method"]: r for r in run.rows}
    assert by["fake-missing"]["status"] == "skipped"
    assert "illuknit[imaginary]" in by["fake-missing"]["reason"]
    assert by["fake-broken"]["status"] == "error" and "boom" in by["fake-broken"]["reason"]
    assert by["fake-nothing"]["status"] == "timeout"
    assert by["fake-single-only"]["status"] == "skipped"
    assert "not applicable" in by["fake-single-only"]["reason"]
    summary = (tmp_path / "r" / "summary.md").read_text()
    assert "| fake-missing | skipped | needs the imaginary extra" in summary
    # skipped and errored cells are retried next time; a no-pattern timeout is a result
    CALLS.clear()
    again = run_bench(
        instances()[:1], ["fake-missing", "fake-nothing"], tmp_path / "r", progress=False
    )
    assert again.ran == ["tiny-a/fake-missing"] and again.reused == ["tiny-a/fake-nothing"]


def test_unknown_names_fail_before_anything_runs(tmp_path):
    with pytest.raises(UnknownNameError, match=r"valid: .*fake-copy"):
        run_bench(instances(), ["fake-copy", "nope"], tmp_path / "r", progress=False)
    assert not (tmp_path / "r").exists()
    with pytest.raises(UnknownNameError, match="executor"):
        run_bench(instances(), ["fake-copy"], tmp_path / "r", executor="slurm", progress=False)


def test_results_of_another_version_are_refused_unless_forced(tmp_path):
    out = tmp_path / "r"
    run_bench(instances()[:1], ["fake-copy"], out, progress=False)
    meta = json.loads((out / "bench.json").read_text())
    meta["illuknit_version"] = "0.0.1"
    (out / "bench.json").write_text(json.dumps(meta))
    with pytest.raises(ResultsVersionError, match=r"illuknit 0\.0\.1.*--force"):
        run_bench(instances()[:1], ["fake-copy"], out, progress=False)
    CALLS.clear()
    run = run_bench(instances()[:1], ["fake-copy"], out, force=True, progress=False)
    assert CALLS == ["tiny-a/copy"] and len(run.rows) == 1
    assert json.loads((out / "bench.json").read_text())["illuknit_version"] == __version__


def test_a_foreign_folder_is_not_used(tmp_path):
    (tmp_path / "r").mkdir()
    (tmp_path / "r" / "thesis.tex").write_text("precious")
    with pytest.raises(ResultsVersionError, match="does not look like a results folder"):
        run_bench(instances()[:1], ["fake-copy"], tmp_path / "r", progress=False)
    assert (tmp_path / "r" / "thesis.tex").read_text() == "precious"


def test_parallel_processes_give_the_same_rows(tmp_path):
    # Worker processes only know the built-in methods: the single-view compiler is one.
    single = parse_manifest(
        {
            "instance": [
                {
                    "name": f"s{k}",
                    "kind": "single",
                    "size": [6, 6],
                    "yarns": ["black", "white"],
                    "input": {"draw": d},
                }
                for k, d in enumerate(["plus", "heart", "circle"])
            ]
        }
    ).instances
    par = run_bench(single, ["single"], tmp_path / "p", jobs=2, progress=False)
    ser = run_bench(single, ["single"], tmp_path / "s", jobs=1, progress=False)
    keys = (
        "instance",
        "logical_error_a",
        "logical_error_b",
        "color_changes_mean",
        "carriage_passes",
    )
    assert [[r[k] for k in keys] for r in par.rows] == [[r[k] for k in keys] for r in ser.rows]
    assert all(r["status"] == "ok" for r in par.rows)


def test_dask_executor_with_a_local_cluster(tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    with (
        distributed.LocalCluster(
            n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        run = run_bench(
            instances(),
            ["fake-copy"],
            tmp_path / "d",
            executor="dask",
            dask_client=client,
            progress=False,
        )
    assert sorted(run.ran) == ["tiny-a/fake-copy", "tiny-b/fake-copy"]
    assert all(r["status"] == "ok" for r in run.rows)


def test_cli_bad_input_is_one_line_and_exit_2(tmp_path, capsys):
    from illuknit.cli import main

    manifest = tmp_path / "m.toml"
    manifest.write_text(
        '[[instance]]\nname = "x"\nsize = [6, 6]\nyarns = ["black", "white"]\n'
        'a = { draw = "plus" }\nb = { draw = "circle" }\n',
        encoding="utf-8",
    )
    cases = [
        (["--instances", "nope"], "unknown instance 'nope'; valid: quick, all, x"),
        (["--instances", "x", "--methods", "dp,zzz"], "unknown method 'zzz'; valid: default, all"),
        (["--instances", "x", "--jobs", "0"], "--jobs"),
    ]
    for args, msg in cases:
        with pytest.raises(SystemExit) as e:
            main(["bench", "--manifest", str(manifest), *args, "-o", str(tmp_path / "o")])
        assert e.value.code == 2
        err = capsys.readouterr().err
        assert msg in err and err.count("\n") == 1, err
    bad = tmp_path / "bad.toml"
    bad.write_text(
        '[[instance]]\nname = "x"\nsize = [6, 6]\nyarns = ["black", "white"]\n'
        'a = { draw = "plus" }\n',
        encoding="utf-8",
    )
    with pytest.raises(SystemExit) as e:
        main(["bench", "--manifest", str(bad), "-o", str(tmp_path / "o")])
    assert e.value.code == 2 and "needs input `b`" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_cli_runs_and_resumes(tmp_path):
    import subprocess

    manifest = tmp_path / "m.toml"
    manifest.write_text(
        '[[instance]]\nname = "x"\nkind = "single"\nsize = [6, 6]\nyarns = ["black", "white"]\n'
        'tags = ["quick"]\ninput = { draw = "plus" }\n',
        encoding="utf-8",
    )
    cmd = [sys.executable, "-m", "illuknit", "bench", "--manifest", str(manifest),
           "--methods", "single", "--no-progress", "-o", str(tmp_path / "o")]  # fmt: skip
    first = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert first.returncode == 0, first.stderr
    assert "1 cell(s) run, 0 reused" in first.stdout
    second = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert "0 cell(s) run, 1 reused" in second.stdout
    meta = tmp_path / "o" / "bench.json"
    meta.write_text(json.dumps({"format": "illuknit-bench-results", "illuknit_version": "9.9"}))
    third = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert third.returncode == 2 and "illuknit 9.9" in third.stderr
    assert "Traceback" not in third.stderr and third.stderr.count("\n") == 1


def test_times_and_solver_fields_are_recorded(tmp_path):
    run = run_bench(
        instances()[:1], ["fake-slow"], tmp_path / "r", progress=False, write_outputs=False
    )
    (row,) = run.rows
    assert row["wall_s"] >= 0.2 and row["solve_s"] == 0.15 and row["metrics_s"] > 0
    assert (row["status"], row["objective"], row["bound"], row["gap"]) == ("feasible", 10, 4, 0.6)


def test_a_solver_backend_missing_from_this_install_is_a_skipped_row(tmp_path, monkeypatch):
    import illuknit.solvers

    monkeypatch.setattr(illuknit.solvers, "available_backends", lambda: ["dp"])
    run = run_bench(
        instances()[:1], ["rc2", "dp"], tmp_path / "r", progress=False, write_outputs=False
    )
    by = {r["method"]: r for r in run.rows}
    assert by["rc2"]["status"] == "skipped" and "'rc2' is not available" in by["rc2"]["reason"]
    assert by["dp"]["status"] == "optimal"


def test_the_keywords_are_a_shorthand_for_bench_options(tmp_path):
    """``jobs=1, progress=False`` is ``options=BenchOptions(...)``; an unknown keyword is
    refused, named, before anything runs."""
    from illuknit.bench.runner import BenchOptions
    from illuknit.core.errors import OptionError

    quiet = BenchOptions(progress=False, write_outputs=False)
    run = run_bench(instances()[:1], ["fake-copy"], tmp_path / "o", options=quiet)
    again = run_bench(instances()[:1], ["fake-copy"], tmp_path / "o", progress=False)
    assert run.ran == again.reused == ["tiny-a/fake-copy"]
    with pytest.raises(OptionError, match="jobz"):
        run_bench(instances(), ["fake-copy"], tmp_path / "r", jobz=2)
    assert not (tmp_path / "r").exists()
