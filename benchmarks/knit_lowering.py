"""Benchmark: lowering, scheduling and writing knitout for the paper's largest piece size.

The paper's Van Gogh piece is 660 x 400 stitches = 330 x 200 units. Target: lowering + scheduling +
writing in < 5 s. Both orientations are timed: 330 rows x 200 columns (400 wales, fits the default
540-needle bed) and 200 rows x 330 columns (660 wales, on a 700-needle bed).

Run: ``python benchmarks/knit_lowering.py``
"""

from __future__ import annotations

import time

import numpy as np

from illuknit.core.machine import get_machine
from illuknit.core.pattern import LogicalPattern, Yarn
from illuknit.knit import (
    estimate_knit_time,
    lower_to_stitches,
    schedule_courses,
    write_knitout,
)

TARGET_S = 5.0


def single_view(rows: int, cols: int, seed: int = 0) -> LogicalPattern:
    """Alternating stripe rows with a random 40% of units raised (any single-view illusion)."""
    yarn = np.repeat((np.arange(rows) % 2)[:, None], cols, axis=1)
    raised = np.random.default_rng(seed).random((rows, cols)) < 0.4
    return LogicalPattern(
        yarn, raised, (Yarn("dark", (27, 27, 27)), Yarn("light", (244, 240, 232)))
    )


def main() -> None:
    print(
        f"{'units':>10} {'stitches':>10} {'lower':>7} {'schedule':>9} {'write':>7} {'total':>7}  target  passes  ratio  est. time"
    )
    for rows, cols, needles in ((330, 200, 540), (200, 330, 700)):
        p = single_view(rows, cols)
        m = get_machine().with_width(needles)
        t0 = time.perf_counter()
        s = lower_to_stitches(p, machine=m)
        t1 = time.perf_counter()
        sch = schedule_courses(s, machine=m)
        t2 = time.perf_counter()
        text = write_knitout(sch, machine=m)
        t3 = time.perf_counter()
        st = sch.stats
        total = t3 - t0
        ok = "ok" if total < TARGET_S else "MISSED"
        print(
            f"{rows:>4}x{cols:<5} {s.wales:>4}x{s.courses:<5} {t1 - t0:>6.3f}s {t2 - t1:>8.3f}s {t3 - t2:>6.3f}s "
            f"{total:>6.2f}s  <{TARGET_S:.0f}s {ok:>3}  {st.passes:>6}  {st.ratio:.2f}  {estimate_knit_time(sch)}"
            f"  ({len(text) / 1e6:.1f} MB)"
        )


if __name__ == "__main__":
    main()
