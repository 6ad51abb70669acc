"""Every kind of pattern the project makes knits through ``knit_pattern`` into a clean program.

Each program must have zero blocking findings in illuknit's checker and run through the PyPI
knitout-interpreter / virtual-knitting-machine without errors (small sizes: that simulator is
slow).
"""

from __future__ import annotations

import numpy as np

from illuknit.check import check_knitout
from illuknit.core.machine import MachineSpec
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.knitting import knit_pattern
from illuknit.pictures.drawings import draw_shape, to_index_image

YARNS = parse_yarns("#1b1b1b,#f4f0e8")
COLS = np.array([[27, 27, 27], [244, 240, 232]], dtype=np.uint8)


def assert_knits(pattern: LogicalPattern, *, simulate: bool = True, machine=None):
    result = knit_pattern(pattern, machine=machine)
    report = check_knitout(result.text, float_limit=result.machine.float_limit, simulate=simulate)
    assert report.ok, [f.to_dict() for f in report.blocking][:3]
    assert report.pieces == 1
    if simulate:
        assert report.vm is not None and report.vm.get("ran"), report.vm
        assert not [f for f in report.findings if f.source == "vm" and f.blocking]
        assert report.vm["pieces"] == 1
    s = result.summary()
    assert s["lower_bound"] <= s["passes"]
    return result


def targets(shape):
    a = to_index_image(draw_shape("plus", shape), ink=0, paper=1)
    b = to_index_image(draw_shape("circle", shape), ink=0, paper=1)
    return a, b


def test_double_view_from_tiles():
    from illuknit.design.tiles import assign_tiles, compile_tiles

    a, b = targets((6, 8))
    found = assign_tiles((a, COLS), (b, COLS), yarns=YARNS, candidates=1, time_limit=10)
    pattern, _ = compile_tiles(found[0])
    assert (pattern.yarn != pattern.yarn[:, :1]).any()  # really mixed colourwork
    r = assert_knits(pattern)
    assert r.schedule.scheduler == "mixed-colourwork"


def test_head_on_tiles():
    from illuknit.design.tiles import assign_headon, compile_tiles

    a, _ = targets((6, 8))
    found = assign_headon((a, COLS), yarns=YARNS, candidates=1, time_limit=10)
    pattern, _ = compile_tiles(found[0])
    assert_knits(pattern)


def test_solver_output_dp():
    from illuknit.design.models.illusion_models import solve_illusion

    a, b = targets((5, 6))
    res = solve_illusion(a, b, solver="dp", yarns=YARNS, time_limit=10)
    assert_knits(res.pattern)


def test_calibration_swatch():
    from illuknit.design.render import calibrate

    swatch = calibrate.calibration_swatch(bump_sizes=(1, 2), flat_sizes=(1, 2), cell_width=3)
    assert_knits(swatch)


def test_single_view_still_takes_the_one_color_scheduler():
    from illuknit.design.single_view import compile_single_view

    img = to_index_image(draw_shape("heart", (5, 6)), ink=0, paper=1)
    r = assert_knits(compile_single_view(img, yarns=YARNS))
    assert r.schedule.scheduler == "one-colour-per-course"


def test_three_yarns_and_long_floats_on_a_narrow_float_limit():
    rng = np.random.default_rng(3)
    yarn = rng.integers(0, 3, size=(4, 10))
    raised = rng.random((4, 10)) < 0.4
    pattern = LogicalPattern(yarn, raised, parse_yarns("#1b1b1b,#f4f0e8,#b3202a"))
    assert_knits(pattern, machine=MachineSpec(float_limit=4))
