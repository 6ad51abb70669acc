"""Solve time and objective per backend on binary target pairs (a heart seen from above, an ECG
pulse from below), drawn by code at 50 x 50, 100 x 100 and 330 x 200 units.

Targets (issue "Constraint models and pluggable solvers"):

* DP < 1 s at 330 x 200 (model (a));
* RC2 and CP-SAT prove optimality of model (a) at 100 x 100 within 60 s;
* model (b) (knit-aware) at 100 x 100: objective and gap after 60 s.

Usage: python benchmarks/solvers_speed.py [--time-limit 60] [--quick]
(``--quick``: 50 x 50 only, 10 s limit). Prints one line per run; nothing is asserted.
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np

from illuknit.drawings import draw_ecg, draw_heart
from illuknit.illusion_models import KnitWeights, build_model, make_problem
from illuknit.solvers import available_backends, get_backend, solve
from illuknit.solvers.dp import hint_values


def pair(rows: int, cols: int) -> tuple[np.ndarray, np.ndarray]:
    return draw_heart((rows, cols)).astype(np.int16), draw_ecg((rows, cols)).astype(np.int16)


def run(kind: str, rows: int, cols: int, backend: str, limit: float, weights: KnitWeights) -> str:
    a, b = pair(rows, cols)
    problem = make_problem(a, b, n_yarns=2, kind=kind, weights=weights)
    t0 = time.perf_counter()
    model = build_model(problem)
    build = time.perf_counter() - t0
    b = get_backend(backend)
    if not b.handles(model):
        why = getattr(b, "why_not", lambda m: "")(model)
        return f"{kind:<10} {rows:>3}x{cols:<3} {backend:<6} skipped: {why}"
    if backend != "dp":
        model.hint = hint_values(problem, model)
    sol = solve(model, solver=backend, time_limit=limit)
    gap = "-" if sol.gap is None else f"{100 * sol.gap:.1f}%"
    bound = "-" if sol.bound is None else f"{sol.bound:g}"
    return (
        f"{kind:<10} {rows:>3}x{cols:<3} {backend:<6} {sol.status.value:<8} "
        f"obj {sol.objective!s:>6}  bound {bound:>7}  gap {gap:>6}  "
        f"solve {sol.wall_time:7.3f} s  (build {build:.3f} s, {model.num_vars} vars)"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--time-limit", type=float, default=60.0)
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    limit = 10.0 if args.quick else args.time_limit
    sizes = [(50, 50)] if args.quick else [(50, 50), (100, 100), (330, 200)]
    have = available_backends()
    print(
        f"# illuknit solver benchmark on {platform.processor() or platform.machine()}, limit {limit:g} s"
    )
    print("# targets: DP < 1 s at 330x200; RC2/CP-SAT optimal on (a) at 100x100 within 60 s")
    w_a = KnitWeights()
    for rows, cols in sizes:
        for backend in ("dp", "cpsat", "rc2", "lsu"):
            if backend in have:
                print(run("logical", rows, cols, backend, limit, w_a), flush=True)
    w_b = KnitWeights(view=4, color_change=1, transfer=1)
    for rows, cols in sizes[:2]:
        for backend in ("cpsat", "rc2", "lsu"):
            if backend in have:
                print(run("knit-aware", rows, cols, backend, limit, w_b), flush=True)


if __name__ == "__main__":
    main()
