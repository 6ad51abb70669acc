"""Benchmark metrics on cases small enough to compute by hand."""

from __future__ import annotations

import numpy as np
import pytest

from illuknit.bench.instances import Targets
from illuknit.bench.metrics import PeakMemory, knit_stats, logical_errors, yarn_map
from illuknit.core.colors import linear_from_srgb, srgb_from_linear
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.design.measures import (
    angled_renders,
    blur_image,
    color_changes,
    ghosting,
    render_correlation,
    render_error,
)

BW = parse_yarns("#000000,#ffffff")


def test_logical_error_counts_wrongly_seen_units():
    # 2 x 2, nothing raised: every view sees C itself.
    p = LogicalPattern([[0, 1], [1, 1]], np.zeros((2, 2), bool), BW)
    t = Targets(np.array([[0, 1], [1, 0]]), np.array([[1, 1], [1, 1]]), BW)
    assert logical_errors(p, t) == {"A": 0.25, "B": 0.25}


def test_logical_error_follows_can_see_with_a_bump():
    # Column of 3: top unit is a black bump. View A sees it at rows 0 and 1; view B sees C.
    p = LogicalPattern([[0], [1], [1]], [[True], [False], [False]], BW)
    t = Targets(np.array([[0], [0], [1]]), np.array([[0], [1], [1]]), BW)
    assert logical_errors(p, t) == {"A": 0.0, "B": 0.0}
    t2 = Targets(np.array([[0], [1], [1]]), np.array([[0], [1], [1]]), BW)
    assert logical_errors(p, t2)["A"] == pytest.approx(1 / 3)


def test_yarns_are_compared_by_color_not_index():
    # The pattern lists the same yarns in the opposite order; a foreign yarn never matches.
    p = LogicalPattern([[0, 1]], [[False, False]], parse_yarns("#ffffff,#000000"))
    t = Targets(np.array([[1, 0]]), np.array([[1, 0]]), BW)
    assert logical_errors(p, t) == {"A": 0.0, "B": 0.0}
    assert yarn_map(parse_yarns("#ffffff,#ff0000"), BW).tolist() == [1, -1]


def test_blur_turns_two_row_stripes_into_their_linear_light_mean():
    stripes = np.zeros((40, 20, 3))
    stripes[::2] = 1.0  # black / white rows
    grey = srgb_from_linear(np.full((40, 20, 3), 0.5)) / 255.0  # the mean, in linear light
    b = blur_image(stripes)
    inner = b[10:30, 5:15]
    assert np.allclose(inner, grey[10:30, 5:15], atol=0.01)
    mse, ssim = render_error(stripes, grey)
    assert mse < 1e-3 and ssim > 0.9  # only the edge rows differ
    # but stripes are far from a solid black of the same size
    assert render_error(stripes, np.zeros_like(stripes))[0] > 0.4


def test_render_error_extremes():
    black = np.zeros((16, 16, 3))
    white = np.ones((16, 16, 3))
    assert render_error(black, black) == (0.0, 1.0)
    mse, _ = render_error(black, white)
    assert mse == pytest.approx(1.0)


def test_blur_keeps_a_flat_image_and_mixes_in_linear_light():
    img = np.full((10, 10, 3), 0.3)
    assert np.allclose(blur_image(img), 0.3)
    assert linear_from_srgb(np.array([255.0]))[0] == pytest.approx(1.0)


def test_correlation_and_ghosting():
    rng = np.random.default_rng(0)
    a = np.kron(rng.random((6, 6)) > 0.5, np.ones((4, 4))).astype(float)
    b = np.kron(rng.random((6, 6)) > 0.5, np.ones((4, 4))).astype(float)
    A, B = (np.repeat(x[:, :, None], 3, axis=2) for x in (a, b))
    assert render_correlation(A, A) == pytest.approx(1.0)
    assert render_correlation(1.0 - A, A) == pytest.approx(-1.0)
    # a faded copy reads as well as the original (correlation ignores contrast)
    assert render_correlation(0.3 + 0.4 * A, A) == pytest.approx(1.0)
    assert np.isnan(render_correlation(np.zeros_like(A), A))
    # no ghost in a clean view; a view mixing in B shows B's ghost
    assert abs(ghosting(A, A, B)) < 1e-6 or np.isnan(ghosting(A, A, B))
    assert ghosting(0.6 * A + 0.4 * B, A, B) > 0.8
    assert ghosting(0.9 * A + 0.1 * B, A, B) > 0.5


def test_color_changes_per_course():
    p = LogicalPattern([[0, 1, 1, 0], [0, 0, 0, 0], [1, 0, 1, 0]], np.zeros((3, 4), bool), BW)
    cc = color_changes(p)
    assert cc["changes_mean"] == pytest.approx((2 + 0 + 3) / 3)
    assert cc["changes_max"] == 3
    assert cc["yarns_per_course_mean"] == pytest.approx(5 / 3)
    assert cc["yarns_per_course_max"] == 2


