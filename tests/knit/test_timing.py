"""The knitting-time model: carriage speeds, its range, the bind-off apart, and calibration from
one timed knit (library, machine file and ``illuknit calibrate time``)."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from illuknit.core.errors import CalibrationError, OptionError
from illuknit.core.machine import (
    KNITERATE,
    SWG_TIMING,
    CarriageTiming,
    get_machine,
    load_machine_file,
    save_machine_file,
)
from illuknit.core.pattern import LogicalPattern, parse_yarns, save_pattern
from illuknit.knit.timing import MachineRun, calibrate_timing, run_seconds
from illuknit.knitting import knit_pattern
from illuknit.knitting.stats import calibrate_knit_time, program_run

SHIMA = get_machine("generic540")


def tiny() -> LogicalPattern:
    return LogicalPattern(
        np.array([[0, 1, 0], [1, 0, 1]]),
        np.array([[True, False, False], [False, True, False]]),
        parse_yarns("red,white"),
    )


def test_a_pass_is_travel_at_the_carriage_speed_plus_the_overhead() -> None:
    t = CarriageTiming(knit_speed=1.0, transfer_speed=0.5, overrun_m=0.3, pass_overhead_s=2.0)
    pitch = 0.0254 / 7
    assert t.pass_seconds(100, transfer=False, pitch_m=pitch) == pytest.approx(
        (100 * pitch + 0.3) / 1.0 + 2.0
    )
    # transfers run slower; a wider pass takes longer
    assert t.pass_seconds(100, transfer=True, pitch_m=pitch) > t.pass_seconds(
        100, transfer=False, pitch_m=pitch
    )
    assert t.pass_seconds(200, transfer=False, pitch_m=pitch) > t.pass_seconds(
        100, transfer=False, pitch_m=pitch
    )
    for n, x in ((0, False), (50, True), (540, False)):
        fast, nominal, slow = (
            SWG_TIMING.pass_seconds(n, transfer=x, pitch_m=pitch, end=e)
            for e in ("fast", "", "slow")
        )
        assert fast <= nominal <= slow
    with pytest.raises(OptionError):
        CarriageTiming(knit_speed=0, transfer_speed=0.5, overrun_m=0.3, pass_overhead_s=1)
    with pytest.raises(OptionError):
        replace(SHIMA, seconds_per_needle=0.01)  # a linear model needs both of its values


def test_the_estimate_has_a_range_and_the_bind_off_apart() -> None:
    r = knit_pattern(tiny())
    t = r.time
    assert t.low_seconds < t.seconds < t.high_seconds
    assert 0 < t.bind_off_seconds < t.seconds
    assert t.transfer_passes > 0 and t.passes == r.stats.passes
    s = r.summary()
    assert s["time_range_seconds"] == [round(t.low_seconds, 1), round(t.high_seconds, 1)]
    assert "m/s" in s["time_model"]


def test_calibrating_on_a_timed_knit_reproduces_it_and_persists() -> None:
    run = MachineRun({"knit": 3}, (100, 40, 0), (False, True, False))
    fit = calibrate_timing(run, 600.0, SHIMA, what="swatch")
    assert run_seconds(run, fit.machine) == pytest.approx(600.0, abs=0.01)
    assert fit.machine.timing.calibrated_from.startswith("swatch: 10 min")
    assert fit.travel_seconds < 600.0 and "a pass" in fit.report()
    with pytest.raises(CalibrationError, match="shorter than the carriage travel"):
        calibrate_timing(run, 1.0, SHIMA)
    with pytest.raises(CalibrationError):
        calibrate_timing(run, 0.0, SHIMA)


def test_a_machine_file_carries_the_calibration(tmp_path) -> None:
    fit = calibrate_knit_time(tiny(), 15.0, machine="kniterate")
    path = save_machine_file(fit.machine, tmp_path / "mine.json", base="kniterate")
    back = get_machine(str(path))
    assert back == load_machine_file(path)
    assert back.timing == fit.machine.timing and back.name == KNITERATE.name
    assert back.needles == KNITERATE.needles and back.formats == ("kc",)
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"kind": "illuknit-machine", "base": "generic540", "timing": 3}))
    with pytest.raises(OptionError, match="timing"):
        get_machine(str(bad))
    with pytest.raises(OptionError, match="not found"):
        get_machine(str(tmp_path / "missing.json"))


def test_kniterate_transfer_passes_run_at_their_own_slower_speed() -> None:
    r = knit_pattern(tiny(), machine="kniterate")
    run = program_run(r.text, KNITERATE)
    speeds = {
        bool(x): {v for v, y in zip(run.speeds, run.transfers, strict=True) if y == x}
        for x in (True, False)
    }
    assert speeds[True] == {KNITERATE.transfer.speed_number}
    assert KNITERATE.speed_number in speeds[False]
    n = 100
    assert KNITERATE.pass_seconds(n, transfer=True, speed_number=100) > KNITERATE.pass_seconds(
        n, speed_number=300
    )


def test_calibrate_time_cli_then_knit_uses_the_machine_file(tmp_path, run_cli) -> None:
    pattern = tmp_path / "p.json"
    save_pattern(tiny(), pattern)
    machine = tmp_path / "my-shima.json"
    code, out, err = run_cli(
        ["calibrate", "time", str(pattern), "--minutes", "4", "-o", str(machine)]
    )
    assert code == 0, err
    assert "measured 4 min 00 s" in out and machine.exists()
    code, out, err = run_cli(
        ["knit", str(pattern), "-o", str(tmp_path / "p.k"), "--machine", str(machine), "--json"]
    )
    assert code == 0, err
    assert json.loads(out)["time_seconds"] == pytest.approx(240.0, abs=0.1)
    code, _, err = run_cli(
        ["calibrate", "time", str(pattern), "--minutes", "0.01", "-o", str(tmp_path / "x.json")]
    )
    assert code == 2 and "shorter than the carriage travel" in err
    assert not (tmp_path / "x.json").exists()
