"""How the benchmark's independent certification fares on knit-aware models of growing size.

Usage: python benchmarks/certify_knit_aware.py [--sizes 8,10,12,16,20] [--time-limit 60]

For each square crop of the 3-yarn photo pair (astronaut / coffee, as benchmarks/knit_aware_gap.py
builds it), the ``descent`` backend's best pattern within 10 s is handed to
:func:`illuknit.bench.certify.certify_claim` as a claimed optimum with its assignment, as the
solver benchmark does for an ``optimal`` row that no reference settles. Prints the claim, the
Lagrangian lower bound of the same run, the certificate (``certified``: no cheaper pattern;
``refuted``: the SAT call found a cheaper one, its cost; ``unchecked (time)``) and the seconds
the check took, with the load average: times are wall clock on a shared machine. Nothing is
asserted.
"""

from __future__ import annotations

import argparse
import os
import time

from illuknit.bench.certify import certify_claim
from illuknit.bench.instances import Instance, instance_model
from illuknit.core.pattern import parse_yarns
from illuknit.solvers import solve

YARNS = "dark=#1e1b24,mid=#8c6f5a,light=#efe6d8"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="8,10,12,16,20")
    ap.add_argument("--time-limit", type=float, default=60.0, help="seconds per check")
    ap.add_argument("--pair", default="astronaut,coffee")
    args = ap.parse_args()
    a, b = args.pair.split(",")
    print(
        f"# knit-aware certification, {args.time_limit:g} s per check, exact engine rc2 per "
        f"component, {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f}"
    )
    print("size   vars    soft  claim  lagrangian  certificate          seconds")
    for n in (int(s) for s in args.sizes.split(",")):
        inst = Instance(
            f"{a}-{b}-{n}",
            "double",
            (n, n),
            tuple(parse_yarns(YARNS)),
            10.0,
            {"A": {"image": a}, "B": {"image": b}},
        )
        model, _ = instance_model(inst, model="knit-aware")
        sol = solve(model, solver="descent", time_limit=10.0)
        ok, cost = model.evaluate(sol.values)
        assert ok
        t0 = time.perf_counter()
        cert = certify_claim(model, int(cost), values=sol.values, time_limit=args.time_limit)
        wall = time.perf_counter() - t0
        found = f" (cost {cert.cost})" if cert.cost is not None else ""
        print(
            f"{n:>3}x{n:<3}{model.pool.top:>6}{len(model.to_clauses().soft):>7}{cost:>7}"
            f"{sol.bound:>12.0f}  {cert.result + found:<20} {wall:>7.1f}"
        )
    print(f"# load average {os.getloadavg()[0]:.1f} at the end")


if __name__ == "__main__":
    main()
