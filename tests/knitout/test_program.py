"""The program as data: what the scheduler's lowering returns is what its text parses to, every
reader takes it as it is, and ``knit_pattern`` parses no text."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from illuknit.check import check_knitout
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.formats.kc import knitout_to_kc, knitout_to_kc_code
from illuknit.formats.swg_passes import machine_passes
from illuknit.knit.knitout import lower_to_knitout, step_operations, write_knitout
from illuknit.knitout import parse
from illuknit.knitout.floats import is_long_float
from illuknit.knitout.program import Bed, Direction, Opcode, format_knitout
from illuknit.knitting import knit_pattern
from illuknit.knitting.carriage import kc_run

YARNS = parse_yarns("#1b1b1b,#f4f0e8,#cc2222")


def _pattern(seed: int = 0, rows: int = 8, cols: int = 10) -> LogicalPattern:
    rng = np.random.default_rng(seed)
    yarn = rng.integers(0, 3, (rows, cols))
    raised = rng.random((rows, cols)) < 0.4
    upper = np.where(raised & (rng.random((rows, cols)) < 0.5), (yarn + 1) % 3, yarn)
    return LogicalPattern(yarn, raised, YARNS, upper=upper)


@pytest.fixture(scope="module", params=["generic540", "kniterate"])
def result(request: pytest.FixtureRequest):  # type: ignore[no-untyped-def]
    return knit_pattern(_pattern(), machine=request.param, allow_long_floats=True)


def test_the_program_formats_to_its_text_and_its_text_parses_back_to_it(result) -> None:  # type: ignore[no-untyped-def]
    program = result.knitout
    text = format_knitout(program)
    assert text == result.text
    parsed = parse.parse_knitout(text)
    assert parsed == program  # operations, header, lines (provenance is not compared)
    assert parsed.comments == program.comments
    assert format_knitout(parsed) == text
    assert result.summary()["lines"] == text.count("\n")


def test_the_vocabulary_is_typed(result) -> None:  # type: ignore[no-untyped-def]
    for op in result.knitout.operations:
        assert isinstance(op.op, Opcode) or op.op.startswith("x-")
        assert op.direction is None or isinstance(op.direction, Direction)
        assert all(isinstance(n.bed, Bed) and isinstance(n.index, int) for n in op.needles)
        assert isinstance(op.carriers, tuple)


def test_each_operation_names_the_schedule_step_it_came_from(result) -> None:  # type: ignore[no-untyped-def]
    steps = result.schedule.steps
    made = [op for op in result.knitout.operations if op.step is not None]
    assert len(made) == sum(len(step_operations(s)) for s in steps)
    for op in made:
        assert op in [o.at(op.line, op.step) for o in step_operations(steps[op.step])]
    by_step = [op.step for op in made]
    assert by_step == sorted(by_step)
    if not result.machine.inserting_hook:  # the waste section comes from no step
        first = made[0].line
        assert any(op.line < first and op.op == "tuck" for op in result.knitout.operations)


def test_write_knitout_is_the_lowering_formatted() -> None:
    result = knit_pattern(_pattern(1), allow_long_floats=True)
    schedule = result.schedule
    assert write_knitout(schedule) == format_knitout(lower_to_knitout(schedule))


def test_knit_pattern_parses_no_text(monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(text: str) -> None:
        raise AssertionError("knit_pattern parsed text")

    original = parse.parse_knitout
    for module in list(sys.modules.values()):  # every binding, from-imports included
        named = getattr(module, "__name__", "").startswith("illuknit")
        if named and getattr(module, "parse_knitout", None) is original:
            monkeypatch.setattr(module, "parse_knitout", refuse)
    for machine in ("generic540", "kniterate"):
        result = knit_pattern(_pattern(2), machine=machine, allow_long_floats=True)
        result.summary()  # the machine's passes, the .kc and its passes included


def test_readers_give_the_same_answer_on_the_program_and_on_its_text(result) -> None:  # type: ignore[no-untyped-def]
    program, text = result.knitout, result.text
    a, b = check_knitout(program), check_knitout(text)
    assert a.to_json() == b.to_json()
    if result.machine.inserting_hook:
        assert machine_passes(program) == machine_passes(text)
    else:
        code = knitout_to_kc_code(program, name="x.kc")
        assert code.text == knitout_to_kc(text, name="x.kc")
        assert kc_run(code) == kc_run(code.text)  # the rows it wrote = the rows read back


def test_one_rule_for_a_long_float() -> None:
    assert not is_long_float(20, 20)
    assert is_long_float(21, 20)


def test_the_float_measure_keeps_its_old_path_for_a_release() -> None:
    import illuknit.check.floats as old
    from illuknit.knitout import floats

    with pytest.warns(DeprecationWarning, match="moved to illuknit.knitout.floats"):
        assert old.program_floats is floats.program_floats
    with pytest.raises(AttributeError):
        _ = old.no_such_name
