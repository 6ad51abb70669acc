"""Reported passes are the machine's: pass counts against the reference SWG backend's ``.dat``.

Mixed-colourwork programs are also checked for what the carrier parking buys: no carrier is in a
pass's way, so the machine adds no kickbacks in the body.
"""

from __future__ import annotations

import struct
import subprocess
from pathlib import Path

import numpy as np
import pytest

from illuknit.check import check_knitout
from illuknit.core.machine import MachineSpec
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.knitting import knit_pattern
from illuknit.knitting.carriage import machine_run, runs_on_swg

YARNS3 = parse_yarns("#1b1b1b,#8a8a8a,#f4f0e8")


def dat_passes(text: str, tmp_path: Path, backend: Path) -> int:
    """Pass rows of the reference backend's ``.dat`` (raster height - 19); fails on any error."""
    k, dat = tmp_path / "p.k", tmp_path / "p.dat"
    k.write_text(text)
    r = subprocess.run(["node", str(backend), str(k), str(dat)], capture_output=True, text=True)
    log = r.stdout + r.stderr
    assert r.returncode == 0 and "ERROR" not in log and "Assertion" not in log, log[-300:]
    _, y0, _, y1 = struct.unpack("<4H", dat.read_bytes()[:8])
    return y1 - y0 + 1 - 19


def mixed_pattern(seed: int, shape=(8, 10), k=3) -> LogicalPattern:
    rng = np.random.default_rng(seed)
    # blocks of colour that move from row to row (intarsia and stranded) and a few bumps
    yarn = np.repeat(rng.integers(0, k, size=(shape[0], shape[1] // 2)), 2, axis=1)
    raised = rng.random(shape) < 0.2
    return LogicalPattern(yarn.astype(np.int16), raised, YARNS3[:k])


@pytest.mark.parametrize("seed", [0, 1])
def test_reported_passes_equal_the_reference_dat(seed, tmp_path, swg_backend):
    result = knit_pattern(mixed_pattern(seed))
    assert result.stats.passes == dat_passes(result.text, tmp_path, swg_backend)
    assert result.stats.lower_bound <= result.stats.passes


def test_machine_counts_add_up_and_parked_carriers_need_no_kickbacks():
    result = knit_pattern(mixed_pattern(2))
    run = machine_run(result.text)
    s = result.stats
    assert s.passes == run.passes == sum(run.kinds.values())
    assert s.schedule_passes == result.schedule.stats.passes
    # Every carrier is parked outside the fabric between its passes: nothing to kick, except a
    # carrier whose last pass ran rightward before it goes out (the machine takes carriers out
    # with a rightward pass).
    from illuknit.formats.swg_passes import machine_passes

    kinds = [p.kind.value for p in machine_passes(result.text)]
    kicks = [i for i, k in enumerate(kinds) if k == "kickback"]
    assert all(kinds[i + 1] == "carrier-out" for i in kicks), kinds
    assert result.schedule.mixed is not None
    assert s.kickbacks == len(kicks) <= result.schedule.mixed.carriers
    assert result.time.passes == s.passes
    assert check_knitout(result.text, machine=result.machine).ok


def test_non_swg_machines_report_the_schedule_passes():
    m = MachineSpec(carriers=("1", "2", "3", "4", "5", "6"))
    assert not runs_on_swg(m)
    result = knit_pattern(mixed_pattern(3, k=2), machine=m)
    assert result.stats == result.schedule.stats
