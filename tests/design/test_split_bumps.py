"""Split bumps in the design model (docs/split-bumps.md): the views, the constraint model, the
exact DP, the tiles and the renderer agree with one another."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from illuknit.core.errors import OptionError
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.core.views import can_see
from illuknit.design.models.backends.dp import solve_dp_split, values_from_pattern
from illuknit.design.models.illusion_models import build_model, make_problem, solve_illusion
from illuknit.design.render import render_pattern
from illuknit.design.render.params import RenderParams
from illuknit.design.tiles.bank import canonical_bank
from illuknit.design.tiles.tile import Tile, tile_fills, tile_seen

YARNS = parse_yarns("#1b1b1b,#f4f0e8,#c0392b")


@st.composite
def split_patterns(draw, max_rows=6, max_cols=4):
    n = draw(st.integers(1, max_rows))
    m = draw(st.integers(1, max_cols))
    k = draw(st.integers(1, 3))
    yarn = draw(arrays(np.int16, (n, m), elements=st.integers(0, k - 1)))
    raised = draw(arrays(np.bool_, (n, m)))
    second = draw(arrays(np.int16, (n, m), elements=st.integers(0, k - 1)))
    return LogicalPattern(yarn, raised, YARNS[:k], upper=np.where(raised, second, yarn))


def _walk(p: LogicalPattern, view: str) -> np.ndarray:
    """What each cell shows, unit by unit along the wale: the nearest raised unit between the
    viewer and the cell hides it, and a bump shows the course on the viewer's side."""
    n, m = p.shape
    out = np.empty((n, m), dtype=np.int64)
    for i in range(n):
        for j in range(m):
            if view == "A":  # from the top edge: the unit above, its second course
                k = i - 1 if i > 0 and p.raised[i - 1, j] else i
                out[i, j] = p.upper_yarn[k, j]
            else:  # from the bottom edge: the unit below, its first course
                k = i + 1 if i < n - 1 and p.raised[i + 1, j] else i
                out[i, j] = p.yarn[k, j]
    return out


@settings(max_examples=40, deadline=None)
@given(split_patterns(), st.data())
def test_model_views_equal_can_see(p, data):
    """The constraint model's cost of a pattern is exactly can_see's mismatch count, and
    can_see matches the unit-by-unit walk."""
    for view in ("A", "B"):
        assert np.array_equal(can_see(p, view), _walk(p, view))
    k = len(p.yarns)
    ta = data.draw(arrays(np.int16, p.shape, elements=st.integers(0, k - 1)))
    tb = data.draw(arrays(np.int16, p.shape, elements=st.integers(0, k - 1)))
    model = build_model(make_problem(ta, tb, n_yarns=k, split_bumps=True))
    ok, cost = model.evaluate(values_from_pattern(model, p.yarn, p.raised, p.upper_yarn))
    assert ok
    assert cost == int((can_see(p, "A") != ta).sum() + (can_see(p, "B") != tb).sum())


@settings(max_examples=25, deadline=None)
@given(st.data())
def test_dp_optimum_equals_maxsat_optimum(data):
    n = data.draw(st.integers(1, 5))
    m = data.draw(st.integers(1, 3))
    k = data.draw(st.integers(2, 3))
    ta = data.draw(arrays(np.int16, (n, m), elements=st.integers(0, k - 1)))
    tb = data.draw(arrays(np.int16, (n, m), elements=st.integers(0, k - 1)))
    problem = make_problem(ta, tb, n_yarns=k, split_bumps=True)
    yarn, raised, upper, cost = solve_dp_split(problem)
    p = LogicalPattern(yarn, raised, YARNS[:k], upper=upper)
    assert cost == int((can_see(p, "A") != ta).sum() + (can_see(p, "B") != tb).sum())
    sat = solve_illusion(ta, tb, solver="rc2", warm_start="none", n_yarns=k, split_bumps=True)
    assert sat.solution.status.value == "optimal"
    assert sat.solution.objective == cost
    # split bumps can only help: the plain optimum is never better
    plain = solve_illusion(ta, tb, solver="dp", n_yarns=k)
    assert plain.solution.objective >= cost


def test_split_bump_tile_shows_two_colours():
    """``1^0`` shows solid 0 from A and solid 1 from B to can_see; its fills count the far
    course with 1 - split_share, so at share 1 they are those solids."""
    t = Tile.from_rows(["1^0"])
    assert t.code() == "1^0" and Tile.from_rows(t.rows()) == t
    assert tile_seen(t, "A").tolist() == [[0]] and tile_seen(t, "B").tolist() == [[1]]
    fills = tile_fills(t, YARNS[:2])
    assert (fills["A"].key(), fills["B"].key()) == ("0:3/4,1:1/4", "0:1/4,1:3/4")
    assert fills["headon"].key() == "0:1/2,1:1/2" and fills["side"] is None
    solid = tile_fills(t, YARNS[:2], split_share=1.0)
    assert (solid["A"].key(), solid["B"].key()) == ("0:1", "1:1")
    for share in (0.75, 1.0):
        bank = canonical_bank(YARNS[:2], split_bumps=True, split_share=share)
        f = bank.fills_of(t)
        assert bank.tile_for(f["A"], f["B"]) == t
        # the enumeration's weighted counts agree with tile_fills: one tile per pair of fills
        pairs = [(fl["A"], fl["B"]) for fl in bank.fills]
        assert len(set(pairs)) == len(pairs)
    plain = canonical_bank(YARNS[:2])
    assert plain.tile_for(solid["A"], solid["B"]) is None
    assert all(t.upper is None for t in plain.tiles)


def test_renderer_agrees_with_can_see_at_the_exact_angle():
    """With split_share 1 and the angle at which a bump hides exactly one unit, every rendered
    pixel is the colour of the yarn can_see names; a lower share mixes in the far course."""
    p = LogicalPattern(
        np.array([[0], [1], [2], [0], [1]]),
        np.array([[True], [False], [True], [True], [False]]),
        YARNS,
        upper=np.array([[2], [1], [0], [1], [1]]),
    )
    params = RenderParams(split_share=1.0)
    params = params.with_angle(params.exact_angle)
    for view in ("A", "B"):
        img = render_pattern(p, params=params, view=view)
        assert np.abs(img.astype(int) - p.palette[can_see(p, view)]).max() <= 1
    half = render_pattern(p, params=RenderParams(split_share=0.75).with_angle(params.theta))
    assert not np.array_equal(half, render_pattern(p, params=params))


def test_plain_patterns_render_and_solve_as_before():
    p = LogicalPattern(np.array([[0, 1]]), np.array([[True, False]]), YARNS[:2])
    assert np.array_equal(
        render_pattern(p), render_pattern(p.replace(upper=p.yarn))
    )  # upper == yarn is no split bump
    with pytest.raises(OptionError, match="logical model only"):
        make_problem(np.zeros((2, 2), int), kind="knit-aware", split_bumps=True)


def test_hand_rows_knit_the_second_course_in_its_yarn():
    from illuknit.outputs.chart import hand_rows
    from illuknit.outputs.hand_pattern import row_colourwork

    p = LogicalPattern(
        np.array([[1, 0]]), np.array([[True, False]]), YARNS[:2], upper=np.array([[0, 0]])
    )
    rows = hand_rows(p)
    assert rows[0].yarn.tolist() == [1, 1, 0, 0]  # first course: the unit's yarn
    assert rows[1].yarn.tolist() == [0, 0, 0, 0]  # second course: the split bump's upper yarn
    assert rows[1].purl_on_rs.tolist() == [True, True, False, False]
    assert [r.yarns for r in row_colourwork(p)] == [2, 1]
