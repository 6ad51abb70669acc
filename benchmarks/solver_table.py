"""The solver table on the quick instances (issue 17 targets).

Targets: at least 8 solvers on the quick instances in under 5 minutes on 2 cores; every complete
solver's optimum equals the DP's on the logical model (no flagged run).

Usage: python benchmarks/solver_table.py [--time-limit 10] [--jobs 2] [--solvers LIST] [-o DIR]
Prints the summary and the verdicts; writes the full table (solvers.csv, traces.csv, solvers.md,
plots) into DIR (default: a temporary folder). Nothing is asserted.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

from illuknit.bench.instances import load_manifest, select_instances
from illuknit.bench.solver_table import make_tasks, run_solver_table
from illuknit.solvers import available_backends

SOLVERS = "dp,rc2,rc2:cd19,lsu,fm,cpsat,uwrmaxsat,cgss,evalmaxsat,openwbo,cashwmaxsat,loandra"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--time-limit", type=float, default=10.0)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--solvers", default=SOLVERS)
    ap.add_argument("-o", "--outdir", default=None)
    args = ap.parse_args()
    have = set(available_backends())
    solvers = [s for s in args.solvers.split(",") if s.partition(":")[0] in have]
    outdir = args.outdir or tempfile.mkdtemp(prefix="illuknit-solver-table-")
    instances = select_instances(load_manifest(), "quick")
    tasks = make_tasks(instances, solvers, time_limit=args.time_limit)
    print(
        f"# {len(solvers)} solvers x {len(instances)} quick instances, {args.time_limit:g} s "
        f"each, {args.jobs} jobs, {os.cpu_count()} CPUs, load {os.getloadavg()[0]:.1f}"
    )
    t0 = time.perf_counter()
    table = run_solver_table(tasks, outdir, jobs=args.jobs)
    wall = time.perf_counter() - t0
    for s in table.summary:
        print(
            f"  {s['solver']:16s} solved {s['solved']}/{s['runs']}  PAR-2 {s['par2']:7.2f}  "
            f"flagged {s.get('flagged', '-')}"
        )
    flagged = [r for r in table.rows if r.get("flag")]
    print(f"# wall {wall:.0f} s (target < 300 s with >= 8 solvers): {len(solvers)} solvers")
    print(f"# flagged runs: {len(flagged)} (target 0)")
    for r in flagged:
        print(f"  {r['instance']} {r['solver']}: {r['flag']}")
    print(f"# table in {outdir}")


if __name__ == "__main__":
    main()
