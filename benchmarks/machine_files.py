"""Benchmark: converting a large piece's knitout to machine files.

Issue target: a 660 x 400-stitch piece (the paper's largest) converts in under 5 s for either
machine format.

Kniterate ``.kc``: its bed has 252 needles, so 400 or 660 wales do not fit; the piece timed has
the same 264,000 stitches as 240 wales x 1100 courses (120 x 550 units, single-view stripes with
40 % raised units), plus a mixed-colourwork piece of 240 x 400 stitches. The knitout is made with
``--machine kniterate`` (waste section and draw thread included), then converted with
:func:`illuknit.formats.kc.knitout_to_kc`; with ``node`` on PATH the reference backend converts the
same file, for comparison and to check that the two outputs agree.

Shima ``.dat``: the 660 x 400-stitch piece itself (330 x 200 units, single-view stripes with 40 %
raised units, and a mixed-colourwork piece of the same size) on the ``generic540`` preset widened to
720 needles, converted with :func:`illuknit.formats.dat.knitout_to_dat`; with ``node`` the
reference ``knitout-to-dat.js`` converts the same file and the two ``.dat`` must be byte-identical.

Times are wall-clock seconds of one run; on a busy machine the CPU seconds (``cpu``) are the
fairer figure.

Run: ``python benchmarks/machine_files.py``
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from illuknit.core.machine import KNITERATE, MACHINES
from illuknit.core.pattern import LogicalPattern, Yarn
from illuknit.formats.dat import knitout_to_dat, read_dat
from illuknit.formats.kc import knitout_to_kc
from illuknit.knitting import knit_pattern

TARGET_S = 5.0
#: The reference backends: ``ILLUKNIT_ORACLES``, else ``shared/oracles`` beside the checkout.
ORACLES = Path(
    os.environ.get("ILLUKNIT_ORACLES") or Path(__file__).resolve().parents[2] / "shared" / "oracles"
)
YARNS = (Yarn("dark", (27, 27, 27)), Yarn("light", (244, 240, 232)))


def stripes(rows: int, cols: int, seed: int = 0) -> LogicalPattern:
    yarn = np.repeat((np.arange(rows) % 2)[:, None], cols, axis=1)
    raised = np.random.default_rng(seed).random((rows, cols)) < 0.4
    return LogicalPattern(yarn, raised, YARNS)


def blocks(rows: int, cols: int, seed: int = 0) -> LogicalPattern:
    """Two colour regions per row (mixed colourwork)."""
    yarn = (np.arange(cols)[None, :] >= cols // 2).repeat(rows, axis=0).astype(int)
    raised = np.random.default_rng(seed).random((rows, cols)) < 0.4
    return LogicalPattern(yarn, raised, YARNS)


def oracle_script() -> Path | None:
    script = ORACLES / "kniterate" / "knitout-to-kcode.js"
    return script if script.exists() and shutil.which("node") else None


def swg_oracle_script() -> Path | None:
    script = ORACLES / "swg" / "knitout-to-dat.js"
    return script if script.exists() and shutil.which("node") else None


def bench_dat() -> None:
    """The 660 x 400-stitch piece as a Shima .dat, against the reference backend."""
    script = swg_oracle_script()
    machine = MACHINES["generic540"].with_width(720)
    print(
        f"{'piece':<34} {'stitches':>9} {'knitout':>8} {'.dat':>7} {'cpu':>6} {'target':>7} "
        f"{'node':>7} {'passes':>7}  byte-identical to reference"
    )
    for label, pattern in (
        ("single-view 330 x 200 units", stripes(200, 330)),
        ("mixed colourwork 330 x 200 units", blocks(200, 330)),
    ):
        t0 = time.perf_counter()
        text = knit_pattern(pattern, machine=machine).text
        t1 = time.perf_counter()
        c1 = time.process_time()
        dat = knitout_to_dat(text)
        t2, c2 = time.perf_counter(), time.process_time()
        node_s, same = "-", "node not available"
        if script is not None:
            with tempfile.TemporaryDirectory() as d:
                src, out = Path(d) / "piece.k", Path(d) / "piece.dat"
                src.write_text(text)
                t3 = time.perf_counter()
                subprocess.run(["node", str(script), str(src), str(out)], capture_output=True)
                node_s = f"{time.perf_counter() - t3:.2f}"
                same = "yes" if out.exists() and out.read_bytes() == dat else "NO"
        passes = len(read_dat(dat).passes)
        ok = "ok" if t2 - t1 < TARGET_S else "SLOW"
        print(
            f"{label:<34} {pattern.yarn.size * 4:>9} {t1 - t0:>7.2f}s {t2 - t1:>6.2f}s "
            f"{c2 - c1:>5.2f}s {ok:>7} {node_s:>6}s {passes:>7}  {same}"
        )


def main() -> None:
    bench_kc()
    print()
    bench_dat()


def bench_kc() -> None:
    """The Kniterate pieces as .kc, against the reference backend."""
    script = oracle_script()
    print(
        f"{'piece':<34} {'stitches':>9} {'knitout':>8} {'.kc':>7} {'cpu':>6} {'target':>7} "
        f"{'node':>7} {'kc passes':>9}  same as reference"
    )
    for label, pattern in (
        ("single-view 120 x 550 units", stripes(550, 120)),
        ("mixed colourwork 120 x 200 units", blocks(200, 120)),
    ):
        t0 = time.perf_counter()
        text = knit_pattern(pattern, machine=KNITERATE).text
        t1, c1 = time.perf_counter(), time.process_time()
        kc = knitout_to_kc(text, name="piece.kc")
        t2, cpu = time.perf_counter(), time.process_time() - c1
        node_s, same = "-", "node not available"
        if script is not None:
            with tempfile.TemporaryDirectory() as d:
                src, out = Path(d) / "piece.k", Path(d) / "piece.kc"
                src.write_text(text)
                t3 = time.perf_counter()
                subprocess.run(["node", str(script), str(src), str(out)], capture_output=True)
                node_s = f"{time.perf_counter() - t3:.2f}"
                ref = out.read_text().split("\n") if out.exists() else []
                mine = kc.split("\n")
                same = "yes" if ref[:2] + ref[3:] == mine[:2] + mine[3:] else "NO"
        passes = kc.count("\n>>") + kc.count("\n<<")
        stitches = pattern.yarn.size * 4
        ok = "ok" if t2 - t1 < TARGET_S else "SLOW"
        print(
            f"{label:<34} {stitches:>9} {t1 - t0:>7.2f}s {t2 - t1:>6.2f}s {cpu:>5.2f}s {ok:>7} "
            f"{node_s:>6}s {passes:>9}  {same}"
        )


if __name__ == "__main__":
    main()
