"""Every kind of pattern the project makes knits through ``knit_pattern`` into a clean program.

Each program must have zero blocking findings in illuknit's checker and run through the PyPI
knitout-interpreter / virtual-knitting-machine without errors (small sizes: that simulator is
slow).
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from illuknit.check import check_knitout
from illuknit.core.machine import MACHINES, MachineSpec
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.knitting import knit_pattern
from illuknit.pictures.drawings import draw_shape, to_index_image

sys.path.insert(0, str(Path(__file__).parents[1] / "formats"))
sys.path.insert(0, str(Path(__file__).parent))
from test_float_truth import assert_one_float_truth
from test_kc import assert_same_as_reference

YARNS = parse_yarns("#1b1b1b,#f4f0e8")
YARNS3 = parse_yarns("#1b1b1b,#f4f0e8,#b3202a")
YARNS4 = parse_yarns("#1b1b1b,#f4f0e8,#b3202a,#2030a0")
COLS = np.array([[27, 27, 27], [244, 240, 232]], dtype=np.uint8)


@pytest.fixture(params=["generic540", "kniterate"])
def machine(request) -> MachineSpec:
    """Both kinds of machine: a Shima with an inserting hook, and the Kniterate without."""
    return MACHINES[request.param]


def assert_knits(pattern: LogicalPattern, *, simulate: bool = True, machine=None, tmp_path=None):
    """Knit ``pattern``: clean in illuknit's checker (no finding at all), one piece, through the
    PyPI simulator without errors, the reported floats the checker's, and on the Kniterate
    accepted by the reference backend."""
    result = knit_pattern(pattern, machine=machine)
    report = check_knitout(result.text, float_limit=result.machine.float_limit, simulate=simulate)
    assert report.ok, [f.to_dict() for f in report.blocking][:3]
    assert not [f for f in report.findings if f.source == "illuknit"], report.findings[:3]
    assert report.pieces == 1
    if simulate:
        assert report.vm is not None and report.vm.get("ran"), report.vm
        assert not [f for f in report.findings if f.source == "vm" and f.blocking]
        assert report.vm["pieces"] == 1
    # the schedule's bound and passes (the Kniterate's summary counts the .kc's passes)
    assert result.stats.lower_bound <= result.stats.passes
    assert_one_float_truth(result)
    if not result.machine.inserting_hook and tmp_path is not None:
        assert assert_same_as_reference(result.text, tmp_path) is not None, "backend refused"
    return result


def targets(shape):
    a = to_index_image(draw_shape("plus", shape), ink=0, paper=1)
    b = to_index_image(draw_shape("circle", shape), ink=0, paper=1)
    return a, b


def test_double_view_from_tiles(machine, tmp_path):
    from illuknit.design.tiles import assign_tiles, compile_tiles

    a, b = targets((6, 8))
    found = assign_tiles((a, COLS), (b, COLS), yarns=YARNS, candidates=1, time_limit=10)
    pattern, _ = compile_tiles(found[0])
    assert (pattern.yarn != pattern.yarn[:, :1]).any()  # really mixed colourwork
    r = assert_knits(pattern, machine=machine, tmp_path=tmp_path)
    assert r.schedule.scheduler == "mixed-colourwork"


def test_head_on_tiles(machine, tmp_path):
    from illuknit.design.tiles import assign_headon, compile_tiles

    a, _ = targets((6, 8))
    found = assign_headon((a, COLS), yarns=YARNS, candidates=1, time_limit=10)
    pattern, _ = compile_tiles(found[0])
    assert_knits(pattern, machine=machine, tmp_path=tmp_path)


def test_solver_output_dp(machine, tmp_path):
    from illuknit.design.models.illusion_models import solve_illusion

    a, b = targets((5, 6))
    res = solve_illusion(a, b, solver="dp", yarns=YARNS, time_limit=10)
    assert_knits(res.pattern, machine=machine, tmp_path=tmp_path)


def test_calibration_swatch(machine, tmp_path):
    from illuknit.design.render import calibrate

    swatch = calibrate.calibration_swatch(bump_sizes=(1, 2), flat_sizes=(1, 2), cell_width=3)
    assert_knits(swatch, machine=machine, tmp_path=tmp_path)


def test_single_view_still_takes_the_one_color_scheduler(machine, tmp_path):
    from illuknit.design.single_view import compile_single_view

    img = to_index_image(draw_shape("heart", (5, 6)), ink=0, paper=1)
    r = assert_knits(compile_single_view(img, yarns=YARNS), machine=machine, tmp_path=tmp_path)
    assert r.schedule.scheduler == "one-colour-per-course"


def test_three_yarns_and_long_floats_on_a_narrow_float_limit(machine, tmp_path):
    rng = np.random.default_rng(3)
    yarn = rng.integers(0, 3, size=(4, 10))
    raised = rng.random((4, 10)) < 0.4
    pattern = LogicalPattern(yarn, raised, YARNS3)
    # (On the Kniterate up to six yarns come in with tucks every sixth needle of the waste
    # section: its float limit must be at least 5.)
    limit = 4 if machine.inserting_hook else 5
    assert_knits(pattern, machine=replace(machine, float_limit=limit), tmp_path=tmp_path)


def test_a_float_limit_below_the_waste_sections_yarn_in_tucks_is_refused_saying_so():
    from illuknit.core.errors import LongFloatError

    stripes = np.repeat(np.arange(4), 2)[None].repeat(2, axis=0)  # no float in the piece
    pattern = LogicalPattern(stripes, np.zeros(stripes.shape, bool), YARNS4)
    kniterate = replace(MACHINES["kniterate"], float_limit=4)
    with pytest.raises(LongFloatError, match="in the waste section the yarns come in with") as e:
        knit_pattern(pattern, machine=kniterate)
    assert "tucks 6 needles apart: a float limit below 5 needs fewer yarns" in str(e.value)
    assert (
        knit_pattern(pattern, machine=replace(kniterate, float_limit=5)).schedule.long_floats == ()
    )
