"""The viewing angle's lower bound is declared once (RankOptions.angle, 3 degrees) where the
renderer can draw the side views: `double --angle 1` used to fail late with "`unit_aspect` must
be a finite number in [0.05, 20]" (the contact sheet undoes the foreshortening, unit aspect /
sin(angle), which leaves the renderer's range below 2.006 degrees at stocking stitch)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from PIL import Image

from illuknit.cli import main
from illuknit.core.arguments import UNIT_ASPECT_RANGE
from illuknit.core.errors import OptionError
from illuknit.core.gauge import STOCKINETTE_COURSE_ASPECT
from illuknit.core.machine import resolve_machine
from illuknit.core.pattern import LogicalPattern
from illuknit.core.yarns import parse_yarns
from illuknit.design.options import RankOptions
from illuknit.design.render.raycast import render_image


def _pictures(tmp_path):
    a = np.full((6, 10, 3), 240, np.uint8)
    a[2:4, 2:8] = 20
    b = np.full((6, 10, 3), 20, np.uint8)
    b[1:5, 4:6] = 240
    Image.fromarray(a).save(tmp_path / "a.png")
    Image.fromarray(b).save(tmp_path / "b.png")
    return [str(tmp_path / "a.png"), str(tmp_path / "b.png")]


def test_the_declared_bound_is_where_the_renderer_can_draw_the_default_fabric():
    aspect = resolve_machine(None).fabric_gauge.unit_aspect
    true_bound = math.degrees(math.asin(aspect / UNIT_ASPECT_RANGE[1]))
    assert 2.0 < true_bound < 3.0
    assert 20 * math.sin(math.radians(3)) >= STOCKINETTE_COURSE_ASPECT
    yarn = np.tile(np.repeat(np.arange(2, dtype=np.int16), 2), 2).reshape(2, 4)
    pattern = LogicalPattern(yarn, yarn.astype(bool), parse_yarns("a=#000000,b=#ffffff"))
    for angle in (3.0, 30.0):  # as the contact sheet draws a side view
        sine = math.sin(math.radians(angle))
        img = render_image(pattern, angle, scale=2, unit_aspect=aspect / sine)
        assert img.shape[0] == round(2 * 2 * aspect)


@pytest.mark.parametrize("angle", [1, 2.9, 0])
def test_the_library_refuses_an_angle_below_the_bound(angle):
    with pytest.raises(OptionError, match=r"`angle` must be a number in \[3, 90\]"):
        RankOptions(angle=angle)


def test_double_refuses_angle_1_in_one_line_naming_it(tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["double", *_pictures(tmp_path), "--candidates", "1", "--angle", "1",
              "-o", str(tmp_path / "out")])  # fmt: skip
    assert exit_.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--angle" in err[0] and "3<=x<=90" in err[0], err
    assert "unit_aspect" not in err[0]
    assert not (tmp_path / "out").exists()
