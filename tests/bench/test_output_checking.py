"""The solver's output is read as strictly as the MaxSAT Evaluation reads it: a v-line of the
wrong length, a variable in both polarities, a second v-line or a literal out of range is an
error with the reason, never an accepted answer."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from illuknit.core.errors import SolverError
from illuknit.solvers.wcnf import parse_maxsat_output

NV = 6


def test_a_well_formed_answer_is_read():
    status, cost, values = parse_maxsat_output("o 3\ns OPTIMUM FOUND\nv 101100\n", NV)
    assert status == "OPTIMUM FOUND" and cost == 3
    assert values is not None and values[1:].tolist() == [True, False, True, True, False, False]
    _, _, lits = parse_maxsat_output("v 1 -2 3\nv 4 -5 -6 0\n", NV)  # continued, then closed
    assert lits is not None and np.array_equal(lits, values)


@pytest.mark.parametrize(
    ("text", "why"),
    [
        ("v 10110\n", "5 values for 6 variables"),
        ("v 10110011111\n", "11 values for 6 variables"),
        ("v 101100\nv 101100\n", "a second 'v' line"),
        ("v 1 -2 3 4 -5 -6 0\nv 1 2 3 4 5 6 0\n", "a second 'v' line"),
        ("v 1 -2 3 4 -5 7 0\n", "literal 7 out of range 1..6"),
        ("v 1 -2 3 -1 -5 -6 0\n", "variable 1 in both polarities"),
        ("v x y z\n", "not a binary string nor literals"),
    ],
)
def test_a_malformed_v_line_is_an_error_naming_the_fault(text, why):
    with pytest.raises(SolverError, match="malformed 'v' line") as e:
        parse_maxsat_output("s OPTIMUM FOUND\n" + text, NV)
    assert why in str(e.value)


@given(st.text(alphabet="01", min_size=2, max_size=12))
def test_a_binary_string_is_accepted_exactly_when_its_length_is_the_variable_count(bits):
    if len(bits) == NV:
        values = parse_maxsat_output(f"v {bits}\n", NV)[2]
        assert values is not None and "".join("01"[int(b)] for b in values[1:]) == bits
    else:
        with pytest.raises(SolverError, match=f"{len(bits)} values for {NV} variables"):
            parse_maxsat_output(f"v {bits}\n", NV)
