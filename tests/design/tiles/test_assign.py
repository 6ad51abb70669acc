"""Tile assignment: agreement with brute force, brightness order, bad input and explanations."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from illuknit.core.colors import luminance
from illuknit.core.errors import ImageInputError, TileAssignmentError
from illuknit.core.pattern import parse_yarns
from illuknit.design.tiles.assign import (
    assign_tiles,
    brute_force_assignments,
    overlap_pairs,
)
from illuknit.design.tiles.bank import TileBank, canonical_bank
from illuknit.design.tiles.tile import Tile
from illuknit.solvers import available_backends

Y2 = parse_yarns("black=#1b1b1b,white=#f4f0e8")
Y3 = parse_yarns("black=#1b1b1b,white=#f4f0e8,red=#c03030")
SOLVERS = [s for s in ("cpsat", "rc2") if s in available_backends()]


def blocky(draw, k: int, shape=(12, 10), blocks=(3, 2)):
    """A region map of a few rectangular blocks (so every colour forms real regions)."""
    cells = draw(
        st.lists(
            st.integers(0, k - 1), min_size=blocks[0] * blocks[1], max_size=blocks[0] * blocks[1]
        )
    )
    grid = np.array(cells).reshape(blocks)
    reps = (shape[0] // blocks[0], shape[1] // blocks[1])
    return np.kron(grid, np.ones(reps, dtype=int)).astype(np.int16)


@st.composite
def image_pair(draw, ka: int = 2, kb: int = 2):
    ia = blocky(draw, ka)
    ib = blocky(draw, kb)

    # distinct grey levels, in random order of index
    def colors(k):
        levels = draw(st.lists(st.integers(0, 255), min_size=k, max_size=k, unique=True))
        return np.array([[v, v, v] for v in levels], dtype=np.uint8)

    return (ia, colors(ka)), (ib, colors(kb))


def _order_kept(indices, colors, fills) -> bool:
    used = np.unique(indices)
    lum = luminance(colors.astype(float))
    for p in used:
        for q in used:
            if lum[p] < lum[q] - 1e-9 and not fills[p].brightness < fills[q].brightness:
                return False
    return True


@pytest.mark.parametrize("solver", SOLVERS)
@settings(
    max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(pair=image_pair())
def test_model_agrees_with_brute_force(solver, pair):
    qa, qb = pair
    bank = canonical_bank(Y2)
    brute = brute_force_assignments(qa, qb, bank=bank)
    if not brute:
        with pytest.raises(TileAssignmentError):
            assign_tiles(qa, qb, bank=bank, candidates=3, solver=solver, explain=False)
        return
    got = assign_tiles(qa, qb, bank=bank, candidates=3, solver=solver)
    n = min(3, len(brute))
    assert len(got) == n
    assert [round(c.score, 6) for c in got] == [round(s, 6) for s, _, _ in brute[:n]]
    feasible = {(fa, fb): s for s, fa, fb in brute}
    for c in got:
        assert round(feasible[(c.fills_a, c.fills_b)], 6) == round(c.score, 6)
    assert len({(c.fills_a, c.fills_b) for c in got}) == n  # distinct candidates
    assert [c.rank for c in got] == list(range(1, n + 1))


@settings(max_examples=6, deadline=None)
@given(pair=image_pair(ka=3, kb=2))
def test_model_agrees_with_brute_force_three_colors(pair):
    qa, qb = pair
    bank = canonical_bank(Y2)
    brute = brute_force_assignments(qa, qb, bank=bank)
    if not brute:
        with pytest.raises(TileAssignmentError):
            assign_tiles(qa, qb, bank=bank, candidates=2, explain=False)
        return
    got = assign_tiles(qa, qb, bank=bank, candidates=2)
    assert [round(c.score, 6) for c in got] == [round(s, 6) for s, _, _ in brute[: len(got)]]


@settings(max_examples=8, deadline=None)
@given(pair=image_pair(ka=3, kb=3))
def test_brightness_order_holds_in_every_candidate(pair):
    qa, qb = pair
    try:
        got = assign_tiles(qa, qb, bank=canonical_bank(Y3), candidates=3, explain=False)
    except TileAssignmentError:
        return
    for c in got:
        assert _order_kept(qa[0], qa[1], c.fills_a)
        assert _order_kept(qb[0], qb[1], c.fills_b)
        # every occurring pair is realised by a tile that shows exactly the chosen fills
        for a, b in overlap_pairs(qa[0], qb[0]):
            f = c.bank.fills_of(c.tiles[a, b])
            assert f["A"] == c.fills_a[a] and f["B"] == c.fills_b[b]


def test_soft_brightness_is_never_worse():
    ia = np.array([[0, 1, 2], [2, 1, 0], [1, 2, 0]]).repeat(4, axis=0)
    ib = np.array([[1, 0, 0], [0, 1, 1], [0, 0, 1]]).repeat(4, axis=0)
    ca = np.array([[20, 20, 20], [128, 128, 128], [240, 240, 240]], np.uint8)
    cb = np.array([[240, 240, 240], [20, 20, 20]], np.uint8)
    hard = assign_tiles((ia, ca), (ib, cb), bank=canonical_bank(Y2), candidates=1)
    soft = assign_tiles(
        (ia, ca), (ib, cb), bank=canonical_bank(Y2), candidates=1, brightness="soft"
    )
    assert soft[0].score <= hard[0].score + 1e-9


def test_text_pair_prefers_a_striped_background():
    # white text-free background everywhere, black text: the paper's choice is a striped
    # background with solid text (the text colour must be shared by both sides' bumps)
    ia = np.zeros((12, 12), int)
    ia[3:9, 2:5] = 1
    ib = np.zeros((12, 12), int)
    ib[3:9, 7:10] = 1
    cols = np.array([[240, 240, 240], [20, 20, 20]], np.uint8)
    best = assign_tiles((ia, cols), (ib, cols), yarns=Y2, candidates=1)[0]
    assert best.fills_a[1].is_solid and not best.fills_a[0].is_solid


def test_inputs_of_different_sizes_are_refused():
    cols = np.array([[0, 0, 0], [255, 255, 255]], np.uint8)
    with pytest.raises(ImageInputError, match="same size"):
        assign_tiles((np.zeros((4, 5), int), cols), (np.zeros((5, 4), int), cols), yarns=Y2)


def test_more_colors_than_the_bank_can_serve():
    solids = TileBank(Y2, (Tile.from_rows(["0"]), Tile.from_rows(["1"])))
    ia = np.array([[0, 1, 2]] * 4)
    cols = np.array([[0, 0, 0], [128, 128, 128], [255, 255, 255]], np.uint8)
    with pytest.raises(TileAssignmentError, match="distinct brightness"):
        assign_tiles((ia, cols), (ia, cols), bank=solids)


def test_no_candidates_is_explained():
    solids = TileBank(Y2, (Tile.from_rows(["0"]), Tile.from_rows(["1"])))
    ia = np.array([[0, 0, 1, 1]] * 4)
    ib = np.array([[0, 1, 0, 1]] * 4)
    cols = np.array([[20, 20, 20], [240, 240, 240]], np.uint8)
    with pytest.raises(TileAssignmentError) as info:
        assign_tiles((ia, cols), (ib, cols), bank=solids)
    msg = str(info.value)
    assert "cannot all be realised" in msg
    assert "over" in msg and ("A0" in msg or "A1" in msg)
    assert "stripes on both sides" in msg


def test_one_yarn_cannot_serve_two_colors():
    # one yarn only: two colours per input can never differ in brightness
    y1 = parse_yarns("black")
    bank = canonical_bank(y1)
    ia = np.array([[0, 1]] * 4)
    cols = np.array([[20, 20, 20], [240, 240, 240]], np.uint8)
    with pytest.raises(TileAssignmentError, match="brightness"):
        assign_tiles((ia, cols), (ia, cols), bank=bank)


def test_candidates_argument_checked():
    cols = np.array([[0, 0, 0]], np.uint8)
    with pytest.raises(TileAssignmentError, match="candidates"):
        assign_tiles(
            (np.zeros((2, 2), int), cols), (np.zeros((2, 2), int), cols), yarns=Y2, candidates=0
        )


def test_with_tile_override_and_unknown_pair():
    ia = np.zeros((6, 4), int)
    ib = np.zeros((6, 4), int)
    cols = np.array([[240, 240, 240]], np.uint8)
    c = assign_tiles((ia, cols), (ib, cols), yarns=Y2, candidates=1)[0]
    c2 = c.with_tile((0, 0), "0/1/0^")
    assert c2.tiles[0, 0] == Tile.from_rows(["0", "1", "0^"]) and c2.overridden == ((0, 0),)
    assert c.tiles[0, 0] != c2.tiles[0, 0]  # the original is untouched
    with pytest.raises(TileAssignmentError, match="does not occur"):
        c.with_tile((1, 0), "0")
    with pytest.raises(TileAssignmentError, match="uses yarn"):
        c.with_tile((0, 0), "5")


@settings(max_examples=8, deadline=None)
@given(pair=image_pair(), candidates=st.integers(1, 3), pool=st.integers(1, 40))
def test_a_pool_finds_every_assignment_up_to_its_size_in_score_order(pair, candidates, pool):
    qa, qb = pair
    bank = canonical_bank(Y2)
    brute = brute_force_assignments(qa, qb, bank=bank)
    if not brute:
        return
    got = assign_tiles(qa, qb, bank=bank, candidates=candidates, pool=pool)
    n = min(max(candidates, pool), len(brute))
    assert len(got) == n
    assert len({(c.fills_a, c.fills_b) for c in got}) == n
    assert [round(c.score, 6) for c in got] == [round(s, 6) for s, _, _ in brute[:n]]


def test_a_pool_past_its_time_stops_at_the_candidates_asked_for():
    qa = (np.kron(np.array([[0, 1], [1, 0]]), np.ones((4, 4), int)), np.array([[0] * 3, [255] * 3]))
    qb = (np.kron(np.array([[0, 0], [1, 1]]), np.ones((4, 4), int)), np.array([[0] * 3, [255] * 3]))
    bank = canonical_bank(Y2)
    everything = assign_tiles(qa, qb, bank=bank, candidates=2, pool=50)
    assert len(everything) > 3
    assert len(assign_tiles(qa, qb, bank=bank, candidates=2, pool=50, pool_seconds=0)) == 2
    with pytest.raises(TileAssignmentError, match="pool"):
        assign_tiles(qa, qb, bank=bank, pool=0)


def test_the_keywords_are_a_shorthand_for_assign_options():
    """``candidates=2, brightness="soft"`` is ``options=AssignOptions(...)``; unknown keywords
    and wrong values are refused, named."""
    from illuknit.core.errors import OptionError
    from illuknit.design.tiles.assign import AssignOptions

    ia = np.array([[0, 1, 2], [2, 1, 0], [1, 2, 0]]).repeat(4, axis=0)
    ib = np.array([[1, 0, 0], [0, 1, 1], [0, 0, 1]]).repeat(4, axis=0)
    ca = np.array([[20, 20, 20], [128, 128, 128], [240, 240, 240]], np.uint8)
    cb = np.array([[240, 240, 240], [20, 20, 20]], np.uint8)
    bank = canonical_bank(Y2)
    by_keywords = assign_tiles((ia, ca), (ib, cb), bank=bank, candidates=2, brightness="soft")
    options = AssignOptions(candidates=2, brightness="soft")
    by_options = assign_tiles((ia, ca), (ib, cb), bank=bank, options=options)
    assert [t.score for t in by_options] == [t.score for t in by_keywords]
    with pytest.raises(OptionError, match="candidatez"):
        assign_tiles((ia, ca), (ib, cb), bank=bank, candidatez=2)
    with pytest.raises(TileAssignmentError, match="`brightness`"):
        AssignOptions(brightness="firm")
