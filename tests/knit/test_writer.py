"""Knitout text: the header and syntax the SWG converter accepts, a golden file, the checker and
the PyPI simulator on every generated program."""

from __future__ import annotations

import os
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from illuknit.core.machine import MachineSpec
from illuknit.core.pattern import LogicalPattern, Yarn
from illuknit.knit.knitout import format_racking
from illuknit.knitting import knit_pattern

DATA = Path(__file__).parent / "data"
GOLDEN = DATA / "knit_tiny_single_view.k"
YARNS = (
    Yarn("Charcoal", (27, 27, 27)),
    Yarn("Off white", (244, 240, 232)),
    Yarn("Rust", (180, 70, 30)),
)


def tiny_pattern() -> LogicalPattern:
    """3 x 3 units, stripes of two yarns, a diagonal of bumps."""
    yarn = np.repeat((np.arange(3) % 2)[:, None], 3, axis=1)
    return LogicalPattern(yarn, np.eye(3, dtype=bool), YARNS[:2], {"name": "tiny"})


def stripes(n: int, m: int, k: int, raised: np.ndarray) -> LogicalPattern:
    yarn = np.repeat((np.arange(n) % k)[:, None], m, axis=1)
    return LogicalPattern(yarn, raised, YARNS[:k])


def vm_run(text: str) -> None:
    """Run the PyPI knitout-interpreter strictly: any violation raises, any warning fails.

    Its grammar is narrower than knitout: ``;;Width``/``;;Yarn`` headers are commented out first.
    """
    pytest.importorskip("knitout_interpreter")
    from knitout_interpreter.knitout_execution import Knitout_Executer
    from knitout_interpreter.knitout_language.Knitout_Parser import parse_knitout

    lines = [
        ("; " + ln[2:]) if ln.startswith((";;Width", ";;Yarn")) else ln for ln in text.splitlines()
    ]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        program = parse_knitout("\n".join(lines) + "\n", pattern_is_file=False)
        ex = Knitout_Executer(program)
    messages = [str(w.message) for w in caught if not issubclass(w.category, DeprecationWarning)]
    assert not messages, messages[:5]
    assert len(ex.carriage_passes) > 0
    assert ex.knitting_machine is not None


def check_clean(text: str, machine: MachineSpec) -> None:
    """Zero blocking findings from illuknit's own checker."""
    from illuknit.check import check_knitout

    report = check_knitout(
        text,
        float_limit=machine.float_limit,
        max_racking=machine.max_racking,
        bed_width=machine.needles,
    )
    assert not report.blocking, [f"{f.line}: {f.code} {f.message}" for f in report.blocking]
    assert report.pieces == 1


def test_header_is_exactly_what_the_swg_converter_wants():
    text = knit_pattern(tiny_pattern()).text
    lines = text.split("\n")
    assert lines[:6] == [
        ";!knitout-2",
        ";;Machine: SWG091N2",
        ";;Gauge: 7",
        ";;Width: 540",
        ";;Carriers: 1 2 3 4 5 6 7 8 9 10",
        ";;Position: Center",
    ]
    assert lines[6:8] == [";;Yarn-1: 50-50 Charcoal", ";;Yarn-2: 50-50 Off-white"]
    assert text.endswith("\n") and "\r" not in text and "\t" not in text


def test_every_line_is_well_formed_with_single_spaces():
    text = knit_pattern(stripes(4, 3, 3, np.ones((4, 3), bool))).text
    op = re.compile(
        r"^(?:(?:knit|tuck|miss) [+-] [fb]\d+ \d+"
        r"|xfer [fb]\d+ [fb]\d+|drop [fb]\d+|rack -?\d+(?:\.25|\.75)?"
        r"|(?:inhook|releasehook|outhook) \d+)$"
    )
    for ln in text.splitlines():
        if ln.startswith(";"):
            continue
        assert op.match(ln), ln
        assert "  " not in ln


def test_carriers_come_in_on_the_hook_start_leftward_at_the_right_edge_and_all_go_out():
    text = knit_pattern(stripes(5, 4, 3, np.zeros((5, 4), bool))).text
    ops = [ln.split() for ln in text.splitlines() if not ln.startswith(";")]
    right = max(int(t[2][1:]) for t in ops if t[0] == "knit")
    for c in ("1", "2", "3"):
        i = ops.index(["inhook", c])
        first = next(t for t in ops[i:] if t[0] in ("knit", "tuck") and t[-1] == c)
        assert first[1] == "-" and int(first[2][1:]) == right
        assert ops.index(["releasehook", c]) > i
        assert ["outhook", c] in ops
    assert ops[-1][0] == "drop"


def test_racking_is_written_as_integers_or_quarter_pitch():
    assert [format_racking(r) for r in (0, -1, 1.0, 0.25, -0.75)] == [
        "0",
        "-1",
        "1",
        "0.25",
        "-0.75",
    ]
    text = knit_pattern(tiny_pattern()).text
    racks = {ln for ln in text.splitlines() if ln.startswith("rack")}
    assert racks == {"rack -1", "rack 0"} or racks == {"rack 1", "rack 0"}


def test_golden_program_is_stable():
    text = knit_pattern(tiny_pattern()).text
    if os.environ.get("ILLUKNIT_REGEN_GOLDEN"):
        GOLDEN.write_text(text, encoding="utf-8")
    assert text == GOLDEN.read_text(encoding="utf-8")


def test_golden_program_is_clean_for_checker_and_simulator():
    text = GOLDEN.read_text(encoding="utf-8")
    check_clean(text, MachineSpec())
    vm_run(text)


@st.composite
def single_view(draw):
    n = draw(st.integers(1, 5))
    m = draw(st.integers(1, 4))
    k = draw(st.integers(1, 3))
    raised = np.array(draw(st.lists(st.booleans(), min_size=n * m, max_size=n * m))).reshape(n, m)
    return stripes(n, m, k, raised)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(single_view(), st.integers(0, 3))
def test_generated_programs_pass_the_checker_and_the_simulator(p, cast_on):
    m = MachineSpec()
    text = knit_pattern(p, machine=m, cast_on_courses=cast_on).text
    check_clean(text, m)
    vm_run(text)


def test_stitch_and_speed_numbers_are_written_when_set():
    m = MachineSpec(
        stitch_number=61, cast_on_stitch_number=40, speed_number=5, gauge=14, needles=100
    )
    text = knit_pattern(tiny_pattern(), machine=m).text
    lines = text.splitlines()
    assert ";;Gauge: 14" in lines and ";;Width: 100" in lines
    assert "x-speed-number 5" in lines
    assert lines.index("x-stitch-number 40") < lines.index("x-stitch-number 61")


@pytest.mark.parametrize("shape", ["heart", "plus"])
def test_single_view_compiler_output_knits_cleanly(shape):
    """The push-button single-view path end to end: drawing -> pattern -> knitout -> checks."""
    from illuknit.design import single_view
    from illuknit.pictures import drawings

    mask = drawings.draw_shape(shape, (10, 8))
    pattern = single_view.compile_single_view(mask.astype(int), yarns=YARNS[:2])
    m = MachineSpec()
    result = knit_pattern(pattern, machine=m)
    # The schedule meets its bound; the machine adds exactly its 4 hook passes, no kickbacks.
    assert result.schedule.stats.ratio == 1.0
    assert result.stats.passes == result.schedule.stats.passes + 4
    assert result.stats.kickbacks == 0
    check_clean(result.text, m)
    vm_run(result.text)
