"""Machine presets, lookup by name, and the machine a program's headers name."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from illuknit.check import check_knitout
from illuknit.core.errors import SchedulingError, UnknownNameError
from illuknit.core.machine import (
    DEFAULT_MACHINE,
    DEFAULT_MACHINE_NAME,
    MACHINES,
    MachineSpec,
    get_machine,
    machine_from_headers,
    machine_names,
)
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.knitout import parse_knitout
from illuknit.knitting import knit_pattern


def test_presets_are_the_default_bed_and_the_physical_swg091n2() -> None:
    assert (
        DEFAULT_MACHINE
        is MACHINES[DEFAULT_MACHINE_NAME]
        == MachineSpec(description=DEFAULT_MACHINE.description, backend="swg")
    )
    swg = get_machine("swg091n2")
    assert (swg.needles, swg.gauge, swg.name) == (252, 7.0, "SWG091N2")
    # 36 inches at 7 needles per inch, less the parking room on both sides
    assert swg.max_fabric_width == 247 and swg.max_units == 123
    assert get_machine("SWG091N2") is swg and get_machine(None) is DEFAULT_MACHINE
    assert get_machine(swg) is swg
    assert all(m.description for m in MACHINES.values())


def test_unknown_machine_lists_the_known_ones() -> None:
    with pytest.raises(UnknownNameError) as e:
        get_machine("knitmaster")
    assert "knitmaster" in str(e.value)
    assert all(name in str(e.value) for name in machine_names())


def test_check_units_refuses_a_pattern_wider_than_the_bed() -> None:
    swg = get_machine("swg091n2")
    swg.check_units(123)
    with pytest.raises(SchedulingError, match=r"124 units = 248 stitches .* at most 123 units"):
        swg.check_units(124)


@pytest.mark.parametrize("name", ["generic540", "swg091n2"])
def test_a_program_names_its_machine(name: str) -> None:
    """knit on a preset -> headers -> the same preset, and the checker judges by it."""
    yarns = parse_yarns("black,white")
    yarn = np.tile(np.arange(8) % 2, (6, 1))
    pattern = LogicalPattern(yarn, np.zeros(yarn.shape, bool), yarns)
    spec = get_machine(name)
    text = knit_pattern(pattern, machine=spec).program
    headers = {n: v for n, v, _ in parse_knitout(text).headers}
    assert machine_from_headers(headers) is spec
    report = check_knitout(text)
    assert report.ok and report.machine is not None
    assert report.machine["needles"] == spec.needles
    assert report.machine["float_limit"] == spec.float_limit


def test_headers_of_an_unknown_bed_keep_their_width_and_gauge() -> None:
    m = machine_from_headers({"Machine": "SWG091N2", "Width": "300", "Gauge": "12"})
    assert (m.needles, m.gauge, m.float_limit) == (300, 12.0, DEFAULT_MACHINE.float_limit)
    assert machine_from_headers({}) is DEFAULT_MACHINE
    assert machine_from_headers({"Width": "wide", "Gauge": "-1"}) is DEFAULT_MACHINE


def test_checker_float_limit_is_the_machines() -> None:
    """One float limit: the checker's long-float warnings follow the machine, not a constant."""
    head = ";!knitout-2\n;;Machine: SWG091N2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\n"
    body = ["inhook 3", "tuck + f0 3", "tuck + f15 3", "releasehook 3", "knit - f15 3"]
    body += ["knit - f0 3", "outhook 3", "drop f0", "drop f15"]
    text = head + "\n".join(body) + "\n"

    def long_floats(**kw: object) -> int:
        return check_knitout(text, **kw).codes()["long-float"]  # type: ignore[arg-type]

    assert long_floats() == 0  # 14 needles: within the default machine's 20
    assert long_floats(machine=replace(DEFAULT_MACHINE, float_limit=10)) > 0
    assert long_floats(float_limit=10) > 0


def test_shima_transfer_speed_switches_around_transfer_passes_and_the_dat_is_the_backends(
    swg_backend,
) -> None:
    import sys
    from pathlib import Path

    from illuknit.core.errors import OptionError
    from illuknit.core.machine import TransferSettings
    from illuknit.formats.dat import knitout_to_dat

    sys.path.insert(0, str(Path(__file__).parents[1] / "formats"))
    from reference import reference_dat

    rng = np.random.default_rng(5)
    shape = (6, 8)
    pattern = LogicalPattern(
        np.repeat(rng.integers(0, 2, size=(shape[0], 1)), shape[1], axis=1),
        rng.random(shape) < 0.4,
        parse_yarns("#1b1b1b,#f4f0e8"),
    )
    m = replace(DEFAULT_MACHINE, speed_number=5, transfer=TransferSettings(speed_number=2))
    text = knit_pattern(pattern, machine=m).text
    speed, seen = None, set()
    for line in text.splitlines():
        if line.startswith("x-speed-number"):
            speed = int(line.split()[1])
        elif line.startswith(("xfer ", "knit ", "tuck ")):
            seen.add((line.split()[0], speed))
    assert seen == {("xfer", 2), ("knit", 5), ("tuck", 5)}
    assert knitout_to_dat(text) == reference_dat(text, swg_backend)
    # the SWG backend has no transfer-stitch or roller extension: refused, not silently dropped
    with pytest.raises(OptionError, match="transfer stitch"):
        replace(DEFAULT_MACHINE, transfer=TransferSettings(stitch_number=2))
    with pytest.raises(OptionError, match="roller"):
        replace(DEFAULT_MACHINE, transfer=TransferSettings(roller_advance=20))


def test_every_preset_names_its_backend_and_a_spec_without_one_is_read_from_its_carriers():
    from illuknit.core.errors import OptionError
    from illuknit.core.machine import MACHINES, MachineSpec

    assert {k: m.backend for k, m in MACHINES.items()} == {
        "generic540": "swg",
        "swg091n2": "swg",
        "kniterate": "kniterate",
    }
    assert MachineSpec().backend is None and MachineSpec().runs_on() == "swg"
    assert MachineSpec(carriers=("1", "2", "3")).runs_on() is None
    with pytest.raises(OptionError, match="Shima carriers"):
        MachineSpec(carriers=("1", "2", "3"), backend="swg")
    with pytest.raises(OptionError, match="backend"):
        MachineSpec(backend="brother")
