"""The SWG pass model: pass counts (and kinds) against the reference backend, and its rules."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from illuknit.core.errors import MachineRuleError, UnsupportedKnitoutError
from illuknit.formats import MachinePassKind, machine_passes
from illuknit.formats.swg_ir import CarriageDirection
from tests.formats.reference import (
    GENERATED,
    generated_programs,
    reference_pass_count,
)

HEAD = ";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\n"


def prog(body: str) -> str:
    return HEAD + "\n".join(line.strip() for line in body.strip().splitlines()) + "\n"


def kinds(text: str) -> list[str]:
    return [p.kind.value for p in machine_passes(text)]


def test_same_direction_rows_cost_a_kickback():
    text = prog("""
        in 3
        knit + f1 3
        knit + f2 3
        knit + f1 3
        knit + f2 3
        out 3
    """)
    # second rightward row: the carrier may have stopped anywhere right of f2 -> kick it back left
    assert kinds(text) == ["knit", "kickback", "knit"]
    assert [p.direction for p in machine_passes(text)] == [
        CarriageDirection.RIGHT,
        CarriageDirection.LEFT,
        CarriageDirection.RIGHT,
    ]


def test_hook_release_is_its_own_pass_after_a_carriage_move():
    text = prog("""
        inhook 3
        knit - f2 3
        knit - f1 3
        releasehook 3
        knit + f1 3
        knit + f2 3
        outhook 3
    """)
    passes = machine_passes(text)
    assert kinds(text) == ["knit", "carriage-move", "hook-release", "knit"]
    assert passes[0].hook is not None and passes[0].hook.value == "hook-in"
    assert passes[-1].hook is not None and passes[-1].hook.value == "hook-out"


def test_other_carrier_in_the_way_is_moved():
    text = prog("""
        in 3
        knit + f1 3
        knit + f2 3
        in 4
        knit - f5 4
        knit - f4 4
        knit - f3 4
        knit - f2 4
        knit - f1 4
        out 3
        out 4
    """)
    # carrier 3 hangs right of f2: before carrier 4 knits f2 it is kicked right
    assert MachinePassKind.KICKBACK in {p.kind for p in machine_passes(text)}


def test_transfers_merge_undirected_and_keep_their_racking():
    text = prog("""
        in 3
        knit + f1 3
        knit + f2 3
        xfer f1 b1
        xfer f2 b2
        rack 1
        xfer b1 f2
        rack 0
        out 3
    """)
    passes = machine_passes(text)
    xfers = [p for p in passes if p.kind is MachinePassKind.TRANSFER]
    assert [len(p.slots) for p in xfers] == [2, 1]
    assert [p.racking for p in xfers] == [0.0, 1.0]
    assert xfers[1].slots[0][0] == 2  # back needle 1 sits in slot 1 + floor(1)


@pytest.mark.parametrize(
    ("body", "error", "match"),
    [
        ("in 3\nknit + f1 3\n", MachineRuleError, "taken out"),
        ("knit + f1 3\n", MachineRuleError, "not active"),
        ("in 3\nknit + f1 3\nxfer f1 b2\nout 3\n", MachineRuleError, "not aligned"),
        ("in 3\nknit + f1 3\nrack 0.5\nout 3\n", MachineRuleError, "0.25"),
        ("in 3\nknit + f1 3\nx-foo 1\nout 3\n", UnsupportedKnitoutError, "x-foo"),
        ("in 3\nknit + f1 3\nsplit + f1 bs1 3\nout 3\n", UnsupportedKnitoutError, "slider"),
        ("in 3 4\nknit + f1 3\nout 3 4\n", MachineRuleError, "does not match"),
        ("in 3\nsplit + f1 b1 3\nout 3\n", UnsupportedKnitoutError, "knit or tuck"),
        ("inhook 3\nknit + f1 3\nout 3\n", MachineRuleError, "releasehook"),
        # the reference writes this file but asserts KnitPaint will refuse it
        (
            "inhook 3\nknit - f2 3\nknit - f1 3\nxfer f1 b1\nreleasehook 3\nouthook 3\n",
            MachineRuleError,
            "carriage move",
        ),
    ],
)
def test_refused_programs_name_their_fault(body, error, match):
    with pytest.raises(error, match=match):
        machine_passes(prog(body))


def test_wrong_carriers_header_is_refused():
    with pytest.raises(MachineRuleError, match="Carriers"):
        machine_passes(";!knitout-2\n;;Carriers: 1 2 3 4 5 6\nin 3\nknit + f1 3\nout 3\n")


@pytest.mark.parametrize("name", GENERATED)
def test_pass_count_matches_reference(name, swg_backend):
    text = generated_programs()[name]
    assert len(machine_passes(text)) == reference_pass_count(text, swg_backend)


@st.composite
def small_patterns(draw):
    from illuknit.core.pattern import LogicalPattern, parse_yarns

    k = draw(st.integers(1, 4))
    h, w = draw(st.integers(1, 5)), draw(st.integers(1, 6))
    flat = draw(st.lists(st.integers(0, k - 1), min_size=h * w, max_size=h * w))
    bumps = draw(st.lists(st.booleans(), min_size=h * w, max_size=h * w))
    yarns = parse_yarns("#1b1b1b,#f4f0e8,#c03030,#3050c0")[:k]
    return LogicalPattern(
        np.array(flat, dtype=np.int16).reshape(h, w), np.array(bumps).reshape(h, w), yarns
    )


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(pattern=small_patterns(), cast_on=st.integers(0, 2))
def test_random_patterns_match_reference(swg_backend, pattern, cast_on):
    from illuknit.knitting import knit_pattern

    text = knit_pattern(pattern, cast_on_courses=cast_on).text
    passes = machine_passes(text)
    assert len(passes) == reference_pass_count(text, swg_backend)
    assert all(p.carriers or p.kind is not MachinePassKind.KNIT for p in passes)
