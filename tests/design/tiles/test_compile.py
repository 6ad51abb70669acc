"""Compiling tile assignments: zero error inside regions, unbroken courses, overrides, head-on."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.core.errors import TileAssignmentError
from illuknit.core.pattern import parse_yarns
from illuknit.core.views import can_see
from illuknit.design.tiles.assign import assign_tiles
from illuknit.design.tiles.bank import canonical_bank
from illuknit.design.tiles.compile import compile_tiles, repainted_indices, repainted_rgb
from illuknit.design.tiles.headon import assign_headon
from illuknit.design.tiles.tile import tile_fills

Y2 = parse_yarns("black=#1b1b1b,white=#f4f0e8")
Y3 = parse_yarns("black=#1b1b1b,white=#f4f0e8,red=#c03030")


@st.composite
def region_maps(draw, k: int, shape=(24, 9)):
    """Random region maps made of horizontal bands of random heights with random column splits."""
    n, m = shape
    out = np.zeros(shape, dtype=np.int16)
    r = 0
    while r < n:
        h = draw(st.integers(1, 8))
        split = draw(st.integers(0, m))
        left, right = draw(st.integers(0, k - 1)), draw(st.integers(0, k - 1))
        out[r : r + h, :split] = left
        out[r : r + h, split:] = right
        r += h
    return out


def _far_from_boundaries(ia, ib, reach):
    """Independent of the library: True where the pair is constant for `reach` rows up and down
    the column and the piece's edge is more than `reach` rows away."""
    n, m = ia.shape
    code = ia.astype(int) * 10 + ib
    ok = np.zeros((n, m), bool)
    for r in range(reach, n - reach):
        window = code[r - reach : r + reach + 1]
        ok[r] = (window == code[r]).all(axis=0)
    return ok


@pytest.mark.parametrize(("yarns", "k"), [(Y2, 2), (Y3, 3)], ids=["2 yarns", "3 yarns"])
@settings(max_examples=15, deadline=None)
@given(data=st.data())
def test_zero_error_against_repainted_images_inside_regions(yarns, k, data):
    ia = data.draw(region_maps(k))
    ib = data.draw(region_maps(k))
    grey = np.linspace(20, 240, k).round().astype(np.uint8)
    cols = np.stack([grey] * 3, axis=1)
    try:
        cands = assign_tiles(
            (ia, cols), (ib, cols), bank=canonical_bank(yarns), candidates=2, explain=False
        )
    except TileAssignmentError:
        return
    for cand in cands:
        pattern, report = compile_tiles(cand)
        reach = max(t.height for t in cand.tiles.values())
        inside = _far_from_boundaries(ia, ib, reach)
        for view in ("A", "B"):
            seen = can_see(pattern, view)
            want = repainted_indices(cand, view)
            assert (seen[inside] == want[inside]).all()
            assert report.error_repainted_interior[view] == 0.0
            # the repainted image really shows each colour's fill: proportions over a region
            fills = cand.fills_a if view == "A" else cand.fills_b
            for (a, b), t in cand.tiles.items():
                f = tile_fills(t, yarns)[view]
                assert f == fills[a if view == "A" else b]


def test_phase_from_global_row_gives_unbroken_courses():
    # two side-by-side regions with the same fill in A but different colours in B
    ia = np.zeros((12, 8), int)
    ib = np.zeros((12, 8), int)
    ib[:, 4:] = 1
    cols = np.array([[240, 240, 240], [20, 20, 20]], np.uint8)
    cand = assign_tiles((ia, cols), (ib, cols), yarns=Y2, candidates=1)[0]
    pattern, report = compile_tiles(cand)
    t = cand.tiles[0, 0]
    for r in range(12):
        assert (pattern.yarn[r, :4] == t.yarn[r % t.height, 0]).all()
    assert report.color_changes.shape == (12,)
    assert report.yarns_per_course.max() <= 2
    assert pattern.meta["compiler"] == "tiles"


def test_report_against_original_inputs():
    ia = np.zeros((9, 6), int)
    ia[3:6] = 1
    ib = np.zeros((9, 6), int)
    cols = np.array([[240, 240, 240], [20, 20, 20]], np.uint8)
    cand = assign_tiles((ia, cols), (ib, cols), yarns=Y2, candidates=1)[0]
    _, report = compile_tiles(cand)
    for view in ("A", "B"):
        assert 0.0 <= report.error_original[view] <= 1.0
        assert report.delta_e_original[view] >= 0.0
    j = report.to_json()
    assert set(j) >= {"error_repainted", "error_original", "color_changes_per_course", "tiles"}


