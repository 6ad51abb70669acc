"""The hand knitter's row term of the tile assignment model (issue 37 item 1): off by default
(the machine design unchanged), exact against the brute force when on, and it steers the search
towards fewer colour changes a row."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings

from illuknit.core.errors import TileAssignmentError
from illuknit.design.tiles.assign import AssignmentWeights, assign_tiles, brute_force_assignments
from illuknit.design.tiles.bank import canonical_bank
from illuknit.design.tiles.hand_term import (
    HAND_ROW_CHANGE_PENALTY,
    hand_weights,
    internal_changes,
    row_mismatch,
    row_signature,
    with_hand_candidates,
)
from illuknit.design.tiles.tile import Tile
from tests.design.tiles.test_assign import Y2, image_pair


def test_row_signatures_count_changes_inside_and_between_tiles():
    stripe = Tile.from_rows(["0", "1"])
    solid = Tile.from_rows(["0"])
    assert row_signature(stripe) == ((0,), (0,), (1,), (1,))  # two hand rows a unit row
    assert internal_changes(stripe) == 0.0  # every row in one yarn
    assert internal_changes(Tile.from_rows(["0 1"])) == 1.0
    assert row_mismatch(row_signature(solid), row_signature(solid)) == 0.0
    # a solid region beside a 2-row stripe: the stripe's second course pair differs
    assert row_mismatch(row_signature(solid), row_signature(stripe)) == 0.5


def test_the_term_is_off_by_default():
    assert AssignmentWeights().row_change_penalty == 0.0
    assert hand_weights().row_change_penalty == HAND_ROW_CHANGE_PENALTY
    with pytest.raises(TileAssignmentError):
        AssignmentWeights(row_change_penalty=-1.0)
    ia = np.kron([[0, 1], [1, 0]], np.ones((4, 4), int)).astype(np.int16)
    grey = np.array([[30, 30, 30], [220, 220, 220]], np.uint8)
    (machine,) = assign_tiles((ia, grey), (1 - ia, grey), yarns=Y2, candidates=1)
    assert "row_changes" not in machine.cost
    (hands,) = assign_tiles(
        (ia, grey), (1 - ia, grey), yarns=Y2, candidates=1, weights=hand_weights()
    )
    assert "row_changes" in hands.cost


@settings(max_examples=8, deadline=None)
@given(pair=image_pair())
def test_the_term_agrees_with_brute_force(pair):
    qa, qb = pair
    bank = canonical_bank(Y2)
    w = hand_weights()
    brute = brute_force_assignments(qa, qb, bank=bank, weights=w)
    if not brute:
        return
    got = assign_tiles(qa, qb, bank=bank, candidates=2, weights=w, explain=False)
    n = min(2, len(brute))
    assert [round(c.score, 6) for c in got] == [round(s, 6) for s, _, _ in brute[:n]]


@settings(max_examples=8, deadline=None)
@given(pair=image_pair())
def test_the_best_design_for_hands_changes_colour_no_more_often(pair):
    qa, qb = pair
    bank = canonical_bank(Y2)
    try:
        (machine,) = assign_tiles(qa, qb, bank=bank, candidates=1, explain=False)
    except TileAssignmentError:
        return
    w = hand_weights()
    (hands,) = assign_tiles(qa, qb, bank=bank, candidates=1, weights=w, explain=False)
    scored = {(fa, fb): s for s, fa, fb in brute_force_assignments(qa, qb, bank=bank, weights=w)}
    # the machine optimum measured with the term costs at least as much as the hand optimum
    assert scored[machine.fills_a, machine.fills_b] >= hands.score - 1e-9


def test_a_design_for_hands_is_chosen_from_both_searches():
    ia = np.kron([[0, 1, 0], [1, 0, 1]], np.ones((4, 4), int)).astype(np.int16)
    ib = np.kron([[0, 0, 1], [1, 1, 0]], np.ones((4, 4), int)).astype(np.int16)
    grey = np.array([[30, 30, 30], [220, 220, 220]], np.uint8)
    found = assign_tiles((ia, grey), (ib, grey), yarns=Y2, candidates=2)
    hand = assign_tiles((ia, grey), (ib, grey), yarns=Y2, candidates=4, weights=hand_weights())
    both = with_hand_candidates(found, hand)
    keys = [(a.fills_a, a.fills_b) for a in both]
    assert both[: len(found)] == found and len(set(keys)) == len(keys)
    assert set(keys) == {(a.fills_a, a.fills_b) for a in (*found, *hand)}
    assert [a.rank for a in both] == list(range(1, len(both) + 1))
