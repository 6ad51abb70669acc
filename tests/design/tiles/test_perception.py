"""Candidates ranked by how they read (tiles.perception) and the `double` outputs built on it."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

from illuknit.bench.metrics import knit_stats
from illuknit.core.errors import OptionError
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.design.tiles.assign import assign_tiles
from illuknit.design.tiles.perception import (
    CLEANER_GHOSTING_MARGIN,
    CONTRAST_FLOOR,
    RANK_KEYS,
    CandidateMeasures,
    cleaner_alternative,
    diagnostic_rgb,
    measure_candidate,
    rank_candidates,
    rank_designs,
)

YARNS = parse_yarns("black,white")


def _m(read, contrast=(0.5, 0.5), ghost=(0.0, 0.0), minutes=None):
    return CandidateMeasures(("A", "B"), tuple(read), tuple(contrast), tuple(ghost), minutes)


def _disc(n: int, r: float, cy: float, cx: float) -> np.ndarray:
    y, x = np.mgrid[:n, :n]
    return ((y - cy) ** 2 + (x - cx) ** 2 < r * r).astype(np.int16)


def test_contrast_below_the_floor_costs_a_readable_looking_candidate_its_place():
    washed = _m((0.97, 0.96), contrast=(0.05, 0.05))  # correlates, but no light/dark left
    clear = _m((0.93, 0.92), contrast=(0.45, 0.40))
    assert rank_candidates([washed, clear], [1.0, 2.0]) == [1, 0]
    # above the floor, readability leads: contrast is not traded against it
    assert rank_candidates([_m((0.97, 0.96), (CONTRAST_FLOOR, 0.3)), clear], [2.0, 1.0]) == [0, 1]


@given(
    st.lists(
        st.tuples(
            st.floats(-1, 1), st.floats(-1, 1), st.floats(0, 1), st.floats(0, 1), st.floats(0, 1)
        ),
        min_size=1,
        max_size=8,
    )
)
@settings(max_examples=60, deadline=None)
def test_default_order_is_by_perceptual_score_and_every_key_is_a_permutation(rows):
    ms = [_m((a, b), (c, c), (g, -g)) for a, b, c, g, _ in rows]
    scores = [s for *_, s in rows]
    order = rank_candidates(ms, scores)
    assert sorted(order) == list(range(len(ms)))
    ps = [ms[i].perceptual_score for i in order]
    assert ps == sorted(ps, reverse=True)
    for key in RANK_KEYS:
        if key not in ("knit-time", "hand-time", "legibility"):  # each needs a measure given
            assert sorted(rank_candidates(ms, scores, by=key)) == list(range(len(ms)))
    assert rank_candidates(ms, scores, by="score") == sorted(
        range(len(ms)), key=lambda i: (scores[i], i)
    )


def test_ghosting_weighs_by_how_much_of_the_render_it_is():
    # The bundled astronaut/coffee pair in numbers: a design that reproduces its pictures almost
    # exactly has a tiny residue, and a high ghosting correlation of that residue is a faint
    # outline; the same correlation next to a poorer reproduction is a second picture.
    faithful = _m((0.99, 0.98), ghost=(0.29, 0.09))
    washed = _m((0.96, 0.96), ghost=(0.07, 0.09))
    assert faithful.worst_visible_ghosting == pytest.approx(0.29 * np.sqrt(1 - 0.99**2))
    assert washed.worst_visible_ghosting == pytest.approx(0.09 * np.sqrt(1 - 0.96**2))
    assert (
        faithful.worst_visible_ghosting
        < 0.05
        < _m((0.9, 0.9), ghost=(0.29, 0)).worst_visible_ghosting
    )
    # the default order reads first; between equal readings the less visible ghost leads
    assert rank_candidates([washed, faithful], [1.0, 2.0]) == [1, 0]
    ghostly = _m((0.90, 0.90), ghost=(0.30, 0.0))
    clean = _m((0.90, 0.90), ghost=(0.05, 0.0))
    assert rank_candidates([ghostly, clean], [1.0, 2.0]) == [1, 0]
    assert rank_candidates([clean, ghostly], [2.0, 1.0], by="ghosting") == [0, 1]
    # no picture to read (plain, or nothing reads): all of the ghosting shows
    assert _m((None, float("nan")), ghost=(0.2, -0.3)).visible_ghosting == (0.2, 0.3)
    assert _m((0.9, 0.9), ghost=(None, float("nan"))).visible_ghosting == (None, None)


@given(st.floats(-1, 1), st.floats(-1, 1))
def test_visible_ghosting_never_exceeds_ghosting(read, ghost):
    (v, _) = _m((read, read), ghost=(ghost, ghost)).visible_ghosting
    assert 0.0 <= v <= abs(ghost) + 1e-12


def test_visible_ghosting_is_the_semipartial_correlation_of_the_render():
    a, b = _disc(30, 9, 15, 10), _disc(30, 8, 15, 20)
    pal = np.array([[240, 240, 240], [20, 20, 20]], np.uint8)
    mixed = np.where(b == 1, 1 - a, a)  # picture A, with B punched through part of it
    p = LogicalPattern(mixed.astype(np.int16), np.zeros_like(a), YARNS[::-1])
    m = measure_candidate(p, [pal[a], pal[b]])
    # independently: regress the blurred render on the picture, correlate the residue with B
    # and scale by the residue's share of the render's spread
    from illuknit.design.measures import BLUR_SIGMA, angled_renders
    from illuknit.design.measures import blurred_luminance as _grey

    g = _grey(angled_renders(p)[0]["A"], BLUR_SIGMA).ravel()
    t, o = (_grey(pal[x] / 255.0, BLUR_SIGMA).ravel() for x in (a, b))
    design = np.stack([np.ones_like(t), t], axis=1)
    e = g - design @ np.linalg.lstsq(design, g, rcond=None)[0]
    expected = abs(np.corrcoef(e, o)[0, 1]) * e.std() / g.std()
    assert m.visible_ghosting[0] == pytest.approx(expected, rel=1e-6)
    assert 0.05 < m.visible_ghosting[0] < abs(m.ghosting[0])


def test_bad_rank_keys_are_option_errors():
    with pytest.raises(OptionError, match="rank by one of"):
        rank_candidates([_m((1, 1))], [0.0], by="beauty")
    with pytest.raises(OptionError, match="knitting time"):
        rank_candidates([_m((1, 1))], [0.0], by="knit-time")
    assert rank_candidates(
        [_m((1, 1), minutes=2.0), _m((1, 1), minutes=1.0)], [0, 0], by="knit-time"
    ) == [1, 0]


def test_measures_see_the_picture_and_the_ghost():
    a = _disc(30, 9, 15, 10)
    b = _disc(30, 8, 15, 20)
    pal = np.array([[240, 240, 240], [20, 20, 20]], np.uint8)
    # A pattern that shows picture A from both sides: readable as A, ghosting A into view B.
    p = LogicalPattern(a.astype(np.int16), np.zeros_like(a), YARNS[::-1])
    m = measure_candidate(p, [pal[a], pal[b]])
    assert m.readability[0] > 0.9
    assert m.readability[1] < 0.6
    assert abs(m.ghosting[1]) > 0.3
    assert 0.5 < m.contrast[0] < 1.5
    flat = LogicalPattern(np.zeros_like(a), np.zeros_like(a), YARNS)
    fm = measure_candidate(flat, [pal[a], pal[b]])
    assert fm.worse_readability == 0.0  # a flat field reads as nothing (nan counted as 0)
    with pytest.raises(OptionError):
        measure_candidate(flat, [pal[a]])


def test_measures_at_the_eyes_resolution_see_stripes_the_fixed_blur_hides():
    """A picture drawn in row stripes (a striped fill, as the eye sees it from near) reads well
    under the fixed 1.5-unit blur and worse at the eye's resolution from 3 m; a solid picture
    reads the same at both."""
    from illuknit.design.tiles.perception import eye_blur_units

    a = _disc(30, 9, 15, 15)
    pal = np.array([[240, 240, 240], [20, 20, 20]], np.uint8)
    striped = a.copy()
    striped[::2] = False  # the dark disc in alternate dark and light rows
    p = LogicalPattern(striped.astype(np.int16), np.zeros_like(a), YARNS[::-1])
    solid = LogicalPattern(a.astype(np.int16), np.zeros_like(a), YARNS[::-1])
    near = eye_blur_units(3.0)
    assert measure_candidate(p, [pal[a], pal[a]], ghost=False, blur=near).worse_readability < (
        measure_candidate(p, [pal[a], pal[a]], ghost=False).worse_readability - 0.1
    )
    assert (
        measure_candidate(solid, [pal[a], pal[a]], ghost=False, blur=near).worse_readability > 0.9
    )
    default = measure_candidate(p, [pal[a], pal[a]], ghost=False)
    assert measure_candidate(p, [pal[a], pal[a]], ghost=False, blur=1.5) == default
    with pytest.raises(OptionError):
        measure_candidate(p, [pal[a], pal[a]], blur=-1.0)


def test_diagnostic_marks_wrong_units_red():
    a = _disc(30, 9, 15, 15)
    pal = np.array([[240, 240, 240], [20, 20, 20]], np.uint8)
    good = LogicalPattern(a.astype(np.int16), np.zeros_like(a), YARNS[::-1])
    img, stats = diagnostic_rgb(good, pal[a])
    assert img.shape == (30, 30, 3) and img.dtype == np.uint8
    assert stats["wrong"] < 0.05
    broken = a.copy()
    broken[11:19, 11:19] = 0  # a hole knitted in the disc
    bad = LogicalPattern(broken.astype(np.int16), np.zeros_like(a), YARNS[::-1])
    img, stats = diagnostic_rgb(bad, pal[a])
    assert stats["wrong"] > 0.03
    red = (img[..., 0] > 200) & (img[..., 1] < 60)
    near = np.zeros_like(red)
    near[8:24, 8:24] = True
    assert red[near].sum() > 0 and red[~near].sum() == 0


def test_rank_designs_default_reads_best_on_a_small_pair():
    a, b = _disc(24, 8, 12, 8), _disc(24, 7, 10, 16)
    pal = np.array([[20, 20, 20], [240, 240, 240]], np.uint8)
    cands = assign_tiles((a, pal), (b, pal), yarns=YARNS, candidates=4)
    ranked = rank_designs(cands, [pal[a], pal[b]])
    assert [r.assignment.rank for r in ranked] == list(range(1, len(ranked) + 1))
    assert sorted(r.score_rank for r in ranked) == sorted(c.rank for c in cands)
    top = ranked[0].measures.perceptual_score
    assert all(top >= r.measures.perceptual_score for r in ranked)


def test_double_writes_measures_diagnostics_and_reranks(tmp_path, run_cli):
    for name, img in (("a.png", _disc(30, 10, 15, 11)), ("b.png", _disc(30, 9, 15, 19))):
        Image.fromarray(((1 - img) * 255).astype(np.uint8)).save(tmp_path / name)
    out = tmp_path / "out"
    code, _, err = run_cli(
        ["double", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "-o", str(out)]
    )
    assert code == 0, err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["ranked_by"] == "perception"
    rows = summary["candidates"]
    assert rows[0]["default"] and rows[0]["rank"] == 1
    assert rows[0]["perceptual_score"] == max(row["perceptual_score"] for row in rows)
    for row in rows:
        assert len(row["readability"]) == 2 and len(row["ghosting"]) == 2
        for letter in "ab":
            assert (out / row["folder"] / f"diagnostic_{letter}.png").is_file()
    report = json.loads((out / "candidate_1" / "report.json").read_text())
    assert "perceptual_score" in json.dumps(report)
    by_score = tmp_path / "by_score"
    code, _, err = run_cli(
        ["double", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "-o", str(by_score),
         "--rank-by", "score"])  # fmt: skip
    assert code == 0, err
    rows = json.loads((by_score / "summary.json").read_text())["candidates"]
    assert [row["score_rank"] for row in rows] == [row["rank"] for row in rows]
    code, _, err = run_cli(
        ["double", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "-o", str(tmp_path / "x"),
         "--rank-by", "beauty"])  # fmt: skip
    assert code == 2 and not (tmp_path / "x").exists()
    assert len(err.strip().splitlines()) == 1


def test_rank_designs_keeps_the_best_of_a_pool_and_knits_only_those():
    a, b = _disc(20, 7, 10, 7), _disc(20, 6, 9, 13)
    pal = np.array([[20, 20, 20], [240, 240, 240]], np.uint8)
    pool = assign_tiles((a, pal), (b, pal), yarns=YARNS, candidates=2, pool=8)
    assert len(pool) > 2
    everything = rank_designs(pool, [pal[a], pal[b]])
    knitted = []

    def knit_time(pattern):
        knitted.append(pattern)
        return knit_stats(pattern)

    kept = rank_designs(pool, [pal[a], pal[b]], keep=2, knit_time=knit_time)
    assert [r.score_rank for r in kept] == [r.score_rank for r in everything[:2]]
    assert [r.assignment.rank for r in kept] == [1, 2]
    assert all(r.measures.knit_minutes and r.measures.machine_passes for r in kept)
    assert len(knitted) == 2
    with pytest.raises(OptionError, match="keep"):
        rank_designs(pool, [pal[a], pal[b]], keep=0)
    with pytest.raises(OptionError, match="knit_time"):
        rank_designs(pool, [pal[a], pal[b]], rank_by="knit-time")


def test_double_writes_the_best_of_the_pool_it_searched(tmp_path, run_cli):
    a, b = _disc(24, 8, 12, 8), _disc(24, 7, 11, 15)
    for name, img in (("a.png", a), ("b.png", b)):
        Image.fromarray(((1 - img) * 255).astype(np.uint8)).save(tmp_path / name)
    out = tmp_path / "out"
    code, _, err = run_cli(
        ["double", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "-o", str(out),
         "--candidates", "2", "--pool", "12", "--square-units"])  # fmt: skip
    assert code == 0, err
    summary = json.loads((out / "summary.json").read_text())
    rows = summary["candidates"]
    assert len(rows) == 2 and summary["searched"] > 2
    assert "best 2 of" in (out / "summary.txt").read_text()
    # the written default is the best-reading design of the whole pool, recomputed here
    pal = np.array([[255, 255, 255], [0, 0, 0]], np.uint8)
    pool = assign_tiles((a, pal), (b, pal), candidates=summary["searched"], yarns=YARNS)
    best = rank_designs(pool, [pal[a], pal[b]])[0].measures
    assert rows[0]["readability"] == pytest.approx(list(best.readability), abs=1e-4)
    code, _, err = run_cli(
        ["double", str(tmp_path / "a.png"), str(tmp_path / "b.png"), "-o", str(tmp_path / "x"),
         "--pool", "0"])  # fmt: skip
    assert code == 2 and not (tmp_path / "x").exists() and len(err.strip().splitlines()) == 1


def test_rank_designs_reports_progress_and_a_raising_hook_stops_it():
    a, b = _disc(16, 5, 8, 5), _disc(16, 5, 8, 11)
    pal = np.array([[20, 20, 20], [240, 240, 240]], np.uint8)
    pool = assign_tiles((a, pal), (b, pal), yarns=YARNS, candidates=3)
    seen: list[float] = []
    rank_designs(pool, [pal[a], pal[b]], progress=lambda f, _: seen.append(f))
    assert len(seen) == len(pool) and seen == sorted(seen) and seen[0] == 0.0

    class Cancelled(Exception):
        pass

    def cancel(fraction, _):
        if fraction > 0:
            raise Cancelled

    with pytest.raises(Cancelled):
        rank_designs(pool, [pal[a], pal[b]], progress=cancel)


def test_rank_designs_takes_its_measuring_as_a_context_or_as_the_old_keywords():
    # #36: at most 8 parameters; the measuring settings are one MeasureContext, and its fields
    # stay accepted as keywords, so callers written for the 13-parameter signature need no change
    import inspect

    from illuknit.design.tiles.perception import MeasureContext

    assert len(inspect.signature(rank_designs).parameters) <= 8
    a, b = _disc(16, 5, 8, 5), _disc(16, 5, 8, 11)
    pal = np.array([[20, 20, 20], [240, 240, 240]], np.uint8)
    pool = assign_tiles((a, pal), (b, pal), yarns=YARNS, candidates=3)
    pictures = [pal[a], pal[b]]
    by_keywords = rank_designs(pool, pictures, angle=40.0, blur=1.0, views=("A", "B"))
    context = MeasureContext(angle=40.0, blur=1.0)
    by_context = rank_designs(pool, pictures, context=context)
    assert [r.measures for r in by_keywords] == [r.measures for r in by_context]
    assert [r.score_rank for r in by_keywords] == [r.score_rank for r in by_context]
    # a keyword replaces that field of the context
    wider = rank_designs(pool, pictures, context=context, blur=2.0)
    alone = rank_designs(pool, pictures, context=MeasureContext(angle=40.0, blur=2.0))
    assert [r.measures for r in wider] == [r.measures for r in alone]
    assert [r.measures for r in wider] != [r.measures for r in by_context]
    with pytest.raises(OptionError, match="unknown ranking option 'anlge'; valid: views"):
        rank_designs(pool, pictures, anlge=40.0)
    with pytest.raises(OptionError, match="`context` must be a MeasureContext"):
        rank_designs(pool, pictures, context={"angle": 40.0})
    with pytest.raises(OptionError, match="knit_time"):
        rank_designs(pool, pictures, rank_by="knit-time", context=context)


def test_a_cleaner_candidate_is_named_when_the_default_shows_much_of_the_other_picture():
    ghostly = _m((0.95, 0.944), ghost=(0.8, 0.8))  # shows 0.8 * sqrt(1 - 0.944**2) = 0.26
    clean = _m((0.96, 0.935), ghost=(0.1, 0.12))  # 0.04, reads nearly as well
    cleaner_still = _m((0.96, 0.89), ghost=(0.0, 0.0))  # cleaner, but 0.054 below: not offered
    assert ghostly.worst_visible_ghosting == pytest.approx(0.264, abs=1e-3)
    assert cleaner_alternative([ghostly, cleaner_still, clean], 0) == 2
    assert cleaner_alternative([ghostly, cleaner_still], 0) is None
    # the default already the cleanest, or no candidate cleaner by the margin: none
    assert cleaner_alternative([clean, ghostly], 0) is None
    slightly = _m((0.95, 0.944), ghost=(0.5, 0.5))  # half as much, but only 0.1 less
    assert (
        ghostly.worst_visible_ghosting - slightly.worst_visible_ghosting < CLEANER_GHOSTING_MARGIN
    )
    assert cleaner_alternative([ghostly, slightly], 0) is None
    little = _m((0.95, 0.944), ghost=(0.2, 0.2))  # 0.066: less by 0.20 (> the margin)
    assert cleaner_alternative([ghostly, little], 0) == 1
    # a candidate that reads fewer sides is never offered for less ghosting
    read_two, read_one = replace(ghostly, sides_read=2), replace(clean, sides_read=1)
    assert cleaner_alternative([read_two, read_one], 0) is None
    assert cleaner_alternative([read_two, replace(clean, sides_read=2)], 0) == 1


@settings(max_examples=60, deadline=None)
@given(
    st.lists(
        st.tuples(st.floats(0.3, 1.0), st.floats(0.3, 1.0), st.floats(0.0, 1.0)),
        min_size=1,
        max_size=6,
    ),
    st.data(),
)
def test_the_cleaner_candidate_is_cleaner_and_reads_nearly_as_well(rows, data):
    ms = [_m((a, b), ghost=(g, g)) for a, b, g in rows]
    default = data.draw(st.integers(0, len(ms) - 1))
    k = cleaner_alternative(ms, default)
    d = ms[default]
    ok = [
        i
        for i, m in enumerate(ms)
        if i != default
        and m.worst_visible_ghosting <= d.worst_visible_ghosting / 2
        and m.worst_visible_ghosting <= d.worst_visible_ghosting - CLEANER_GHOSTING_MARGIN
        and m.perceptual_score >= d.perceptual_score - 0.05
    ]
    if not ok:
        assert k is None
    else:
        assert k in ok
        assert ms[k].perceptual_score == max(ms[i].perceptual_score for i in ok)