def test_knit_stats_for_one_color_per_course_and_for_mixed_courses():
    stripes = LogicalPattern(
        np.repeat(np.array([[0], [1], [0], [1]]), 6, axis=1), np.eye(4, 6, dtype=bool), BW
    )
    ks = knit_stats(stripes)
    assert ks["knit_note"] == ""
    from illuknit.formats import machine_passes
    from illuknit.knitting import knit_pattern

    # the machine's passes (the .dat's rows), not the scheduler's own count
    ref = knit_pattern(stripes)
    passes = machine_passes(ref.program)
    # (KnitResult.stats is the machine's count too; the schedule's own is schedule.stats)
    assert ks["carriage_passes"] == len(passes) == ref.stats.passes >= ref.schedule.stats.passes
    assert ks["scheduled_passes"] == ref.schedule.stats.passes
    assert ks["transfer_passes"] == sum(p.kind.value == "transfer" for p in passes)
    assert ks["knit_time_min"] == pytest.approx(ref.time.seconds / 60)
    assert ref.time.passes == len(passes)  # the time is counted on the machine's passes
    assert ks["carriage_passes"] > 0 and ks["knit_time_min"] > 0
    assert 0 <= ks["transfer_passes"] < ks["carriage_passes"]
    narrow = knit_stats(stripes, machine="swg091n2")
    assert narrow["carriage_passes"] == ks["carriage_passes"]
    mixed = LogicalPattern([[0, 1, 0, 1]] * 4, np.zeros((4, 4), bool), BW)
    km = knit_stats(mixed)
    if km["carriage_passes"] is None:  # until the mixed-colourwork scheduler lands
        assert km["knit_note"] and km["knit_time_min"] is None
    else:
        assert km["carriage_passes"] > ks["carriage_passes"] / 4


def test_renders_have_one_pixel_per_unit_and_three_views():
    p = LogicalPattern([[0, 1], [1, 0], [0, 0]], [[True, False], [False, True], [False, False]], BW)
    views, name = angled_renders(p)
    assert set(views) == {"A", "B", "headon"}
    assert all(v.shape == (3, 2, 3) and v.min() >= 0 and v.max() <= 1 for v in views.values())
    assert name.startswith(("angled", "boolean"))


def test_peak_memory_sees_a_large_allocation():
    with PeakMemory() as mem:
        block = np.ones(80 * 1024 * 1024 // 8)  # 80 MB, touched
        block.sum()
        del block
    assert mem.delta_mb > 60
    assert mem.peak_mb >= mem.start_mb + mem.delta_mb - 1e-6


def test_unschedulable_patterns_get_a_reason_instead_of_numbers():
    wide = LogicalPattern(np.zeros((2, 400), int), np.zeros((2, 400), bool), BW)
    ks = knit_stats(wide)
    assert ks["carriage_passes"] is None and ks["knit_time_min"] is None
    assert "not schedulable" in ks["knit_note"] and "wide" in ks["knit_note"]


def test_knit_stats_measure_a_pattern_with_long_floats_and_note_them(monkeypatch):
    from illuknit.core.machine import MACHINES, MachineSpec
    from tests.knitting.test_pipeline import _crowded

    # the bench allows long floats (it compares passes); the note says they are there
    tight = MachineSpec(name="Tight", float_limit=1, carriers=("1", "2", "3"))
    monkeypatch.setitem(MACHINES, "tight", tight)
    ks = knit_stats(_crowded(), machine="tight")
    assert ks["carriage_passes"] > 0 and ks["knit_time_min"] > 0
    assert "float(s) longer than the float limit of 1 needles" in ks["knit_note"]
    assert "the longest" in ks["knit_note"] and "course" in ks["knit_note"]


def test_summary_says_which_methods_were_knit_with_long_floats():
    from illuknit.bench.report import format_summary

    row = {
        "instance": "tiny",
        "kind": "double",
        "rows": 4,
        "cols": 4,
        "n_yarns": 2,
        "time_limit": 10,
        "method": "tiles",
        "status": "feasible",
        "logical_error_a": 0.0,
        "logical_error_b": 0.0,
        "render_mse_a": 0.0,
        "render_mse_b": 0.0,
        "render_ssim_a": 1.0,
        "render_ssim_b": 1.0,
        "color_changes_mean": 1.0,
        "color_changes_max": 1,
        "carriage_passes": 40,
        "transfer_passes": 4,
        "knit_time_min": 1.0,
        "knit_note": "1 float(s) longer than the float limit of 1 needles kept",
    }
    text = format_summary([row])
    assert "Knit with long floats (measured anyway) -- tiles: 1 float(s)" in text
    assert "No knitting numbers" not in text
