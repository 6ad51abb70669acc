"""``made_for="hands"`` on the constraint models (issue 37 item 1): every row knittable by hand
is a hard constraint of the model, judged on the pattern by the hand measure, never by the
solver's word; where it cannot apply it is refused in one line, never silently ignored."""

from __future__ import annotations

import json

import numpy as np
import pytest
from PIL import Image

from illuknit.cli import main
from illuknit.core.errors import OptionError, SolverError
from illuknit.design.hand_cost import hand_cost
from illuknit.design.options import MadeFor, ModelKind, SolveOptions
from illuknit.pipeline.solve import check_made_for, solve_design


def _pictures(seed: int = 0, shape: tuple[int, int] = (10, 20)) -> tuple[np.ndarray, np.ndarray]:
    """Two black-and-white noise pictures: many colour changes a row, not knittable as drawn."""
    rng = np.random.default_rng(seed)
    a, b = ((rng.random(shape) < 0.5).astype(np.uint8) * 255 for _ in range(2))
    return np.stack([a] * 3, -1), np.stack([b] * 3, -1)


def test_a_design_made_for_hands_has_every_row_knittable():
    a, b = _pictures()
    opts = SolveOptions(time_limit=3)
    machine = solve_design(a, b, options=opts, width=20)
    hands = solve_design(a, b, options=opts, width=20, made_for="hands")
    assert hand_cost(machine.pattern).knittable_rows < hand_cost(machine.pattern).rows
    cost = hand_cost(hands.pattern)
    assert cost.knittable_rows == cost.rows
    assert hands.report["made_for"] == "hands"
    assert hands.report["hand"] == cost.to_json()  # measured on the pattern written
    assert "made_for" not in machine.report  # the machine's report is as before
    assert hands.report["solver"]["stats"]["warm_start"]["method"] == "hand"
    assert hands.options.made_for is MadeFor.HANDS


def test_check_made_for_and_the_refusals():
    assert check_made_for(None) is MadeFor.MACHINE
    assert check_made_for("hands") is MadeFor.HANDS
    with pytest.raises(OptionError):
        check_made_for("feet")
    with pytest.raises(OptionError, match="single-view model"):
        SolveOptions(model=ModelKind.SINGLE, made_for="hands")
    with pytest.raises(OptionError, match="split bumps"):
        SolveOptions(split_bumps=True, made_for="hands")
    a, b = _pictures()
    with pytest.raises(SolverError, match=r"hands-14x20.*couples the units of every row"):
        solve_design(a, b, options=SolveOptions(solver="dp"), width=20, made_for="hands")


def _save(tmp_path, a, b):
    Image.fromarray(a).save(tmp_path / "a.png")
    Image.fromarray(b).save(tmp_path / "b.png")
    return [str(tmp_path / "a.png"), str(tmp_path / "b.png")]


def test_the_command_writes_a_design_made_for_hands(tmp_path, capsys):
    pics = _save(tmp_path, *_pictures(1))
    out = tmp_path / "o"
    main(["solve", *pics, "-o", str(out), "--for", "hands", "--time-limit", "3", "--width", "20"])
    report = json.loads((out / "report.json").read_text())
    assert report["made_for"] == "hands"
    assert report["hand"]["knittable_rows"] == report["hand"]["rows"]
    assert (out / "pattern.pdf").is_file()
    text = " ".join(capsys.readouterr().out.split())
    assert f"about {report['hand']['hours']:.1f} hours by hand" in text


@pytest.mark.parametrize(
    ("extra", "said"),
    [(["--model", "single"], "single-view model"), (["--split-bumps"], "split bumps")],
)
def test_the_command_refuses_hands_where_it_cannot_apply(tmp_path, capsys, extra, said):
    a, b = _pictures(2)
    pics = _save(tmp_path, a, b)[: 1 if "single" in extra else 2]
    out = tmp_path / "o"
    with pytest.raises(SystemExit) as exc:
        main(["solve", *pics, "-o", str(out), "--for", "hands", *extra])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert said in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1
    assert not out.exists()
