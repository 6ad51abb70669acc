"""Benchmark: converting a large piece's knitout to machine files.

Issue target: a 660 x 400-stitch piece (the paper's largest) converts in under 5 s for either
machine format.

Kniterate ``.kc``: its bed has 252 needles, so 400 or 660 wales do not fit; the piece timed has
the same 264,000 stitches as 240 wales x 1100 courses (120 x 550 units, single-view stripes with
40 % raised units), plus a mixed-colourwork piece of 240 x 400 stitches. The knitout is made with
``--machine kniterate`` (waste section and draw thread included), then converted with
:func:`illuknit.formats.kc.knitout_to_kc`; with ``node`` on PATH the reference backend converts the
same file, for comparison and to check that the two outputs agree.

Wall time is what the target is about; the CPU time column shows how much of it was this process
computing when the machine is shared with other work.

Run: ``python benchmarks/machine_files.py``
"""

from __future__ import annotations

import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from illuknit.formats.kc import knitout_to_kc
from illuknit.knit import knit_pattern
from illuknit.knit.machine import KNITERATE
from illuknit.pattern import LogicalPattern, Yarn

TARGET_S = 5.0
ORACLE = Path(__file__).resolve().parents[1] / ".." / "shared" / "oracles" / "kniterate"
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
    for base in (ORACLE, Path("/work/shared/oracles/kniterate")):
        script = base / "knitout-to-kcode.js"
        if script.exists() and shutil.which("node"):
            return script
    return None


def main() -> None:
    script = oracle_script()
    print(
        f"{'piece':<34} {'stitches':>9} {'knitout':>8} {'.kc':>7} {'.kc cpu':>7} {'target':>7} "
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
            f"{label:<34} {stitches:>9} {t1 - t0:>7.2f}s {t2 - t1:>6.2f}s {cpu:>6.2f}s {ok:>7} "
            f"{node_s:>6}s {passes:>9}  {same}"
        )


if __name__ == "__main__":
    main()
