"""The schedule IR speaks the knitout program's operation vocabulary."""

from __future__ import annotations

import pytest

import illuknit.knit.ir as ir
from illuknit.core.errors import SchedulingError
from illuknit.knit.ir import NEEDLE_OPS, Op
from illuknit.knitout.program import Bed, Opcode


def test_an_op_holds_the_program_opcode() -> None:
    op = Op("knit", "f", 3)
    assert op.op is Opcode.KNIT and op.bed is Bed.FRONT
    assert Op(Opcode.XFER, Bed.FRONT, 3, Bed.BACK, 3).op is Opcode.XFER
    assert {str(o) for o in NEEDLE_OPS} == {"knit", "tuck", "miss", "split", "xfer", "drop"}


def test_an_op_refuses_an_opcode_that_is_no_needle_operation() -> None:
    with pytest.raises(SchedulingError, match="operation must be one of"):
        Op("rack", "f", 3)
    with pytest.raises(SchedulingError, match="operation must be one of"):
        Op("purl", "f", 3)


def test_opkind_is_a_deprecated_name_of_opcode() -> None:
    with pytest.warns(DeprecationWarning, match="OpKind is deprecated"):
        assert ir.OpKind is Opcode
