"""``illuknit knit`` on colour-changing patterns: ablation switches, summaries and bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest

from illuknit.core.pattern import LogicalPattern, Yarn, save_pattern

YARNS = (Yarn("navy", (29, 43, 83)), Yarn("cream", (244, 240, 232)))


@pytest.fixture
def plus(tmp_path):
    yarn = np.zeros((6, 6), np.int16)
    yarn[:, 2:4] = 1
    raised = np.zeros((6, 6), bool)
    raised[2:4, :] = True
    path = tmp_path / "plus.json"
    save_pattern(LogicalPattern(yarn, raised, YARNS), path)
    return path


def test_mixed_pattern_knits_and_reports_its_passes(plus, tmp_path, run_cli):
    out = tmp_path / "prog.k"
    code, stdout, err = run_cli(["knit", str(plus), "-o", str(out)])
    assert code == 0, err
    assert "mixed colourwork:" in stdout and "plated" in stdout
    assert "check: 0 error(s)" in stdout
    code, stdout, _ = run_cli(["knit", str(plus), "-o", str(out), "--json"])
    s = json.loads(stdout)
    assert s["scheduler"] == "mixed-colourwork"
    assert s["lower_bound"] <= s["passes"] and s["ratio"] >= 1
    for key in ("knit_passes", "transfer_passes", "kickbacks", "explicit_kickbacks"):
        assert key in s


@pytest.mark.parametrize(
    ("flag", "code_name"),
    [
        ("--no-float-avoidance", "face-float"),
        ("--no-catching", "pieces"),
        ("--path-planning=none", "wrong-side-carrier"),
    ],
)
def test_each_ablation_is_caught_by_the_check_and_exits_1(plus, tmp_path, run_cli, flag, code_name):
    out = tmp_path / "prog.k"
    code, stdout, _ = run_cli(["knit", str(plus), "-o", str(out), flag, "--json"])
    assert code == 1
    s = json.loads(stdout)
    assert s["check"]["errors"] > 0
    assert code_name in {f["code"] for f in s["check"]["findings"]}
    assert out.exists()  # the program is still written, for inspection


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--catching", "--no-catching"], "contradict"),
        (["--plate", "--no-catching"], "contradict"),
        (["--strict-floats", "--allow-long-floats"], "contradict"),
        (["--float-avoidance", "--no-float-avoidance"], "contradict"),
        (["--path-planning", "none", "--path-planning", "split"], "contradictory"),
        (["--path-planning", "zigzag"], "zigzag"),
        (["--float-limit", "0"], "--float-limit"),
        (["--catch-every", "0"], "--catch-every"),
    ],
)
def test_bad_switches_are_one_line_exit_2_and_nothing_written(
    plus, tmp_path, run_cli, args, message
):
    out = tmp_path / "prog.k"
    code, _, err = run_cli(["knit", str(plus), "-o", str(out), *args])
    assert code == 2
    assert err.startswith("illuknit: error:") and message in err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert not out.exists()


def test_strict_floats_error_names_the_course_and_row(tmp_path, run_cli):
    yarn = np.zeros((2, 12), np.int16)
    yarn[0, ::2] = 1  # top row: six one-unit runs of each yarn, 2 wales apart
    path = tmp_path / "stripes.json"
    save_pattern(LogicalPattern(yarn, np.zeros((2, 12), bool), YARNS), path)
    out = tmp_path / "p.k"
    args = ["knit", str(path), "-o", str(out), "--float-limit", "1"]
    code, _, err = run_cli([*args, "--strict-floats"])
    assert code == 2 and not out.exists()
    assert "course 2 (pattern row 0) needs 12 carriers" in err
    assert "fewer yarns" in err and "float limit" in err and err.count("\n") == 1
    # without --strict-floats the shortest gaps are bridged and the program is written
    code, stdout, _ = run_cli([*args, "--json"])
    assert code == 0 and out.exists()
    assert json.loads(stdout)["carriers"] <= 10


@pytest.mark.parametrize("command", ["double", "headon"])
def test_design_commands_write_a_checked_program_with_knitout(tmp_path, run_cli, command):
    from PIL import Image

    from illuknit.pictures.drawings import draw_shape

    paths = []
    for name in ("plus", "circle"):
        mask = draw_shape(name, (6, 8))
        path = tmp_path / f"{name}.png"
        Image.fromarray(np.where(mask, 20, 235).astype(np.uint8)).save(path)
        paths.append(str(path))
    if command == "headon":
        paths = paths[:1]
    out = tmp_path / "out"
    code, _, err = run_cli([command, *paths, "-o", str(out), "--candidates", "1", "--knitout"])
    assert code == 0, err
    report = json.loads((out / "check.json").read_text())
    assert report["ok"] and report["pieces"] == 1
    assert (out / "program.k").read_text().startswith(";!knitout-2\n")


def test_calibration_swatch_command_writes_a_checked_program(tmp_path, run_cli):
    out = tmp_path / "swatch"
    args = ["calibrate", "swatch", "-o", str(out), "--bump-sizes", "1", "--flat-sizes", "1,2"]
    code, _, err = run_cli([*args, "--cell-width", "3", "--knitout"])
    assert code == 0, err
    report = json.loads((out / "check.json").read_text())
    assert report["ok"] and report["pieces"] == 1
    assert json.loads((out / "knit.json").read_text())["scheduler"] == "mixed-colourwork"


def test_tuck_passes_flag_tucks_plated_floats_in_passes_of_their_own(tmp_path, run_cli):
    from tests.knit.test_float_tucks import _random_mixed

    pattern, limit = _random_mixed(3)  # 2 x 14, a plated pass whose float cannot tuck in it
    path = tmp_path / "p.json"
    save_pattern(pattern, path)
    base = ["knit", str(path), "--float-limit", str(limit), "--json", "--plate"]
    # by default a float that stays long is refused, naming where and what to change
    code0, _, err0 = run_cli([*base, "-o", str(tmp_path / "x.k")])
    assert code0 == 2 and len(err0.strip().splitlines()) == 1
    assert "longer than the float limit" in err0 and "--allow-long-floats" in err0
    assert not (tmp_path / "x.k").exists()
    base.append("--allow-long-floats")
    code, stdout, err = run_cli([*base, "-o", str(tmp_path / "a.k")])
    assert "warning:" in err and "needles" in err and " at " in err
    plain = json.loads(stdout)
    code2, stdout2, _ = run_cli([*base, "-o", str(tmp_path / "b.k"), "--tuck-passes"])
    tucked = json.loads(stdout2)
    assert code == code2 == 0
    assert tucked["long_floats"] < plain["long_floats"]
    assert tucked["passes"] > plain["passes"]
