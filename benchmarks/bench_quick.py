"""Speed target of the benchmark suite: `illuknit bench --instances quick` in < 3 min on 2 cores.

Runs the quick subset with every default method and 2 worker processes into a temporary folder
and prints the wall time against the target, and the status counts.

    python benchmarks/bench_quick.py [--jobs 2]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from collections import Counter
from pathlib import Path

from illuknit.bench import DEFAULT_METHODS, load_manifest, run_bench, select_instances

TARGET_S = 180.0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args()
    insts = select_instances(load_manifest(), "quick")
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        run = run_bench(
            insts, list(DEFAULT_METHODS), Path(tmp) / "r", jobs=args.jobs, progress=False
        )
        wall = time.perf_counter() - t0
    counts = Counter(r["status"] for r in run.rows)
    print(
        f"quick subset: {len(insts)} instances x {len(DEFAULT_METHODS)} methods = {len(run.rows)} cells"
    )
    print(f"statuses: {dict(counts)}")
    verdict = "OK" if wall < TARGET_S else "OVER TARGET"
    print(f"wall time {wall:.1f} s with --jobs {args.jobs} (target < {TARGET_S:.0f} s): {verdict}")


if __name__ == "__main__":
    main()
