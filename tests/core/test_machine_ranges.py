"""One table of machine value ranges: the library, the CLI, the writers and ``check`` all use it."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from illuknit.check import check_knitout
from illuknit.core.errors import KcodeError, MachineValueError, OptionError, UnsupportedKnitoutError
from illuknit.core.machine import (
    DEFAULT_MACHINE,
    KNITERATE,
    MACHINES,
    MachineSpec,
    TransferSettings,
)
from illuknit.core.machine_ranges import (
    MACHINE_RANGES,
    PARAMETERS,
    check_machine_value,
    machine_value_problem,
    ranges_markdown,
)
from illuknit.core.pattern import LogicalPattern, parse_yarns, save_pattern
from illuknit.formats import knitout_to_format

CASES = [(b, name) for b, table in MACHINE_RANGES.items() for name in table]


def test_every_range_names_its_parameter_and_a_source() -> None:
    for backend, name in CASES:
        r = MACHINE_RANGES[backend][name]
        assert name in PARAMETERS and r.low <= r.high and r.source
        # a range is the backend's own, a manual's as our docs cite it, or said to be ours
        assert any(k in r.source for k in (".js", "knit.work", "our own conservative bound"))


@given(case=st.sampled_from(CASES), data=st.data())
def test_in_range_is_taken_and_out_of_range_is_refused_naming_range_and_source(case, data):
    backend, name = case
    r = MACHINE_RANGES[backend][name]
    inside = data.draw(st.integers(math.ceil(r.low), int(r.high)))
    assert check_machine_value(name, inside, backend=backend) == inside
    outside = data.draw(
        st.one_of(
            st.integers(max_value=int(r.low) - 1),
            st.integers(min_value=int(r.high) + 1),
            st.sampled_from([math.nan, math.inf, -math.inf, 10**30, 1e20, "5", None, True]),
        )
    )
    with pytest.raises(MachineValueError) as e:
        check_machine_value(name, outside, backend=backend)
    message = str(e.value)
    assert f"`{name}`" in message and r.text() in message and r.source in message
    assert "\n" not in message and len(message) < 400
    assert (e.value.parameter, e.value.low, e.value.high) == (name, r.low, r.high)


def test_presets_are_within_their_ranges() -> None:
    for spec in MACHINES.values():
        for name, value in (
            ("needles", spec.needles),
            ("gauge", spec.gauge),
            ("stitch_number", spec.stitch_number),
            ("speed_number", spec.speed_number),
        ):
            if value is not None:
                assert machine_value_problem(name, value, backend=spec.runs_on()) is None


@pytest.mark.parametrize(
    "make",
    [
        lambda: DEFAULT_MACHINE.with_width(10**24),
        lambda: DEFAULT_MACHINE.with_gauge(1e20),
        lambda: replace(DEFAULT_MACHINE, speed_number=16),
        lambda: replace(DEFAULT_MACHINE, stitch_number=256),
        lambda: replace(DEFAULT_MACHINE, transfer=TransferSettings(speed_number=16)),
        lambda: replace(KNITERATE, transfer=replace(KNITERATE.transfer, roller_advance=10**29)),
        lambda: replace(KNITERATE, transfer=replace(KNITERATE.transfer, speed_number=601)),
        lambda: KNITERATE.with_width(253),
        lambda: TransferSettings(speed_number=10**30),
        lambda: MachineSpec(max_racking=9),
    ],
)
def test_library_refuses_a_machine_value_out_of_range(make) -> None:
    with pytest.raises(MachineValueError):
        make()


def test_library_refuses_a_gauge_that_is_no_number() -> None:
    with pytest.raises(OptionError, match=r"`gauge` must be (a number|an int or a float)"):
        MachineSpec(gauge=None)  # type: ignore[arg-type]


HEAD = (
    ";!knitout-2\n;;Machine: SWG091N2\n;;Gauge: 7\n;;Width: 540\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\n"
)
BODY = "inhook 3\ntuck - f5 3\ntuck - f3 3\ntuck - f1 3\n{x}knit + f1 3\nknit + f3 3\nknit + f5 3\n"


@pytest.mark.parametrize(
    "head, x",
    [
        (HEAD, "x-stitch-number nan\n"),
        (HEAD, "x-stitch-number -5\n"),
        (HEAD, "x-speed-number 1e20\n"),
        (HEAD, "x-speed-number 16\n"),
        (HEAD.replace("Width: 540", "Width: 1000000000000"), ""),
        (HEAD.replace("Gauge: 7", "Gauge: 100000"), ""),
    ],
)
def test_check_blocks_a_machine_value_out_of_range(head, x) -> None:
    report = check_knitout(head + BODY.format(x=x))
    codes = [f.code for f in report.blocking]
    assert "machine-value" in codes, report.to_text()
    assert report.machine["needles"] == 540  # an absurd ;;Width is not taken as the bed
    # a value in range is no finding
    ok = check_knitout(HEAD + BODY.format(x="x-speed-number 15\nx-stitch-number 90\n"))
    assert "machine-value" not in [f.code for f in ok.findings]


@pytest.mark.parametrize("x", ["x-speed-number 16\n", "x-stitch-number 256\n"])
def test_dat_writer_refuses_a_value_out_of_range(x) -> None:
    with pytest.raises(UnsupportedKnitoutError, match="must be a whole number in"):
        knitout_to_format(HEAD + BODY.format(x=x) + "outhook 3\n", "dat", name="p.dat")


KC_HEAD = ";!knitout-2\n;;Carriers: 1 2 3 4 5 6\n"
KC_BODY = "in 3\ntuck - f5 3\ntuck - f3 3\n{x}knit + f3 3\nknit + f5 3\nout 3\n"


@pytest.mark.parametrize(
    "head, x",
    [
        (KC_HEAD, "x-speed-number 100000000000000000000\n"),
        (KC_HEAD, "x-roller-advance 100000000000000000000000000000\n"),
        (KC_HEAD, "x-add-roller-advance 5000\n"),
        (KC_HEAD + ";;Width: 1000000000000\n", ""),
    ],
)
def test_kc_writer_refuses_a_value_out_of_range(head, x) -> None:
    with pytest.raises(KcodeError, match="must be a"):
        knitout_to_format(head + KC_BODY.format(x=x), "kc", name="p.kc")


@pytest.fixture
def pattern_file(tmp_path: Path) -> Path:
    yarn = np.tile(np.arange(8) % 2, (6, 1))
    pattern = LogicalPattern(yarn, np.zeros(yarn.shape, bool), parse_yarns("black,white"))
    path = tmp_path / "p.json"
    save_pattern(pattern, path)
    return path


@pytest.mark.parametrize(
    "args, parameter",
    [
        (["--xfer-speed", "1" * 30], "transfer_speed_number"),
        (["--machine", "kniterate", "--xfer-roller", "9" * 30], "roller_advance"),
        (["--machine", "kniterate", "--xfer-speed", "601"], "transfer_speed_number"),
        (["--xfer-speed", "16"], "transfer_speed_number"),
        (["--machine-width", "1" * 25], "needles"),
        (["--gauge", "1e20"], "gauge"),
    ],
)
def test_cli_refuses_a_machine_value_out_of_range_in_one_line(
    args, parameter, pattern_file, tmp_path, run_cli
) -> None:
    out = tmp_path / "out.k"
    code, _, err = run_cli(["knit", pattern_file, "-o", out, *args])
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err
    # the range table's message, or click's own for an option with a parse-time range (--gauge)
    named = f"`{parameter}`" in err or f"'--{parameter}'" in err
    assert named and " in " in err
    assert not out.exists() and not (tmp_path / "out.kc").exists()


def test_docs_show_the_table() -> None:
    docs = (Path(__file__).parents[2] / "docs" / "knitting.md").read_text()
    assert ranges_markdown() in docs


def test_kniterate_stitch_numbers_over_9_are_written_as_letters() -> None:
    from illuknit.formats.kc import knitout_to_kc
    from illuknit.knitting import knit_pattern

    yarn = np.tile(np.arange(8) % 2, (4, 1))
    pattern = LogicalPattern(yarn, np.zeros(yarn.shape, bool), parse_yarns("black,white"))
    result = knit_pattern(pattern, machine=replace(KNITERATE, stitch_number=12))
    assert "x-stitch-number C\n" in result.text and "x-stitch-number 12" not in result.text
    knitout_to_kc(result.text, name="p.kc")  # the backend's grammar: 0-9 or A-Z


def test_check_refuses_a_bed_width_out_of_range(tmp_path, run_cli) -> None:
    with pytest.raises(MachineValueError, match="`needles`"):
        check_knitout(HEAD + BODY.format(x=""), bed_width=10**24)
    (tmp_path / "p.k").write_text(HEAD + BODY.format(x=""))
    code, _, err = run_cli(["check", tmp_path / "p.k", "--bed-width", "1" * 25])
    assert code == 2 and err.count("\n") == 1 and "8..2000" in err
