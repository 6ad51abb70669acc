"""Machine truth: what illuknit reports against what the reference SWG backend makes of it.

A small corpus of generated programs -- single view (2 and 3 yarns), tile double views (2, 3 and
4 yarns), a head-on design, a solver optimum and the calibration swatch -- each compiled with
:func:`illuknit.knit.knit_pattern` and converted by the reference SWG backend
(``knitout-to-dat.js``, see the oracles' README). Every program must be accepted by the backend
and pass ``illuknit check`` with nothing blocking, and the passes illuknit reports must be within
1 % of the pass rows of the ``.dat`` (raster height minus 19 fixed rows).
"""

from __future__ import annotations

import functools
import struct
import subprocess
from pathlib import Path

import pytest

from illuknit.check import check_knitout
from illuknit.core.pattern import LogicalPattern
from illuknit.knitting import KnitResult, knit_pattern

#: Fixed raster rows of a SWG ``.dat`` beyond one row per carriage pass.
DAT_FIXED_ROWS = 19

YARNS = {
    2: ["dark=#1b1b1b", "cream=#f4f0e8"],
    3: ["dark=#2b2118", "tan=#b08455", "cream=#f2e8d5"],
    4: ["red=#c8102e", "blue=#1f4e9c", "orange=#f28c28", "white=#f7f5f0"],
}


def _instance(kind: str, yarns: int, size: tuple[int, int], **inputs: object) -> object:
    from illuknit.bench.instances import parse_manifest

    table = {
        "name": f"truth-{kind}-{yarns}",
        "kind": kind,
        "size": list(size),
        "yarns": YARNS[yarns],
        "time_limit": 5,
        **inputs,
    }
    return parse_manifest({"instance": [table]}).instances[0]


def _design(case: str) -> LogicalPattern:
    from illuknit.bench.instances import instance_targets
    from illuknit.bench.methods import get_method

    if case == "swatch":
        from illuknit.design.render.calibrate import calibration_swatch

        return calibration_swatch(bump_sizes=(1, 2), flat_sizes=(1, 2), cell_width=3)
    design, yarns = case.rsplit("-", 1)
    n = int(yarns)
    if design == "single":
        inst = _instance("single", n, (14, 12), input={"image": "camera"})
        return get_method("single").run(inst, 5)[0]
    pair = {"a": {"draw": "heart"}, "b": {"draw": "circle"}}
    if n > 2:
        pair = {"a": {"image": "coffee"}, "b": {"image": "chelsea"}}
    inst = _instance("double", n, (12, 14), **pair)
    if design == "headon":
        from illuknit.design.tiles.compile import compile_tiles
        from illuknit.design.tiles.headon import assign_headon

        t = instance_targets(inst)
        cands = assign_headon((t.a, t.palette), yarns=inst.yarns, candidates=1)  # type: ignore[attr-defined]
        return compile_tiles(cands[0])[0]
    return get_method(design).run(inst, 5)[0]


@functools.cache
def _knit(case: str) -> KnitResult:
    return knit_pattern(_design(case))


@functools.cache
def _dat_passes(case: str, backend: Path) -> int:
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        k, dat = Path(tmp) / "p.k", Path(tmp) / "p.dat"
        k.write_text(_knit(case).program)
        proc = subprocess.run(
            ["node", str(backend), str(k), str(dat)], capture_output=True, text=True, check=False
        )
        assert proc.returncode == 0 and dat.exists(), f"backend refused {case}: {proc.stderr}"
        _x0, y0, _x1, y1 = struct.unpack_from("<4H", dat.read_bytes(), 0)
        return y1 - y0 + 1 - DAT_FIXED_ROWS


CASES = [
    "single-2",
    "single-3",
    "tiles-2",
    "tiles-3",
    "tiles-4",
    "headon-2",
    "dp-2",
    "swatch",
]


@pytest.mark.parametrize("case", CASES)
def test_backend_accepts_and_checker_passes(case: str, swg_backend: Path) -> None:
    result = _knit(case)
    assert (
        _dat_passes(case, swg_backend) >= result.stats.passes
    )  # the backend only ever adds passes
    report = check_knitout(result.program, machine=result.machine)
    assert report.ok, [f"{f.line}: {f.code}: {f.message}" for f in report.blocking[:5]]


@pytest.mark.parametrize("case", CASES)
def test_reported_passes_are_the_machines(case: str, swg_backend: Path) -> None:
    reported, dat = _knit(case).stats.passes, _dat_passes(case, swg_backend)
    assert abs(reported - dat) <= 0.01 * dat, f"{case}: reported {reported}, .dat {dat}"
