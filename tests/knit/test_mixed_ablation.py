"""Paper Fig. 20: each compiler pass switched off produces the failure the checker must find.

The design is a small two-colour plus sign: a colour-1 bar running the full height of a colour-0
ground (so every course changes colour twice, and the bar is a region of its own from cast-on
to bind-off), crossed by a bar of purl bumps, with more bumps inside the colour bar. The ground
yarn is stranded behind the bar, the bar yarn is intarsia.
"""

from __future__ import annotations

import numpy as np
import pytest

from illuknit.check import check_knitout
from illuknit.core.pattern import LogicalPattern, Yarn
from illuknit.knit import lower_to_stitches, write_knitout
from illuknit.knit.mixed import schedule_mixed
from illuknit.knit.options import KnitOptions

YARNS = (Yarn("navy", (29, 43, 83)), Yarn("cream", (244, 240, 232)))


def plus_sign(n: int = 8, m: int = 8) -> LogicalPattern:
    yarn = np.zeros((n, m), np.int16)
    yarn[:, m // 2 - 1 : m // 2 + 1] = 1
    raised = np.zeros((n, m), bool)
    raised[n // 2 - 1 : n // 2 + 1, :] = True
    raised[::3, m // 2] = True
    return LogicalPattern(yarn, raised, YARNS, {"name": "plus"})


def program(**switches) -> str:
    return write_knitout(
        schedule_mixed(lower_to_stitches(plus_sign()), options=KnitOptions(**switches))
    )


@pytest.fixture(scope="module")
def full():
    return program()


def test_all_passes_on_is_clean_in_both_checkers(full):
    report = check_knitout(full, float_limit=20, simulate=True)
    assert report.ok, [f.to_dict() for f in report.blocking][:3]
    assert report.pieces == 1
    assert report.vm is not None and report.vm["ran"] and report.vm["pieces"] == 1
    assert not [f for f in report.findings if f.source == "vm"]


@pytest.mark.parametrize("strategy", ["split", "anchor"])
def test_both_path_strategies_are_clean(strategy):
    report = check_knitout(program(path_planning=strategy), float_limit=20)
    assert report.ok and report.pieces == 1


def test_without_float_avoidance_floats_cross_the_purls():
    codes = check_knitout(program(float_avoidance=False), float_limit=20).codes()
    assert codes["face-float"] > 0
    assert codes["wrong-side-carrier"] == 0 and codes["pieces"] == 0


def test_without_catching_the_bar_falls_off_the_ground():
    report = check_knitout(program(catching="off"), float_limit=20)
    assert report.pieces > 1
    assert report.codes()["pieces"] >= 1
    assert report.codes()["face-float"] == 0 and report.codes()["wrong-side-carrier"] == 0


def test_without_path_planning_stitches_are_made_from_the_wrong_side():
    report = check_knitout(program(path_planning="none"), float_limit=20)
    assert report.codes()["wrong-side-carrier"] > 0


def test_the_ablations_cost_or_save_passes_as_expected():
    st = lower_to_stitches(plus_sign())
    full = schedule_mixed(st).stats
    no_catch = schedule_mixed(st, options=KnitOptions(catching="off")).stats
    plated = schedule_mixed(st, options=KnitOptions(catching="plate")).stats
    # plated stitches are passes of their own: dropping them saves passes; tuck joins ride in
    # the carriers' own passes (the body's: without catching each run binds off on its own)
    assert no_catch.body_passes < plated.body_passes
    assert full.body_passes < plated.body_passes
    assert full.lower_bound <= full.passes
