import json

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from illuknit.core.errors import PatternFormatError, PatternValidationError, YarnSpecError
from illuknit.core.pattern import (
    LogicalPattern,
    Yarn,
    load_pattern,
    parse_yarns,
    pattern_from_json,
    pattern_to_json,
    save_pattern,
)

YARNS3 = parse_yarns("#1b1b1b,#f4f0e8,#c0392b")


@st.composite
def patterns(draw, max_side=12):
    n = draw(st.integers(1, max_side))
    m = draw(st.integers(1, max_side))
    k = draw(st.integers(1, 3))
    yarn = draw(arrays(np.int16, (n, m), elements=st.integers(0, k - 1)))
    raised = draw(arrays(np.bool_, (n, m)))
    meta = draw(
        st.dictionaries(st.text(max_size=5), st.integers() | st.text(max_size=5), max_size=3)
    )
    return LogicalPattern(yarn, raised, YARNS3[:k], meta)


@given(patterns())
def test_json_round_trip_is_identical(p):
    assert pattern_from_json(json.loads(json.dumps(pattern_to_json(p)))) == p


def test_save_load_round_trip(tmp_path):
    p = LogicalPattern(np.array([[0, 1], [2, 0]]), np.array([[1, 0], [0, 1]]), YARNS3, {"a": 1})
    save_pattern(p, tmp_path / "p.json")
    assert load_pattern(tmp_path / "p.json") == p
    assert not list(tmp_path.glob(".*tmp"))


def test_pattern_is_immutable():
    p = LogicalPattern(np.zeros((2, 2), int), np.zeros((2, 2), bool), YARNS3[:1])
    with pytest.raises(ValueError):
        p.yarn[0, 0] = 1
    with pytest.raises(AttributeError):
        p.yarns = ()  # type: ignore[misc]


@pytest.mark.parametrize(
    ("yarn", "raised", "yarns", "match"),
    [
        (np.zeros((2, 2), int), np.zeros((2, 3), bool), YARNS3, "shape"),
        (np.zeros((2,), int), np.zeros((2,), bool), YARNS3, "2-D"),
        (np.full((2, 2), 3), np.zeros((2, 2), bool), YARNS3, "0..2"),
        (np.full((2, 2), -1), np.zeros((2, 2), bool), YARNS3, "0..2"),
        (np.zeros((2, 2), int), np.zeros((2, 2), bool), (), "non-empty"),
        (np.zeros((0, 2), int), np.zeros((0, 2), bool), YARNS3, "at least one unit"),
        (np.zeros((2, 1001), int), np.zeros((2, 1001), bool), YARNS3, "limit"),
        (np.full((2, 2), 0.5), np.zeros((2, 2), bool), YARNS3, "integers"),
    ],
)
def test_invalid_patterns_are_rejected(yarn, raised, yarns, match):
    with pytest.raises(PatternValidationError, match=match):
        LogicalPattern(yarn, raised, yarns)


def test_yarn_parsing():
    ys = parse_yarns("#1b1b1b, navy ,Light=#eee")
    assert [y.rgb for y in ys] == [(27, 27, 27), (0, 0, 128), (238, 238, 238)]
    assert ys[1].name == "navy" and ys[2].name == "Light"
    assert ys[0].name  # named after the nearest colour
    with pytest.raises(YarnSpecError, match="unknown yarn colour"):
        parse_yarns("#1b1b1b,notacolour")
    with pytest.raises(YarnSpecError, match="duplicate"):
        parse_yarns("white,#ffffff")
    with pytest.raises(YarnSpecError):
        parse_yarns(" , ")


def _doc():
    p = LogicalPattern(np.array([[0, 1], [1, 0]]), np.array([[1, 0], [0, 1]]), YARNS3[:2])
    return pattern_to_json(p)


@pytest.mark.parametrize(
    ("mutate", "match"),
    [
        (lambda d: d.update(version=3), "version 3"),
        (lambda d: d.update(format="other"), "not an illuknit pattern"),
        (lambda d: d.update(yarn=["02", "10"]), "out of range"),
        (lambda d: d.update(yarn=["0!", "10"]), "digits"),
        (lambda d: d.update(raised=["1x", "01"]), "'0' or '1'"),
        (lambda d: d.update(rows=3), "declares 3 rows"),
        (lambda d: d.pop("yarns"), "malformed"),
        (lambda d: d.update(yarn=["011", "10"]), "2 characters"),
    ],
)
def test_bad_pattern_files(mutate, match, tmp_path):
    d = _doc()
    mutate(d)
    with pytest.raises(PatternFormatError, match=match):
        pattern_from_json(d)
    f = tmp_path / "p.json"
    f.write_text(json.dumps(d))
    with pytest.raises(PatternFormatError):
        load_pattern(f)


