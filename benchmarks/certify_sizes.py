"""How long the certifier takes on true and false optima of logical models (issue 35 target).

Target: every true optimum of logical models from 57 x 40 to 143 x 100 units with 2-4 yarns
certified, each in at most 10 % of a 60 s run's limit (6 s); every false one refuted.

Each model is written as a WCNF file and read back (the certifier sees the formula, not our
model builder). The true claim is the DP's optimal assignment; the false one is the same
assignment with its last component (the last wale) replaced by a feasible but costlier one.
Both are certified by RC2 (the engine for any claimant but RC2) and by CP-SAT (the engine for
RC2's claims).

Usage: python benchmarks/certify_sizes.py [--sizes 57x40x2,86x60x3,114x80x3,143x100x4]
       [--time-limit 60]
Prints one line per (size, claim, engine); nothing is asserted.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from illuknit.bench.certify import certify_claim, formula_components
from illuknit.bench.instances import Instance, instance_model
from illuknit.bench.wcnf_files import read_wcnf_text
from illuknit.core.pattern import parse_yarns
from illuknit.solvers import solve

COLOURS = ["#1b1b1b", "#f4f0e8", "#b3202a", "#1f4e9c"]


def _instance(rows: int, cols: int, yarns: int) -> Instance:
    if yarns == 2:
        inputs = {"A": {"draw": "heart"}, "B": {"text": "ECG"}}
    else:
        inputs = {"A": {"image": "coffee"}, "B": {"image": "chelsea"}}
    return Instance(
        f"held-out-{rows}x{cols}-{yarns}",
        "double",
        (rows, cols),
        parse_yarns(COLOURS[:yarns]),
        60.0,
        inputs,
    )


def _worse_last(model, values):
    """``values`` with the last component's variables set by a SAT call that prefers to
    violate soft clauses (feasible, costlier when the component allows)."""
    from pysat.solvers import Solver

    cs = model.to_clauses()
    hard_idx, soft_idx = formula_components(cs.hard, cs.soft)[-1]
    hard = [list(map(int, cs.hard[i])) for i in hard_idx]
    against = {abs(x): x < 0 for i in soft_idx for x in cs.soft[i]}
    out = np.asarray(values, dtype=bool).copy()
    with Solver(name="m22", bootstrap_with=hard) as s:
        s.set_phases([v if bad else -v for v, bad in against.items()])
        s.solve()
        for x in s.get_model() or []:
            if abs(x) in against:
                out[abs(x)] = x > 0
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="57x40x2,86x60x3,114x80x3,143x100x4")
    ap.add_argument("--time-limit", type=float, default=60.0, help="the run's limit (s)")
    args = ap.parse_args()
    print(
        f"# certifier, run limit {args.time_limit:g} s (target <= {args.time_limit / 10:g} s), "
        f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f}"
    )
    print("size         vars   soft  comps  claim        engine certificate          seconds")
    for spec in args.sizes.split(","):
        rows, cols, yarns = (int(x) for x in spec.split("x"))
        built, _ = instance_model(_instance(rows, cols, yarns), model="logical")
        model = read_wcnf_text(built.to_wcnf(style="new"), spec)
        sol = solve(built, solver="dp")  # exact on the logical model
        values = np.asarray(sol.values, dtype=bool)[: model.pool.top + 1]
        ok, true_cost = model.evaluate(values)
        assert ok
        false_values = _worse_last(model, values)
        ok, false_cost = model.evaluate(false_values)
        cs = model.to_clauses()
        n = len(formula_components(cs.hard, cs.soft))
        for label, cost, vals in (("true", true_cost, values), ("false", false_cost, false_values)):
            for engine in ("rc2", "cpsat"):
                t0 = time.perf_counter()
                cert = certify_claim(
                    model, int(cost), values=vals, time_limit=args.time_limit, engine=engine
                )
                wall = time.perf_counter() - t0
                print(
                    f"{spec:11s} {model.pool.top:6d} {model.num_soft:6d} {n:5d}  "
                    f"{label:5s} {cost:6d} {engine:6s} {cert.result:20s} {wall:6.2f}",
                    flush=True,
                )


if __name__ == "__main__":
    main()
