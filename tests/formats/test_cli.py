"""``--format dat``: the Shima .dat from ``illuknit knit`` and beside ``program.k`` of every
``--knitout`` command; refused formats exit 2 with nothing written."""

from __future__ import annotations

import numpy as np
import pytest

from illuknit.core.pattern import LogicalPattern, parse_yarns, save_pattern
from illuknit.formats.dat import knitout_to_dat, read_dat
from tests.formats.reference import reference_dat


@pytest.fixture
def pattern_file(tmp_path):
    rng = np.random.default_rng(3)
    yarn = rng.integers(0, 2, (4, 6)).astype(np.int16)
    pattern = LogicalPattern(yarn, rng.random((4, 6)) < 0.5, parse_yarns("#1b1b1b,#f4f0e8"))
    path = tmp_path / "p.json"
    save_pattern(pattern, path)
    return path


def test_knit_writes_the_dat_of_its_knitout(pattern_file, tmp_path, run_cli):
    code, out, err = run_cli(["knit", pattern_file, "--format", "dat", "-o", tmp_path / "a.dat"])
    assert code == 0, err
    assert "dat file" in out
    code, _, err = run_cli(["knit", pattern_file, "-o", tmp_path / "a.k"])
    assert code == 0, err
    text = (tmp_path / "a.k").read_text()
    data = (tmp_path / "a.dat").read_bytes()
    assert data == knitout_to_dat(text)
    assert len(read_dat(data).passes) > 0


def test_knit_dat_is_the_reference_backends(pattern_file, tmp_path, run_cli, swg_backend):
    code, _, err = run_cli(["knit", pattern_file, "-o", tmp_path / "a.k"])
    assert code == 0, err
    run_cli(["knit", pattern_file, "--format", "dat", "-o", tmp_path / "a.dat"])
    assert (tmp_path / "a.dat").read_bytes() == reference_dat(
        (tmp_path / "a.k").read_text(), swg_backend
    )


def test_knit_refuses_unknown_format_with_nothing_written(pattern_file, tmp_path, run_cli):
    code, _, err = run_cli(["knit", pattern_file, "--format", "gif", "-o", tmp_path / "a.gif"])
    assert code == 2 and "gif" in err
    assert not (tmp_path / "a.gif").exists()


def test_kniterate_cannot_take_a_dat(pattern_file, tmp_path, run_cli):
    out = tmp_path / "a.dat"
    args = ["knit", pattern_file, "--machine", "kniterate", "--format", "dat", "-o", out]
    code, _, err = run_cli(args)
    assert code == 2 and err.count("\n") == 1 and "valid: knitout, kc" in err
    assert not out.exists()


def test_knit_summary_counts_the_machines_passes(pattern_file, tmp_path, run_cli):
    code, out, err = run_cli(["knit", pattern_file, "--json", "-o", tmp_path / "a.k"])
    assert code == 0, err
    import json

    from illuknit.formats import machine_passes

    summary = json.loads(out)
    assert summary["machine_passes"] == len(machine_passes((tmp_path / "a.k").read_text()))


@pytest.fixture
def picture(box_picture):
    return box_picture((12, 12))


def test_single_knitout_writes_program_dat_beside_program_k(picture, tmp_path, run_cli):
    out = tmp_path / "out"
    code, _, err = run_cli(
        ["single", picture, "--width", 8, "--knitout", "--format", "dat", "-o", out]
    )
    assert code == 0, err
    assert (out / "program.dat").read_bytes() == knitout_to_dat((out / "program.k").read_text())


def test_format_without_knitout_is_refused_before_any_work(picture, tmp_path, run_cli):
    out = tmp_path / "out"
    code, _, err = run_cli(["single", picture, "--width", 8, "--format", "dat", "-o", out])
    assert code == 2
    assert err.count("\n") == 1 and "--knitout" in err
    assert not out.exists()
