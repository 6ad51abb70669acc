"""Shima .dat writer and reader: byte-identical to the reference backend, and readable back."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from illuknit.core.errors import DatFormatError, MachineRuleError, UnsupportedKnitoutError
from illuknit.formats.dat import decode_dat, encode_dat, knitout_to_dat, read_dat
from illuknit.formats.dat_rows import decode_carriers
from illuknit.formats.swg_ir import PassType
from illuknit.formats.swg_passes import machine_passes
from tests.formats.reference import GENERATED, generated_programs, reference_dat

DATA = Path(__file__).parent / "data"
#: hand-written edge cases both writers accept: kickbacks of several carriers, plated pairs with
#: carrier 10, quarter-pitch and negative racking, x-stitch-number / x-speed-number / stitch,
#: drop, amiss, pause, sliders, split, presser modes, Position Keep/Left/Right, 255-needle runs
ACCEPTED = ["kicks", "plating", "racking", "sliders", "run255", "rack9ok"]
#: edge cases we refuse: (file, error, what the reference does)
REFUSED = {
    "negkeep": (MachineRuleError, "refuses too"),
    "rack9": (MachineRuleError, "refuses too"),
    "three": (UnsupportedKnitoutError, "crashes"),
    "stitch300": (UnsupportedKnitoutError, "writes 300 mod 256"),
    "ext": (UnsupportedKnitoutError, "ignores the extension"),
    "toowide": (MachineRuleError, "writes a negative bed position"),
}


def edge(name: str) -> str:
    return (DATA / f"edge_{name}.k").read_text()


@pytest.mark.parametrize("name", GENERATED)
def test_generated_programs_are_byte_identical(name, swg_backend):
    text = generated_programs()[name]
    assert knitout_to_dat(text) == reference_dat(text, swg_backend)


@pytest.mark.parametrize("name", ACCEPTED)
def test_edge_cases_are_byte_identical(name, swg_backend):
    text = edge(name)
    ref = reference_dat(text, swg_backend)
    assert ref is not None
    assert knitout_to_dat(text) == ref


@pytest.mark.parametrize("name", sorted(REFUSED))
def test_refused_edge_cases_raise_a_named_error(name):
    error, _ = REFUSED[name]
    with pytest.raises(error):
        knitout_to_dat(edge(name))


@pytest.mark.parametrize("name", [*ACCEPTED, "clean_intarsia_plated"])
def test_read_dat_gives_back_the_passes(name):
    text = edge(name) if name in ACCEPTED else generated_programs()[name]
    passes = machine_passes(text)
    dat = read_dat(knitout_to_dat(text))
    assert len(dat.passes) == len(passes)
    lo = min(s for p in passes for s, _ in p.slots)
    for mine, row in zip(passes, dat.passes, strict=True):
        assert row.kind is mine.kind or (
            mine.type is PassType.KNIT_TUCK and row.kind.value == "kickback"
        )
        assert (row.carriage, row.carriage_move) == (mine.carriage, mine.carriage_move)
        assert (row.racking, row.stitch, row.speed) == (mine.racking, mine.stitch, mine.speed)
        assert (row.hook, row.gripper, row.pause) == (mine.hook, mine.gripper, mine.pause)
        assert row.carriers == mine.carriers or "10" in mine.carriers
        assert row.slots == tuple((s - lo, op.color) for s, op in mine.slots)


def test_read_dat_decodes_a_plated_pair_with_carrier_10():
    dat = read_dat(knitout_to_dat(edge("plating")))
    # pairs knit together; carriers in the way are kicked one by one
    pairs = {p.carriers for p in dat.passes if p.kind.value == "knit"}
    assert pairs == {("1", "3"), ("5", "2")}  # (10, 3) is written 13, like (1, 3)
    assert ("10",) in {p.carriers for p in dat.passes if p.kind.value == "kickback"}
    assert decode_carriers(110) == ("1", "10") and decode_carriers(40) == ("4", "10")


@pytest.mark.parametrize(
    "data",
    [b"", b"\x00" * 100, b"GIF89a" + b"\x00" * 2000],
)
def test_read_dat_refuses_what_is_not_a_dat(data):
    with pytest.raises(DatFormatError):
        read_dat(data)


def test_read_dat_refuses_truncated_runs():
    data = knitout_to_dat(edge("kicks"))
    with pytest.raises(DatFormatError, match="runs cover"):
        read_dat(data[:-4])


@settings(max_examples=60, deadline=None)
@given(
    rows=st.integers(1, 4),
    runs=st.lists(st.tuples(st.integers(0, 3), st.integers(1, 600)), min_size=1, max_size=6),
)
def test_run_length_encoding_round_trips(rows, runs):
    row = np.concatenate([np.full(n, c, dtype=np.uint8) for c, n in runs])
    raster = np.tile(row, (rows, 1))
    assert np.array_equal(decode_dat(encode_dat(raster)), raster)