def test_unreadable_pattern_files(tmp_path):
    with pytest.raises(PatternFormatError, match="not found"):
        load_pattern(tmp_path / "missing.json")
    (tmp_path / "x.json").write_text("{not json")
    with pytest.raises(PatternFormatError, match="not valid JSON"):
        load_pattern(tmp_path / "x.json")
    (tmp_path / "b.json").write_bytes(b"\xff\xfe\x00binary")
    with pytest.raises(PatternFormatError):
        load_pattern(tmp_path / "b.json")


def test_yarn_validation():
    with pytest.raises(YarnSpecError):
        Yarn("x", (0, 0, 300))
    with pytest.raises(YarnSpecError):
        Yarn("", (0, 0, 0))


def test_outputs_get_ordinary_permissions(tmp_path):
    import os
    import stat

    from illuknit.core.files import atomic_write_text, staged_dir

    mask = os.umask(0o022)
    try:
        f = atomic_write_text(tmp_path / "a.txt", "x")
        assert stat.S_IMODE(f.stat().st_mode) == 0o644
        with staged_dir(tmp_path / "out") as d:
            (d / "b.txt").write_text("y")
        assert stat.S_IMODE((tmp_path / "out").stat().st_mode) == 0o755
    finally:
        os.umask(mask)


@st.composite
def split_patterns(draw, max_side=8):
    """Patterns with an ``upper`` array: any yarn on raised units, ``yarn`` on flat ones."""
    p = draw(patterns(max_side=max_side))
    other = draw(arrays(np.int16, p.shape, elements=st.integers(0, len(p.yarns) - 1)))
    return p.replace(upper=np.where(p.raised, other, p.yarn))


@given(split_patterns())
def test_split_json_round_trip_is_identical(p):
    doc = pattern_to_json(p)
    assert ("upper" in doc) == (p.upper is not None) == bool(p.split.any())
    assert doc["version"] == (2 if p.upper is not None else 1)
    assert pattern_from_json(json.loads(json.dumps(doc))) == p


def test_upper_none_writes_todays_file():
    p = LogicalPattern(np.array([[0, 1]]), np.array([[True, False]]), YARNS3[:2])
    same = p.replace(upper=p.yarn)  # equal to yarn everywhere: no split bump, stored as None
    assert same.upper is None and pattern_to_json(same) == pattern_to_json(p)
    assert list(pattern_to_json(p)) == [
        "format",
        "version",
        "rows",
        "cols",
        "yarns",
        "yarn",
        "raised",
        "meta",
    ]
    split = p.replace(upper=np.array([[1, 1]]))
    assert split.split.tolist() == [[True, False]] and split != p
    assert split.upper_yarn.tolist() == [[1, 1]] and p.upper_yarn.tolist() == [[0, 1]]


@pytest.mark.parametrize(
    "upper, match",
    [
        (np.array([[0, 0]]), "flat unit"),  # the flat unit (0, 1) changes yarn
        (np.array([[2, 1]]), r"0\.\.1"),
        (np.array([[0, 1, 0]]), "shape"),
        (np.array([[0.5, 1]]), "integers"),
    ],
)
def test_invalid_upper_is_rejected(upper, match):
    p = LogicalPattern(np.array([[0, 1]]), np.array([[True, False]]), YARNS3[:2])
    with pytest.raises(PatternValidationError, match=match):
        p.replace(upper=upper)


@pytest.mark.parametrize(
    "mutate, match",
    [
        (lambda d: d.update(version=1), "needs version 2"),
        (lambda d: d.update(upper=["1"]), "list of 2 strings"),
        (lambda d: d.update(upper=["1!", "00"]), "0-9 or a-z"),
        (lambda d: d.update(upper=["12", "00"]), "out of range"),
        (lambda d: d.update(upper=["11", "01"]), "flat unit"),
    ],
)
def test_bad_split_pattern_files(mutate, match):
    p = LogicalPattern(
        np.zeros((2, 2), int), np.array([[True, False], [False, False]]), YARNS3[:2]
    ).replace(upper=np.array([[1, 0], [0, 0]]))
    doc = pattern_to_json(p)
    mutate(doc)
    with pytest.raises(PatternFormatError, match=match):
        pattern_from_json(doc)
