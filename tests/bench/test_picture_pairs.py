"""``illuknit bench --pair A.png B.png``: a user's pictures as solver-benchmark instances, sized
and modelled as ``illuknit solve`` would, judged against the exact reference (the DP)."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest
from PIL import Image, ImageDraw

from illuknit.bench.pictures import picture_instances
from illuknit.bench.solver_runs import SolverTask, build_task_model
from illuknit.bench.wcnf_files import read_wcnf
from illuknit.cli import main
from illuknit.core.errors import OptionError
from illuknit.solvers import solve


@pytest.fixture
def pair(tmp_path):
    """Two tiny two-colour pictures of different shapes (12 x 10 pixels)."""
    paths = []
    for name, box, shape in (("ring", (2, 2, 9, 9), "ellipse"), ("bar", (3, 1, 8, 8), "rect")):
        im = Image.new("RGB", (12, 10), "white")
        draw = ImageDraw.Draw(im)
        (draw.ellipse if shape == "ellipse" else draw.rectangle)(box, fill="black")
        im.save(tmp_path / f"{name}.png")
        paths.append(str(tmp_path / f"{name}.png"))
    return paths


def _rows(folder: Path) -> list[dict[str, str]]:
    with (folder / "solvers.csv").open() as fh:
        return list(csv.DictReader(fh))


def test_a_picture_pair_runs_end_to_end_against_the_exact_reference(pair, tmp_path, capsys):
    out = tmp_path / "out"
    main(["bench", "--pair", *pair, "--solvers", "rc2,dp", "--time-limit", "20", "-o", str(out)])
    said = capsys.readouterr().out
    assert "ring+bar: " in said and "logical reference (dp)" in said
    rows = {r["solver"]: r for r in _rows(out)}
    assert set(rows) == {"rc2", "dp"}
    for r in rows.values():
        assert r["instance"] == "ring+bar" and r["model"] == "logical"
        assert r["status"] == "optimal" and not r["flag"], r
        assert r["certificate"] == "reference (dp)"
        assert r["verified_cost"] == r["reference_optimum"] != ""
    assert rows["rc2"]["rows"] and rows["rc2"]["cols"]


def test_the_bench_models_a_pair_exactly_as_solve_does(pair, tmp_path):
    """Same sizing policy and model builder: the formula equals ``solve --export-wcnf``'s."""
    wcnf = tmp_path / "solve.wcnf"
    main(["solve", *pair, "--width", "8", "--colors", "2", "--export-wcnf", str(wcnf)])
    from illuknit.cli.knitout_bridge import design_unit_aspect, resolve_machine

    (inst,) = picture_instances(
        [tuple(pair)], width=8, n_colors=2, unit_aspect=design_unit_aspect(resolve_machine(None))
    )
    model, optimum = build_task_model(SolverTask(inst, "logical", "rc2"))
    assert model.to_wcnf(style="new") == wcnf.read_text()
    assert inst.size[1] == 8 and optimum is not None
    # the reference is the file's optimum, whoever reads the file
    assert read_wcnf(wcnf).evaluate(solve(model, solver="dp").values) == (True, optimum)


def test_a_pair_is_built_once_on_the_client_and_travels_built(pair, monkeypatch):
    """A worker never reads the picture files: the task carries the built model."""
    import pickle

    (inst,) = picture_instances([tuple(pair)], models=["logical", "knit-aware"])
    shipped = pickle.loads(pickle.dumps(SolverTask(inst, "knit-aware", "rc2")))
    for p in pair:
        Path(p).unlink()
    model, optimum = build_task_model(shipped)
    assert optimum is None and model.num_soft == inst.model("knit-aware")[0].num_soft
    with pytest.raises(OptionError, match="not 'single'"):
        inst.model("single")


def test_pairs_get_distinct_names_and_single_is_refused(pair):
    got = picture_instances([tuple(pair), tuple(pair), (pair[0], pair[0])])
    assert [i.name for i in got] == ["ring+bar", "ring+bar-2", "ring+ring"]
    assert got[2].model("logical")[1] == 0  # the same picture both ways: no mismatch at all
    with pytest.raises(OptionError, match="`models`"):
        picture_instances([tuple(pair)], models=["single"])


@pytest.mark.parametrize(
    "args",
    [
        ["--pair", "{bad}", "{good}"],
        ["--pair", "{missing}", "{good}"],
        ["--pair", "{folder}", "{good}"],
        ["--pair", "{good}", "{good}", "--yarns", "red"],
        ["--width", "8"],
        ["--colors", "3"],
    ],
)
def test_bad_pictures_and_misplaced_sizing_are_one_line_errors(args, pair, tmp_path, capsys):
    bad = tmp_path / "bad.png"
    bad.write_text("not a picture")
    names = {"bad": bad, "missing": tmp_path / "missing.png", "folder": tmp_path, "good": pair[0]}
    argv = [a.format(**names) for a in args]
    with pytest.raises(SystemExit) as e:
        main(["bench", *argv, "--solvers", "rc2", "-o", str(tmp_path / "out")])
    assert e.value.code == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert not (tmp_path / "out").exists()
