"""Suggested edits of a double-view design's pictures (tiles.simplify) and `double --simplify`."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from PIL import Image
from scipy import ndimage

from illuknit.errors import OptionError
from illuknit.tiles.simplify import (
    EDIT_NAMES,
    apply_edits,
    drop_small_overlaps,
    merge_small_regions,
    smooth_boundaries,
    suggest_edits,
)

maps = arrays(np.int16, st.tuples(st.integers(2, 9), st.integers(2, 9)), elements=st.integers(0, 2))


@given(maps, st.integers(1, 6))
@settings(max_examples=80, deadline=None)
def test_merge_leaves_no_small_region_that_had_a_neighbour(idx, k):
    out = merge_small_regions(idx, min_region=k)
    assert out.shape == idx.shape
    if len(np.unique(idx)) == 1:
        assert (out == idx).all()
    # every unit changed sat in a small region of the input
    for color in np.unique(idx):
        labels, _ = ndimage.label(idx == color)
        sizes = np.bincount(labels.ravel())
        changed = (out != idx) & (idx == color)
        assert (sizes[labels[changed]] < k).all()
    assert set(np.unique(out)) <= set(np.unique(idx))


@given(maps)
@settings(max_examples=60, deadline=None)
def test_smoothing_keeps_solid_areas_and_colors(idx):
    out = smooth_boundaries(idx)
    assert set(np.unique(out)) <= set(np.unique(idx))
    flat = np.full_like(idx, int(idx[0, 0]))
    assert (smooth_boundaries(flat) == flat).all()


@given(maps, st.integers(0, 2**31 - 1), st.integers(1, 6))
@settings(max_examples=80, deadline=None)
def test_small_overlaps_are_gone_and_a_is_untouched(ia, seed, k):
    ib = np.random.default_rng(seed).integers(0, 3, ia.shape).astype(np.int16)
    out = drop_small_overlaps(ia, ib, min_overlap=k)
    for ca in np.unique(ia):
        counts = np.bincount(out[ia == ca], minlength=3)
        main_color = np.bincount(ib[ia == ca], minlength=3).argmax()
        small = (counts > 0) & (counts < k)
        small[main_color] = False
        assert not small.any()


@given(st.lists(st.floats(0, 1), min_size=4, max_size=4))
@settings(max_examples=40, deadline=None)
def test_apply_edits_never_lowers_readability(scores):
    ia = np.zeros((8, 8), np.int16)
    ia[2:6, 2:6] = 1
    ia[0, 7] = 1  # a speck to merge
    ia[5, 6] = 1  # a ragged step
    ib = np.zeros_like(ia)
    ib[3, 3] = 1  # a tiny overlap
    calls = iter(scores)
    _, _, results = apply_edits(ia, ib, lambda x, y: (next(calls, 0.0), 0.0))
    assert results, "the speck, step and overlap each invite an edit"
    best = scores[0]
    for r in results:
        assert r.accepted == (r.after[0] > r.before[0] + 1e-6)
        if r.accepted:
            best = r.after[0]
    assert best >= scores[0]
    assert all(r.suggestion.name in EDIT_NAMES for r in results)


def test_unknown_edit_is_an_option_error():
    with pytest.raises(OptionError, match="known"):
        suggest_edits(np.zeros((3, 3), int), np.zeros((3, 3), int), names=["erase-everything"])


def test_double_suggest_writes_before_after_and_simplify_designs_with_kept_edits(tmp_path, run_cli):
    y, x = np.mgrid[:30, :30]
    a = ((y - 15) ** 2 + (x - 11) ** 2 < 90) | ((y - 3) % 7 == 0) & (x % 9 == 0)  # disc + specks
    b = (abs(y - 15) < 8) & (abs(x - 18) < 7)
    for name, img in (("a.png", a), ("b.png", b)):
        Image.fromarray(np.where(img, 20, 235).astype(np.uint8)).save(tmp_path / name)
    code, _, err = run_cli(
        ["double", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "--suggest",
         "-o", str(tmp_path / "s")])  # fmt: skip
    assert code == 0, err
    data = json.loads((tmp_path / "s" / "suggestions" / "suggestions.json").read_text())
    assert data["edits"], "the specks invite at least one edit"
    for e in data["edits"]:
        assert not e["accepted"]  # --suggest only shows
        assert (tmp_path / "s" / "suggestions" / f"{e['edit']}_a.png").is_file()
    summary = json.loads((tmp_path / "s" / "summary.json").read_text())
    assert summary["edits"] == data["edits"]
    code, _, err = run_cli(
        ["double", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "--simplify",
         "-o", str(tmp_path / "t")])  # fmt: skip
    assert code == 0, err
    kept = json.loads((tmp_path / "t" / "summary.json").read_text())["edits"]
    assert [e["edit"] for e in kept] == [e["edit"] for e in data["edits"]]
    for e in kept:
        assert e["accepted"] == (e["readability_after"] > e["readability_before"])
    code, _, err = run_cli(
        ["headon", str(tmp_path / "a.png"), "--simplify", "-o", str(tmp_path / "h")]
    )
    assert code == 2 and "double-view" in err and not (tmp_path / "h").exists()