def test_per_pair_override_is_reported():
    ia = np.zeros((12, 6), int)
    ia[:, 3:] = 1
    ib = np.zeros((12, 6), int)
    cols = np.array([[240, 240, 240], [20, 20, 20]], np.uint8)
    cand = assign_tiles((ia, cols), (ib, cols), yarns=Y2, candidates=1)[0]
    bank = cand.bank
    fa, fb = cand.fills_a[0], cand.fills_b[0]
    # an override that keeps the fills: same fills, other tile (a phase shift of the same rows)
    t = cand.tiles[0, 0]
    shifted = type(t)(np.roll(t.yarn, 1, axis=0), np.roll(t.raised, 1, axis=0))
    _, rep = compile_tiles(cand, overrides={(0, 0): shifted})
    assert rep.overrides[0]["keeps_fills"] == (
        bank.fills_of(shifted)["A"] == fa and bank.fills_of(shifted)["B"] == fb
    )
    # an override with other fills: flagged, and the repainted error rises inside the region
    other = "1" if t.code() != "1" else "0"
    pattern, rep = compile_tiles(cand, overrides={(0, 0): other})
    assert rep.overrides[0] == {"a": 0, "b": 0, "tile": other, "keeps_fills": False}
    assert max(rep.error_repainted_interior.values()) > 0
    assert (pattern.yarn[:, :3] == int(other)).all()


def test_repainted_pictures():
    ia = np.zeros((6, 6), int)
    ia[:, 3:] = 1
    cols = np.array([[240, 240, 240], [20, 20, 20]], np.uint8)
    cand = assign_tiles((ia, cols), (ia, cols), yarns=Y2, candidates=1)[0]
    avg = repainted_rgb(cand, 0, mode="average")
    assert avg.shape == (6, 6, 3) and avg.dtype == np.uint8
    assert (avg[:, 0] == np.round(cand.fills_a[0].rgb)).all()
    stripes = repainted_rgb(cand, 1)
    assert {tuple(v) for v in stripes.reshape(-1, 3)} <= {Y2[0].rgb, Y2[1].rgb}
    with pytest.raises(TileAssignmentError):
        repainted_rgb(cand, 2)
    with pytest.raises(TileAssignmentError):
        compile_tiles("not an assignment")  # type: ignore[arg-type]


def test_headon_picture_disappears_at_an_angle():
    from illuknit.pictures.drawings import draw_heart

    front = draw_heart((24, 20)).astype(np.int16)
    cols = np.array([[240, 240, 240], [20, 20, 20]], np.uint8)
    cands = assign_headon((front, cols), None, yarns=Y2, candidates=2)
    for cand in cands:
        assert cand.views == ("headon", "side")
        pattern, report = compile_tiles(cand)
        inside = _far_from_boundaries(
            front, np.zeros_like(front), max(t.height for t in cand.tiles.values())
        )
        head = can_see(pattern, "headon")
        # head-on, the two front colours show different fills ...
        assert cand.fills_a[0] != cand.fills_a[1]
        assert report.error_repainted_interior["headon"] == 0.0
        # ... from either side, one fill everywhere: the picture is gone
        assert len({f for f in cand.fills_b if f is not None}) == 1
        for view in ("A", "B"):
            assert report.error_repainted_interior[view] == 0.0
            seen = can_see(pattern, view)
            props = [np.mean(seen[inside & (front == k)] == 0) for k in (0, 1)]
            assert abs(props[0] - props[1]) < 0.2
        # and head-on the front picture is there: its two colours are seen differently
        assert not np.array_equal(
            np.bincount(head[inside & (front == 0)], minlength=2)
            / max(1, (inside & (front == 0)).sum()),
            np.bincount(head[inside & (front == 1)], minlength=2)
            / max(1, (inside & (front == 1)).sum()),
        )


def test_headon_with_a_side_picture():
    from illuknit.pictures.drawings import draw_circle, draw_heart

    front = draw_heart((18, 18)).astype(np.int16)
    side = draw_circle((18, 18)).astype(np.int16)
    cols = np.array([[240, 240, 240], [20, 20, 20]], np.uint8)
    cands = assign_headon((front, cols), (side, cols), yarns=Y2, candidates=1)
    _, report = compile_tiles(cands[0])
    assert report.error_repainted_interior["A"] == 0.0
    for f in cands[0].fills_b:
        assert f is not None
    with pytest.raises(TileAssignmentError, match="views"):
        assign_headon((front, cols), None, yarns=Y2, views=("A", "B"))


def test_stripes_of_one_color_stay_in_phase_across_the_other_picture():
    # A is one ground colour everywhere; B has a dark block. Without phase alignment the ground's
    # stripe would shift over the block and the block would ghost into view A.
    ia = np.zeros((36, 12), np.int16)
    ib = np.zeros((36, 12), np.int16)
    ib[9:27, 4:8] = 1
    cols = np.array([[240, 240, 240], [20, 20, 20]], np.uint8)
    for cand in assign_tiles((ia, cols), (ib, cols), yarns=Y2, candidates=3):
        pattern, _ = compile_tiles(cand)
        heights = {t.height for t in cand.tiles.values()}
        if len(heights) != 1:
            continue  # different periods cannot line up everywhere
        seen = can_see(pattern, "A")
        inside = _far_from_boundaries(ia, ib, max(heights))
        for r in range(36):
            assert len(set(seen[r][inside[r]].tolist())) <= 1, r
