"""A switch that changes nothing says so, with why; a picture keeps its colour count unless
told otherwise, or a note says what was chosen (issue 33, item 4)."""

from __future__ import annotations

import json

import numpy as np
from PIL import Image

from illuknit.core.pattern import load_pattern
from illuknit.pictures.drawings import draw_text


def _levels(path, levels, shape=(18, 24)):
    """A picture of ``len(levels)`` flat grey levels in vertical bands."""
    x = np.empty((*shape, 3), np.uint8)
    bands = np.array_split(np.arange(shape[1]), len(levels))
    for band, v in zip(bands, levels, strict=True):
        x[:, band] = v
    Image.fromarray(x).save(path)
    return path


def _word(path, word, shape=(16, 24)):
    mask = draw_text(word, shape=shape)
    Image.fromarray(np.where(mask, 24, 246).astype(np.uint8)).convert("RGB").save(path)
    return path


def test_three_level_pictures_keep_three_colours_and_say_so(tmp_path, run_cli):
    a = _levels(tmp_path / "a.png", (20, 128, 240))
    b = _levels(tmp_path / "b.png", (240, 20, 128), shape=(18, 24))
    out = tmp_path / "out"
    code, text, err = run_cli(["double", a, b, "--candidates", 1, "-o", out])
    assert code == 0, err
    summary = json.loads((out / "summary.json").read_text())
    assert len(summary["yarns"]) == 3
    assert any("3, the pictures' own count" in n for n in summary["notes"])
    assert "note: colours: 3" in text and "--colors N chooses another" in text
    # told otherwise, no note and the count asked for
    code, text, err = run_cli(["double", a, b, "--candidates", 1, "--colors", 2, "-o", out])
    assert code == 0, err
    assert len(json.loads((out / "summary.json").read_text())["yarns"]) == 2
    assert "note: colours" not in text


def test_a_reduced_picture_is_named(tmp_path, run_cli):
    a = _levels(tmp_path / "three.png", (20, 128, 240))
    b = _word(tmp_path / "b.png", "ON", shape=(18, 24))
    code, text, err = run_cli(["double", a, b, "--candidates", 1, "-o", tmp_path / "out"])
    assert code == 0, err
    assert "quantised to 2 (the default), though three.png has 3 flat colours" in text


def test_split_bumps_that_change_nothing_say_so(tmp_path, run_cli):
    a, b = _word(tmp_path / "a.png", "UP"), _word(tmp_path / "b.png", "ON")
    out = tmp_path / "out"
    code, text, err = run_cli(["double", a, b, "--candidates", 2, "--split-bumps", "-o", out])
    assert code == 0, err
    summary = json.loads((out / "summary.json").read_text())
    used = [int(load_pattern(out / f"candidate_{k}" / "pattern.json").split.sum()) for k in (1, 2)]
    said = any(n.startswith("--split-bumps changed nothing") for n in summary["notes"])
    assert said == (not any(used)), (used, summary["notes"])
    assert said, "these pictures need no split bump at the default share (the case to test)"
    assert "note: --split-bumps changed nothing" in text and "split share 0.75" in text
    assert "note: --split-bumps" in (out / "summary.txt").read_text()
