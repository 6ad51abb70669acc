"""The design commands parse their switches once into a request object (the pictures, where to
write, the size and colours, the stage's option objects, the resolved machine) that the run
helpers take; a switch no command has is a programming error, not a silent default."""

from __future__ import annotations

from pathlib import Path

import pytest

from illuknit.cli.double import DesignRequest
from illuknit.cli.knit import KnitMachine, _knit_options
from illuknit.cli.single import SingleRequest
from illuknit.cli.solve import SolveRequest
from illuknit.core.errors import ImageInputError
from illuknit.design.options import Brightness, PictureEdits, RankBy


def test_a_design_request_holds_the_stage_options():
    r = DesignRequest.from_switches(
        Path("a.png"), Path("b.png"), Path("out"), candidates=3, pool=7, brightness="soft",
        suggest=True, rank_by="score", angle=20.0, width=30, resize=True, yarns="2", read=False,
    )  # fmt: skip
    assert (r.search.candidates, r.search.pool) == (3, 7)
    assert r.search.brightness is Brightness.SOFT and r.search.edits is PictureEdits.SUGGEST
    assert r.ranking.rank_by is RankBy.SCORE and r.ranking.angle == 20.0
    assert (r.sizing.width, r.sizing.stretch, r.sizing.yarns, r.sizing.n_colors) == (
        30,
        True,
        2,
        None,
    )
    assert r.sources == ["a.png", "b.png"]
    assert r.machine.fabric_gauge.unit_aspect == r.sizing.unit_aspect


def test_a_double_view_request_needs_two_pictures_and_known_switches():
    with pytest.raises(ImageInputError, match="two pictures"):
        DesignRequest.from_switches(Path("a.png"), None, Path("out"), read=False)
    with pytest.raises(TypeError, match="candidatez"):
        DesignRequest.from_switches(Path("a.png"), Path("b.png"), Path("o"), candidatez=3)


def test_solve_and_single_requests():
    r = SolveRequest.from_switches(
        Path("a.png"), Path("b.png"), Path("out"), solver="dp", width=12, yarns="black,white"
    )
    assert r.options.solver == "dp" and r.sizing.width == 12 and len(r.sizing.yarns) == 2
    s = SingleRequest.from_switches("a.png", "out", gauge=5.0, first="light")
    assert s.machine.gauge == 5.0 == s.sizing.gauge and s.first == "light"
    with pytest.raises(TypeError, match="colours"):
        SingleRequest.from_switches("a.png", "out", colours=3)


def test_knit_switches_become_knit_options():
    switches = dict(
        cast_on_courses=3, strict_floats=False, allow_long_floats=False, tuck_passes=False,
        float_avoidance_on=False, no_float_avoidance=True, catching_on=False, plate=True,
        no_catching=False, catch_every=1, path_planning=("split",),
    )  # fmt: skip
    opts = _knit_options(**switches)
    assert (opts.cast_on_courses, opts.float_avoidance, opts.catch_every) == (3, False, 1)
    assert opts.catching.value == "plate" and opts.path_planning.value == "split"
    assert KnitMachine("kniterate", float_limit=8).float_limit == 8
