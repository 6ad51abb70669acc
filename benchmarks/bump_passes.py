"""Machine passes of tall and split bumps on both reference backends (docs/split-bumps.md).

For a few bundled designs -- the single-view pattern of ``camera-single``, the tile design
(``illuknit double``) and the exact per-wale DP design without and with split bumps (bench
methods ``dp`` and ``dp-split``: the tile search rarely picks split bumps on these instances, the
DP uses hundreds) of ``plus-circle`` and ``coffee-chelsea-3``, and the calibration swatch with
its split band -- this knits each with and without tall bumps (``KnitOptions.tall_bumps``) for the
Shima SWG091N2 and the Kniterate (their presets, bed width printed), converts each program with the
reference backend of its machine and prints per program:

``bed``        the machine and its bed
``split``      split bumps in the pattern (of ``bumps`` raised units)
``passes``     carriage passes the machine runs: pass rows of the reference ``.dat`` (raster
               height minus its 19 fixed rows) on the SWG091N2, ``>>``/``<<`` rows of the
               reference ``.kc`` on the Kniterate (its waste section included)
``x plain``    over the same design knit with plain bumps on the same bed
``check``      blocking findings and warnings of ``illuknit check`` (told about split bumps), and
               the pieces (target: ``0/0 1``)

Run: ``python benchmarks/bump_passes.py [--time-limit S]``. Needs ``node`` and the reference
backends beside the checkout (``../shared/oracles``, or ``ILLUKNIT_ORACLES``). The tile search
is time-limited, so a loaded machine may pick another design; the passes are the machine's for
the design printed.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))

from machine_passes import dat_passes  # noqa: E402

ORACLES = Path(os.environ.get("ILLUKNIT_ORACLES") or ROOT.parent / "shared" / "oracles")
BACKENDS = {
    "swg091n2": ("swg/knitout-to-dat.js", ".dat"),
    "kniterate": ("kniterate/knitout-to-kcode.js", ".kc"),
}
DESIGNS = (
    ("camera-single", "single"),
    ("plus-circle", "tiles"),
    ("plus-circle", "dp"),
    ("plus-circle", "dp-split"),
    ("coffee-chelsea-3", "tiles"),
    ("coffee-chelsea-3", "dp"),
    ("coffee-chelsea-3", "dp-split"),
    ("swatch", "split band"),
)


def design(name: str, method: str, time_limit: float) -> Any:
    """The pattern of one row of :data:`DESIGNS`."""
    if name == "swatch":
        from illuknit.design.render.calibrate import calibration_swatch

        return calibration_swatch(
            bump_sizes=(1, 2), flat_sizes=(1, 2, 3), cell_width=4, split_rows=3
        )
    from illuknit.bench.instances import load_manifest
    from illuknit.bench.methods import get_method

    instance = next(i for i in load_manifest().instances if i.name == name)
    return get_method(method).run(instance, time_limit)[0]


def machine_passes(program: str, machine: str) -> tuple[int | None, str]:
    """Passes the reference backend of ``machine`` makes of ``program`` (None: refused)."""
    script, suffix = BACKENDS[machine]
    with tempfile.TemporaryDirectory() as tmp:
        k, out = Path(tmp) / "p.k", Path(tmp) / f"p{suffix}"
        k.write_text(program)
        proc = subprocess.run(
            ["node", str(ORACLES / script), str(k), str(out)],
            capture_output=True,
            text=True,
            check=False,
        )
        log = proc.stdout + proc.stderr
        if proc.returncode != 0 or not out.exists() or "Assertion failed" in log:
            return None, (log.strip().splitlines() or ["refused"])[-1][:70]
        if suffix == ".dat":
            return dat_passes(out.read_bytes()), ""
        rows = out.read_text().splitlines()
        return sum(r.startswith((">>", "<<")) for r in rows), ""


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--time-limit", type=float, default=10.0, help="seconds per tile search")
    args = ap.parse_args(argv)
    from illuknit.check import check_knitout
    from illuknit.knitting import knit_pattern

    print(f"{'design':34} {'bed':22} {'tall':>4} {'split':>9} {'passes':>7} {'x plain':>7}  check")
    for name, method in DESIGNS:
        pattern = design(name, method, args.time_limit)
        label = f"{name} ({method}) {pattern.shape[0]}x{pattern.shape[1]}"
        for machine in BACKENDS:
            plain = None
            for tall in (False, True):
                result = knit_pattern(
                    pattern, machine=machine, tall_bumps=tall, allow_long_floats=True
                )
                passes, note = machine_passes(result.program, machine)
                report = check_knitout(
                    result.program, machine=machine, split_bumps=result.split_bumps > 0
                )
                plain = passes if not tall else plain
                ratio = f"{passes / plain:.3f}" if passes and plain else "-"
                bed = f"{result.machine.name} ({result.machine.needles})"
                split = f"{result.split_bumps}/{int(pattern.raised.sum())}"
                shown = "REFUSED " + note if passes is None else str(passes)
                print(
                    f"{label:34} {bed:22} {'yes' if tall else 'no':>4} {split:>9} {shown:>7} "
                    f"{ratio:>7}  {report.n_blocking}/{report.n_warnings} {report.pieces}"
                )
    return 0


if __name__ == "__main__":
    sys.exit(main())
