"""``--machine`` and ``--knitout``: one machine from sizing through scheduling to checking."""

from __future__ import annotations

import json

import pytest

from illuknit.core.machine import machine_names


def test_single_gauge_is_the_gauge_knit_on(picture, tmp_path, run_cli):
    out = tmp_path / "out"
    code, _, err = run_cli(
        ["single", picture, "--width", 30, "--gauge", 12, "--knitout", "-o", out]
    )
    assert code == 0, err
    summary = json.loads((out / "knit.json").read_text())
    assert summary["gauge"] == 12
    assert ";;Gauge: 12" in (out / "program.k").read_text()
    check = json.loads((out / "check.json").read_text())
    assert check["blocking"] == 0 and check["machine"]["gauge"] == 12


def test_machine_preset_sets_the_bed(picture, tmp_path, run_cli):
    out = tmp_path / "out"
    code, _, err = run_cli(
        ["single", picture, "--width", 30, "--knitout", "--machine", "swg091n2", "-o", out],
    )
    assert code == 0, err
    assert json.loads((out / "knit.json").read_text())["needles"] == 252
    assert ";;Width: 252" in (out / "program.k").read_text()
    code, stdout, _ = run_cli(["check", out / "program.k"])
    assert code == 0 and "machine SWG091N2: 252 needles" in stdout


def test_pattern_wider_than_the_bed_is_refused_before_any_work(picture, tmp_path, run_cli):
    out = tmp_path / "out"
    code, _, err = run_cli(
        ["single", picture, "--width", 124, "--knitout", "--machine", "swg091n2", "-o", out],
    )
    assert code == 2
    assert err.startswith("illuknit: error:") and err.count("\n") == 1
    assert "124 units" in err and "at most 123 units" in err
    assert not out.exists()
    # without --knitout the design alone is not limited by a bed
    code, _, err = run_cli(["single", picture, "--width", 124, "-o", out])
    assert code == 0, err


@pytest.mark.parametrize("command", ["single", "check", "knit"])
def test_unknown_machine_lists_the_known_ones(command, picture, tmp_path, run_cli):
    out = tmp_path / "out"
    args = {
        "single": ["single", picture, "--knitout", "-o", out],
        "check": ["check", picture],
        "knit": ["knit", picture, "-o", tmp_path / "p.k"],
    }[command]
    code, _, err = run_cli([*args, "--machine", "knitmaster"])
    assert code == 2 and err.count("\n") == 1
    assert "knitmaster" in err and all(name in err for name in machine_names())
    assert not out.exists() and not (tmp_path / "p.k").exists()
