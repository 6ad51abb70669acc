"""One float truth: the floats ``knit`` reports are the checker's, on every machine and mode.

``KnitResult.summary()``'s ``long_floats`` / ``longest_float`` / ``floats_at_limit``, the
checker's ``long-float`` warnings and its report's ``floats`` are all measured on the written program (:mod:`illuknit.knitout.floats`); these tests
hold random patterns, knitted on each preset with every scheduling switch, to that.
"""

from __future__ import annotations

import sys
import tempfile
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from illuknit.check import check_knitout
from illuknit.check.simulate import simulate_program
from illuknit.core.machine import MACHINES
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.knitout.floats import program_floats
from illuknit.knitout.parse import parse_knitout
from illuknit.knitting import knit_pattern

sys.path.insert(0, str(Path(__file__).parents[1] / "formats"))
from test_kc import assert_same_as_reference

YARNS = parse_yarns("#1b1b1b,#f4f0e8,#b3202a,#2030a0")

#: (catching, float_avoidance, path_planning, tuck_passes): the default and every switch
MODES = [
    (True, True, "anchor", False),
    ("plate", True, "anchor", False),
    ("plate", True, "split", True),
    (False, True, "anchor", False),
    (True, False, "anchor", False),
    (True, True, "none", False),
]


@st.composite
def patterns(draw):
    n = draw(st.integers(1, 4))
    m = draw(st.integers(2, 14))
    k = draw(st.integers(1, 4))
    cells = draw(st.lists(st.integers(0, k - 1), min_size=n * m, max_size=n * m))
    raised = draw(st.lists(st.booleans(), min_size=n * m, max_size=n * m))
    yarn = np.array(cells).reshape(n, m)
    return LogicalPattern(yarn, np.array(raised).reshape(n, m), YARNS[:k])


def assert_one_float_truth(result) -> None:
    """``result``'s reported floats equal the checker's, and its simulator's floats equal
    :func:`program_floats`'."""
    text = result.text
    limit = result.machine.float_limit
    sim = simulate_program(parse_knitout(text))
    assert sim.floats == program_floats(parse_knitout(text))
    report = check_knitout(text, machine=result.machine)
    warned = [f for f in report.findings if f.code == "long-float"]
    over = [f.length for f in sim.floats if f.length > limit]
    s = result.summary()
    assert s["long_floats"] == len(warned) == len(over)
    # the true longest float and the count at the limit, always (not only over the limit),
    # in one unit, the same in the summary and in the checker's report
    lengths = [f.length for f in sim.floats]
    assert s["longest_float"] == max(lengths, default=0) == report.floats["longest"]
    assert s["floats_at_limit"] == lengths.count(limit) == report.floats["at_limit"]
    assert s["float_unit"] == report.floats["unit"] == "needles skipped"
    assert report.floats["over_limit"] == len(over)
    assert [(f.from_needle, f.to_needle) for f in result.schedule.long_floats] == [
        (f.from_slot, f.to_slot) for f in sim.floats if f.length > limit
    ]


@pytest.mark.parametrize("machine", ["generic540", "swg091n2", "kniterate"])
@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(pattern=patterns(), mode=st.sampled_from(MODES), limit=st.sampled_from([3, 6, 20]))
def test_knit_reports_the_floats_the_checker_finds(machine, pattern, mode, limit):
    catching, avoidance, planning, tuck_passes = mode
    m = replace(MACHINES[machine], float_limit=limit)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # LongFloatWarning: kept on purpose here
        try:
            result = knit_pattern(
                pattern,
                machine=m,
                catching=catching,
                float_avoidance=avoidance,
                path_planning=planning,
                tuck_passes=tuck_passes,
                allow_long_floats=True,
            )
        except Exception as e:  # a refusal must be one of the documented ones
            from illuknit.core.errors import CarrierShortageError

            assert isinstance(e, CarrierShortageError), e
            return
    assert_one_float_truth(result)
    if not m.inserting_hook:  # and the reference Kniterate backend takes it as we convert it
        with tempfile.TemporaryDirectory() as tmp:
            assert assert_same_as_reference(result.text, Path(tmp)) is not None


def test_floats_at_the_limit_are_reported_with_the_longest_float(tmp_path):
    """Two yarns alternating in blocks wider than the float limit: every float sits exactly at
    the limit. Before, ``longest_float`` read 0 and nothing counted them; now ``knit``, the
    summary, the set-up sheet and ``check`` all say the longest float and how many sit at the
    limit, in needles skipped."""
    from click.testing import CliRunner

    from illuknit.cli import cli
    from illuknit.core.pattern import save_pattern

    yarn = np.tile(np.repeat([0, 1], 4), (2, 2))  # runs of 4 units = 8 needles
    pattern = LogicalPattern(yarn, np.zeros_like(yarn, bool), YARNS[:2])
    m = replace(MACHINES["generic540"], float_limit=8)
    result = knit_pattern(pattern, machine=m)
    s = result.summary()
    lengths = [f.length for f in program_floats(parse_knitout(result.text))]
    assert s["longest_float"] == max(lengths) == 8 and s["long_floats"] == 0
    assert s["floats_at_limit"] == lengths.count(8) > 0
    assert s["floats"].startswith("longest 8 needles skipped")
    save_pattern(pattern, tmp_path / "p.json")
    run = CliRunner().invoke(
        cli, ["knit", str(tmp_path / "p.json"), "-o", str(tmp_path / "p.k"), "--float-limit", "8"]
    )
    assert run.exit_code == 0, run.output
    assert f"floats: {s['floats']}" in run.output
    run = CliRunner().invoke(cli, ["check", str(tmp_path / "p.k"), "--float-limit", "8"])
    assert f"{s['floats_at_limit']} at the float limit of 8, 0 over it" in run.output
    assert "floats: longest 8 needles skipped" in run.output
