"""The candidates a user may prefer to the default (pipeline.alternatives): named only when one
qualifies, with both designs' figures, in the summaries' and the app's words."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.app.candidates import _alternative_details
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.design.hand_cost import hand_cost, hand_hours
from illuknit.design.options import MadeFor, RankOptions
from illuknit.design.tiles.perception import CandidateMeasures
from illuknit.outputs.hand_pattern import hand_verdict
from illuknit.pipeline.alternatives import alternative_sentences, alternatives

YARNS = parse_yarns("black,white")


def _pattern(rows: list[list[int]]) -> LogicalPattern:
    yarn = np.array(rows, np.int16)
    return LogicalPattern(yarn, np.zeros(yarn.shape, bool), YARNS)


def _design(pattern, read, ghost, rank):
    m = CandidateMeasures(
        ("A", "B"), (read, read), (0.5, 0.5), (ghost, ghost), hand=hand_cost(pattern)
    )
    return SimpleNamespace(rank=rank, pattern=pattern, measures=m)


def _tile_design(made_for, *designs):
    return SimpleNamespace(ranking=RankOptions(made_for=made_for), designs=designs)


BUSY = _pattern([[0, 1] * 8] * 6)  # a colour change every unit: stranded, short floats
CALM = _pattern([[0] * 8 + [1] * 8] * 6)  # two blocks a row


def test_a_ghostly_default_made_for_hands_gets_both_alternatives():
    design = _tile_design(MadeFor.HANDS, _design(BUSY, 0.944, 0.8, 1), _design(CALM, 0.935, 0.1, 2))
    found = alternatives(design)
    assert found["cleaner"]["rank"] == 2 and found["quicker_by_hand"]["rank"] == 2
    q = found["quicker_by_hand"]
    assert (q["colour_rows"], q["default_colour_rows"], q["rows"]) == (12, 12, 12)
    assert q["hours"] < 0.75 * q["default_hours"]  # 8 blocks fewer a row
    said = alternative_sentences(found)
    assert [r for r, _ in said] == [2, 2]
    assert said[0][1].startswith("the other picture shows through the default's worse view on 26%")
    assert "0.009 lower (0.935 against 0.944), with as many rows knittable by hand" in said[0][1]
    # the app's first card carries the same sentences; the other cards none
    assert _alternative_details(design) == {
        "alternatives": [{"rank": r, "text": t} for r, t in said]
    }


def test_made_for_a_machine_only_ghosting_is_named_and_a_clean_default_gets_none():
    design = _tile_design(
        MadeFor.MACHINE, _design(BUSY, 0.944, 0.8, 1), _design(CALM, 0.935, 0.1, 2)
    )
    assert set(alternatives(design)) == {"cleaner"}
    assert alternatives(design, pick=2) == {}
    clean = _tile_design(MadeFor.HANDS, _design(CALM, 0.95, 0.1, 1), _design(BUSY, 0.96, 0.1, 2))
    assert alternatives(clean) == {} and _alternative_details(clean) == {}
    assert alternative_sentences({}) == []


@settings(max_examples=40, deadline=None)
@given(st.lists(st.lists(st.integers(0, 1), min_size=4, max_size=4), min_size=1, max_size=4))
def test_the_hours_are_the_covers(rows):
    p = _pattern(rows)
    assert hand_hours(p) == hand_verdict(p).hours
