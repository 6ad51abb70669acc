"""Calibration: the swatch, the renderer's disappearance angles, and the bump-height fit."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.core.errors import CalibrationError
from illuknit.design.render.calibrate import (
    Measurement,
    calibration_swatch,
    disappearance_angle,
    fit_bump_height,
    measurements_template,
    parse_measurements,
    read_measurements,
)
from illuknit.design.render.params import RenderParams
from illuknit.design.render.raycast import heights_from_pattern, render_soft


def test_swatch_layout():
    sw = calibration_swatch(bump_sizes=(1, 2), flat_sizes=(1, 3), cell_width=4)
    cells = sw.meta["cells"]
    assert [(c["bump_rows"], c["flat_rows"]) for c in cells] == [(1, 1), (1, 3), (2, 1), (2, 3)]
    assert len(sw.yarns) == 2
    for c in cells:
        r0, r1 = c["rows"]
        c0, c1 = c["cols"]
        n, k = c["bump_rows"], c["flat_rows"]
        block_r = sw.raised[r0:r1, c0:c1]
        block_y = sw.yarn[r0:r1, c0:c1]
        assert block_r[:n].all() and block_r[n + k :].all() and not block_r[n : n + k].any()
        assert (block_y[n : n + k] == 1).all() and (block_y[:n] == 0).all()
    # Everything outside the cells is flat background in the bump yarn.
    assert int((sw.yarn == 1).sum()) == sum(c["flat_rows"] * 4 for c in cells)


@pytest.mark.parametrize("view", ["A", "B"])
def test_renderer_hides_flats_exactly_below_the_predicted_angle(view):
    params = RenderParams(flat_height=0.15, bump_height=0.8)
    sw = calibration_swatch(bump_sizes=(1, 2), flat_sizes=(1, 2, 3))
    h = heights_from_pattern(sw, params)
    black = (sw.yarn == 1).astype(float)
    for cell in sw.meta["cells"]:
        theta = disappearance_angle(cell["flat_rows"], params)
        c0, c1 = cell["cols"]
        r0, r1 = cell["rows"]
        below = render_soft(h, black, params=params, view=view, angle=theta - 0.2)[r0:r1, c0:c1]
        above = render_soft(h, black, params=params, view=view, angle=theta + 0.2)[r0:r1, c0:c1]
        assert below.max() < 1e-12
        assert above.max() > 1e-3


def _synthetic(relief, flats, *, noise=0.0, seed=0, unit_length=1.0):
    rng = np.random.default_rng(seed)
    return [
        Measurement(
            k,
            math.degrees(math.atan(relief / (k * unit_length))) + rng.normal(0, noise),
            b,
            line=i + 2,
        )
        for i, (b, k) in enumerate((b, k) for b in (1, 2) for k in flats)
    ]


@settings(max_examples=40, deadline=None)
@given(st.floats(0.05, 5.0), st.floats(0.02, 0.5), st.floats(0.3, 3.0))
def test_fit_recovers_a_known_bump_height(relief, flat, unit_length):
    base = RenderParams(flat_height=flat, bump_height=flat * 3, unit_length=unit_length)
    fit = fit_bump_height(_synthetic(relief, (1, 2, 3, 4), unit_length=unit_length), params=base)
    assert fit.params.bump_height == pytest.approx(flat + relief, rel=1e-6)
    assert fit.rms_deg < 1e-6
    assert fit.params.unit_length == unit_length and fit.params.theta == base.theta


def test_fit_with_noise_reports_residuals():
    fit = fit_bump_height(_synthetic(0.6, (1, 2, 3, 4), noise=0.5, seed=3))
    assert fit.relief == pytest.approx(0.6, rel=0.1)
    assert fit.rms_deg > 0 and fit.relief_stderr > 0
    np.testing.assert_allclose(
        fit.residual_deg, [m.angle_deg for m in fit.measurements] - fit.predicted_deg
    )
    text = fit.report()
    assert "rms residual" in text and "bump_rows 2" in text


def test_template_parses_and_skips_unmeasured_rows():
    sw = calibration_swatch(bump_sizes=(1,), flat_sizes=(1, 2))
    text = measurements_template(sw)
    ms, skipped = parse_measurements(text)
    assert ms == [] and skipped == 2
    lines = text.splitlines()
    lines[1] = lines[1].replace("1,1,,", "1,1,31,")
    lines[2] = lines[2].replace("1,2,,", "1,2,17.2,")
    ms, skipped = parse_measurements("\n".join(lines))
    assert [(m.flat_rows, m.angle_deg, m.bump_rows) for m in ms] == [(1, 31.0, 1), (2, 17.2, 1)]
    assert fit_bump_height(ms).relief == pytest.approx(0.6, rel=0.05)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "empty file"),
        ("flat_rows\n1\n", "missing column"),
        ("flat_rows,angle_deg,colour\n1,20,red\n", "unknown column"),
        ("flat_rows,angle_deg\nx,20\n", "line 2: `flat_rows`"),
        ("flat_rows,angle_deg\n0,20\n", "line 2: `flat_rows`"),
        ("flat_rows,angle_deg\n1,abc\n", "line 2: `angle_deg` must be a number"),
        ("flat_rows,angle_deg\n1,20\n2,90\n", "line 3: `angle_deg` must lie in"),
        ("flat_rows,angle_deg\n1,-5\n", "`angle_deg` must lie in"),
    ],
)
def test_bad_measurement_files(text, message):
    with pytest.raises(CalibrationError, match=message.replace("(", r"\(")):
        parse_measurements(text)


def test_measurements_that_cannot_determine_a_height():
    with pytest.raises(CalibrationError, match="at least two"):
        fit_bump_height([Measurement(1, 30.0)])
    with pytest.raises(CalibrationError, match="at least two"):
        fit_bump_height([])
    with pytest.raises(CalibrationError, match="all 3 measured angles are equal"):
        fit_bump_height([Measurement(k, 25.0) for k in (1, 2, 3)])


def test_read_measurements_file_errors(tmp_path):
    with pytest.raises(CalibrationError, match="not found"):
        read_measurements(tmp_path / "none.csv")
    (tmp_path / "m.csv").write_bytes(
        b"\xef\xbb\xbfflat_rows,angle_deg\n1,30\n2,16\n"
    )  # BOM from spreadsheets
    ms, _ = read_measurements(tmp_path / "m.csv")
    assert len(ms) == 2


def test_bad_swatch_options():
    with pytest.raises(CalibrationError, match="flat_sizes"):
        calibration_swatch(flat_sizes=())
    with pytest.raises(CalibrationError, match="bump_sizes"):
        calibration_swatch(bump_sizes=(1, 0))
    with pytest.raises(CalibrationError, match="two yarns"):
        calibration_swatch(yarns="white,black,red")
