"""``--allow-long-floats`` on every command with ``--knitout``: refuse long floats by default
(one line, exit 2, the design written without its program), keep them with one warning line."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
from PIL import Image

from illuknit.core.machine import MACHINES, MachineSpec

# A machine whose float limit (one needle) a 2-yarn double-view pattern of speckled pictures
# cannot meet: its courses have more colour regions than carriers to keep them apart.
TIGHT = MachineSpec(name="Tight", float_limit=1, description="float limit 1 (tests)")


@pytest.fixture
def tight(monkeypatch):
    monkeypatch.setitem(MACHINES, "tight", TIGHT)
    return "tight"


@pytest.fixture
def speckled(tmp_path):
    rng = np.random.default_rng(0)
    paths = []
    for name in ("a", "b"):
        dark = (rng.random((8, 8)) < 0.5).repeat(3, 0).repeat(3, 1)
        grey = np.where(dark, 20, 240).astype(np.uint8)
        path = tmp_path / f"{name}.png"
        Image.fromarray(np.stack([grey] * 3, axis=2)).save(path)
        paths.append(path)
    return paths


def test_double_refuses_a_long_float_and_keeps_the_design(speckled, tight, tmp_path, run_cli):
    """A knitting refusal never loses the design: the folder is written, all but the program,
    with a note saying why; the one error line names the remedies measured on this pattern
    (tall bumps knit it here, or not: whatever was tried is named with what it gave), never
    'fewer --colors' for a two-colour design."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("mine")
    args = ["double", *speckled, "-o", out, "--candidates", 1, "--width", 12]
    code, _, err = run_cli([*args, "--knitout", "--machine", tight])
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("illuknit: error:")
    assert "longer than the float limit of 1 needles skipped" in err and "at course " in err
    assert "--allow-long-floats" in err and "--tall-bumps" in err and "--colors" not in err
    names = {p.name for p in out.iterdir()}
    assert {"keep.txt", "pattern.json", "summary.json", "program-refused.txt"} <= names
    assert "program.k" not in names
    note = (out / "program-refused.txt").read_text()
    assert "--tall-bumps" in note and "--allow-long-floats" in note
    assert (
        json.loads((out / "summary.json").read_text())["program_refused"]
        == (lines[0].partition("error: ")[2])
    )


def test_double_allow_long_floats_warns_how_long_and_where(speckled, tight, tmp_path, run_cli):
    out = tmp_path / "out"
    args = ["double", *speckled, "-o", out, "--candidates", 1, "--width", 12]
    code, _, err = run_cli([*args, "--knitout", "--machine", tight, "--allow-long-floats"])
    assert code == 0, err
    (warning,) = [line for line in err.splitlines() if line.startswith("illuknit: warning:")]
    summary = json.loads((out / "knit.json").read_text())
    assert summary["long_floats"] >= 1 and summary["longest_float"] > 1
    assert f"the longest, {summary['longest_float']} needles" in warning
    assert summary["longest_float_at"] in warning
    assert (out / "program.k").exists()


@pytest.mark.parametrize("command", ["single", "solve", "double"])
def test_allow_long_floats_without_knitout_is_refused(command, speckled, tmp_path, run_cli):
    pictures = speckled[:1] if command == "single" else speckled
    code, _, err = run_cli(
        [command, *pictures, "-o", tmp_path / "out", "--width", 8, "--allow-long-floats"]
    )
    assert code == 2 and "add --knitout" in err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("command", ["single", "solve"])
def test_allow_long_floats_is_accepted_with_knitout(command, speckled, tight, tmp_path, run_cli):
    # single-view patterns knit one colour per course (no floats); the solver's pattern of this
    # pair keeps its floats within the limit by tucking: both knit with and without the flag
    pictures = speckled[:1] if command == "single" else speckled
    for flag in ([], ["--allow-long-floats"]):
        out = tmp_path / f"out{len(flag)}"
        args = [command, *pictures, "-o", out, "--width", 8, "--knitout", "--machine", tight]
        code, _, err = run_cli([*args, *flag])
        assert code == 0, err
        assert json.loads((out / "knit.json").read_text())["long_floats"] == 0
        assert "illuknit: warning:" not in err


def _commands():
    import importlib

    from illuknit.cli import COMMANDS

    for name, target in COMMANDS.items():
        module, _, attr = target.partition(":")
        cmd = getattr(importlib.import_module(module), attr)
        subs = getattr(cmd, "commands", {}) or {"": cmd}
        for sub, c in subs.items():
            yield f"{name} {sub}".strip(), c


def test_every_command_with_knitout_takes_allow_long_floats():
    with_knitout = {
        name: {p.name for p in c.params}
        for name, c in _commands()
        if any(p.name == "knitout" for p in c.params)
    }
    assert {"single", "double", "headon", "solve", "demo", "calibrate swatch"} <= set(with_knitout)
    for name, params in with_knitout.items():
        assert "allow_long_floats" in params, name


def test_a_refused_split_bump_design_measures_the_default_share(speckled, tight, tmp_path, run_cli):
    """A split-bump design refused for a long float is designed again at the default split
    share and knit: what that gave (it knits, or it is refused too) is in the error line, the
    folder's note and summary.json, measured, not guessed."""
    out = tmp_path / "out"
    args = ["double", *speckled, "-o", out, "--candidates", 1, "--width", 12]
    code, _, err = run_cli([*args, "--split-share", "1.0", "--knitout", "--machine", tight])
    assert code == 2, err
    assert "designed again with --split-share 0.75, it " in err
    assert re.search(r"it (knits \(measured: \d+ split bumps|is refused too)", err), err
    note = (out / "program-refused.txt").read_text()
    assert "Designed again with --split-share 0.75" in note
    refused = json.loads((out / "summary.json").read_text())["program_refused"]
    assert "designed again with --split-share 0.75" in refused
    assert "program.k" not in {p.name for p in out.iterdir()}
