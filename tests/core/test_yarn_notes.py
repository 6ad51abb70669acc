"""Yarns that work but may not be what was meant get one ``note:`` line: two yarns of one name,
colours closer than a just-noticeable difference, control characters in a name (removed
everywhere the name is written)."""

from __future__ import annotations

import json
import unicodedata
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from skimage.color import deltaE_ciede2000, rgb2lab

from illuknit.core.colors import hex_color
from illuknit.core.pattern import (
    JUST_NOTICEABLE_DE,
    Yarn,
    YarnNote,
    clean_yarn_name,
    load_pattern,
    parse_yarns,
    pattern_from_json,
    pattern_to_json,
)


def notes(fn, *args):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = fn(*args)
    return out, [str(w.message) for w in caught if issubclass(w.category, YarnNote)]


def test_two_yarns_of_one_name_are_told_and_renamed():
    yarns, said = notes(parse_yarns, "navy=#000080,navy=#f4f0e8,navy 2=#1b1b1b")
    assert [y.name for y in yarns] == ["navy", "navy 3", "navy 2"]  # never a second "navy 2"
    assert len(said) == 1 and "two yarns are named 'navy'" in said[0]


def test_distinct_yarns_say_nothing():
    _, said = notes(parse_yarns, "black=#1b1b1b,white=#f4f0e8,red")
    assert said == []


def de(a, b) -> float:
    lab = rgb2lab(np.array([[a, b]], dtype=np.float64) / 255.0)[0]
    return float(deltaE_ciede2000(lab[0], lab[1]))


@settings(max_examples=60, deadline=None)
@given(
    st.tuples(*[st.integers(0, 255)] * 3),
    st.tuples(*[st.integers(-3, 3)] * 3),
)
def test_close_colours_are_told_exactly_below_a_just_noticeable_difference(rgb, step):
    other = tuple(min(255, max(0, v + d)) for v, d in zip(rgb, step, strict=True))
    if other == rgb:
        return
    _, said = notes(parse_yarns, f"a={hex_color(rgb)},b={hex_color(other)}")
    close = [s for s in said if "just-noticeable" in s]
    assert bool(close) == (de(rgb, other) < JUST_NOTICEABLE_DE), (rgb, other, said)


CONTROL_NAMES = ["navy\x1b[31m", "na\x00vy", "navy\nblue", "\u202enavy", "navy\x07\x7f\x9b"]


@pytest.mark.parametrize("raw", CONTROL_NAMES)
def test_control_characters_are_removed_and_told(raw):
    clean = clean_yarn_name(raw)
    assert clean and not any(unicodedata.category(c) == "Cc" for c in clean)
    assert "\u202e" not in clean
    assert Yarn(raw, (0, 0, 128)).name == clean
    yarns, said = notes(parse_yarns, [f"{raw}=#000080", "white"])
    assert yarns[0].name == clean
    assert len(said) == 1 and "control characters" in said[0]
    assert "\x1b" not in said[0]  # the note shows them escaped, never raw


def test_a_pattern_file_with_control_characters_in_a_name(tmp_path):
    from illuknit.core.pattern import LogicalPattern

    p = LogicalPattern(np.zeros((2, 2), int), np.zeros((2, 2), bool), (Yarn("ok", (0, 0, 0)),))
    doc = pattern_to_json(p)
    doc["yarns"][0]["name"] = "ok\x1b]0;pwned\x07"
    loaded, said = notes(pattern_from_json, doc)
    assert loaded.yarns[0].name == "ok]0;pwned" and len(said) == 1
    path = tmp_path / "p.json"
    path.write_text(json.dumps(doc))
    with pytest.warns(YarnNote, match="control characters"):
        assert load_pattern(path).yarns[0].name == "ok]0;pwned"


def test_the_command_line_notes_once_and_writes_clean_names(picture, tmp_path, run_cli):
    out = tmp_path / "out"
    r = run_cli(["single", picture, "--yarns", "ink\x1b\x07=#1b1b1b,ink=#f4f0e8", "-o", out])
    assert r.code == 0, r.err
    lines = [line for line in r.err.splitlines() if "note:" in line]
    assert len(lines) == 2, r.err  # control characters; two yarns named 'ink'
    assert any("control characters" in line for line in lines)
    assert any("two yarns are named 'ink'" in line for line in lines)
    assert "\x1b" not in r.out + r.err
    for name in ("instructions.txt", "legend.json", "pattern.json", "report.json"):
        text = (out / name).read_text()
        for bad in ("\x1b", "\x07", "\\u001b", "\\u0007"):
            assert bad not in text, (name, bad)
    assert "ink 2" in (out / "instructions.txt").read_text()


def test_close_yarns_on_the_command_line_are_one_note(picture, tmp_path, run_cli):
    r = run_cli(["single", picture, "--yarns", "#1b1b1b,#1c1b1b", "-o", tmp_path / "o"])
    lines = [line for line in r.err.splitlines() if "note:" in line]
    assert len(lines) == 1 and "just-noticeable" in lines[0], r.err
