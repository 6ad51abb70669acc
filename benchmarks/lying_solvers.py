"""The lying-solver zoo (issue 35): each fake solver of tests/bench/lying_maxsat.py, alone and
beside RC2, through the solver benchmark; prints the verdict per fake. None may be believed:
no fake is counted as solved, and none scores.

Usage: python benchmarks/lying_solvers.py [--size 57x40] [--time-limit 20] [--memory-mb 1000]
Prints one line per (fake, company); nothing is asserted. The `escape` fake runs under at
most 500 MB (its helper holds 600 MB).
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

from illuknit.bench.instances import Instance
from illuknit.bench.solver_table import make_tasks, run_solver_table
from illuknit.bench.wcnf_files import export_wcnf_family
from illuknit.core.pattern import parse_yarns

LIAR = Path(__file__).parents[1] / "tests" / "bench" / "lying_maxsat.py"
MODES = (
    "honest",
    "wale-first",
    "wale-middle",
    "wale-last",
    "early-o",
    "escape",
    "big-alloc",
    "v-long",
    "v-short",
    "v-both",
    "v-twice",
    "v-range",
    "false-unsat",
)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", default="57x40")
    ap.add_argument("--time-limit", type=float, default=20.0)
    ap.add_argument("--memory-mb", type=float, default=1000.0)
    ap.add_argument("--modes", default=",".join(MODES))
    args = ap.parse_args()
    rows, cols = (int(x) for x in args.size.split("x"))
    out = Path(tempfile.mkdtemp(prefix="illuknit-zoo-"))
    inst = Instance(
        f"zoo-{rows}x{cols}",
        "double",
        (rows, cols),
        parse_yarns(["#1b1b1b", "#f4f0e8"]),
        args.time_limit,
        {"A": {"draw": "heart"}, "B": {"text": "ECG"}},
    )
    mf = export_wcnf_family([inst], out / "wcnf", models=["logical"])
    path = str(out / "wcnf" / mf["files"][0]["file"])
    print(
        f"# lying-solver zoo on {inst.name} (logical model as WCNF, {mf['files'][0]['variables']} "
        f"variables), {args.time_limit:g} s, {args.memory_mb:g} MB, {os.cpu_count()} CPUs, "
        f"load {os.getloadavg()[0]:.1f}"
    )
    print(f"{'fake':12s} {'beside':7s} {'status':10s} {'solved':6s} {'score':5s} verdict")
    for mode in args.modes.split(","):
        fake = f"wcnf:{sys.executable} {LIAR} {mode} {{}}"
        for company in ([], ["rc2"]):
            t0 = time.perf_counter()
            # the escaped helper holds 600 MB: under a 500 MB limit only its count can catch it
            memory = min(args.memory_mb, 500.0) if mode == "escape" else args.memory_mb
            tasks = make_tasks(
                [],
                [fake, *company],
                time_limit=args.time_limit,
                memory_mb=memory,
                wcnf_files=[path],
            )
            table = run_solver_table(tasks, out / f"{mode}-{len(company)}")
            row = next(r for r in table.rows if r["solver"] == fake)
            entry = next(s for s in table.summary if s["solver"] == fake)
            score = next((v for k, v in entry.items() if k.startswith("score@")), 0.0)
            verdict = "; ".join(
                filter(
                    None,
                    [
                        f"certificate {row.get('certificate') or '-'}",
                        row.get("flag"),
                        row.get("reason"),
                    ],
                )
            )
            print(
                f"{mode:12s} {'+'.join(company) or 'alone':7s} {row['status']:10s} "
                f"{entry['solved']:<6d} {score:<5.2f} best@{row.get('time_best') or '-'}s "
                f"peak {row.get('peak_rss_mb') or '-'} MB; {verdict[:150]} "
                f"({time.perf_counter() - t0:.0f} s)",
                flush=True,
            )
    print(f"# tables in {out}")


if __name__ == "__main__":
    main()
