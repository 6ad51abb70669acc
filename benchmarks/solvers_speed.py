"""Solve time and objective per backend on binary target pairs (a heart seen from above, an ECG
pulse from below), drawn by code at 50 x 50, 100 x 100 and 330 x 200 units; the knit-aware model
(b) across colour-change weights with estimated knitting times; the single-view model (c) against
the push-button compiler.

Targets (issue "Constraint models and pluggable solvers"):

* DP < 1 s at 330 x 200 (model (a));
* RC2 and CP-SAT prove optimality of model (a) at 100 x 100 within 60 s;
* model (b) (knit-aware) at 100 x 100: objective and gap after 60 s — and a pattern that knits
  faster (fewer colour changes per course) than the MaxSAT optimum.

Usage: python benchmarks/solvers_speed.py [--time-limit 60] [--quick]
       [--sections logical,knit-aware,sweep,single]
(``--quick``: 50 x 50 only, 10 s limit). Prints one line per run; nothing is asserted.
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np

from illuknit.core.errors import SolverError
from illuknit.design.models.illusion_models import (
    KnitWeights,
    build_model,
    default_yarns,
    make_problem,
    pattern_from_solution,
)
from illuknit.pictures.drawings import draw_ecg, draw_heart
from illuknit.solvers import available_backends, solve

SECTIONS = ("logical", "knit-aware", "sweep", "single")


def pair(rows: int, cols: int) -> tuple[np.ndarray, np.ndarray]:
    return draw_heart((rows, cols)).astype(np.int16), draw_ecg((rows, cols)).astype(np.int16)


def run(kind: str, rows: int, cols: int, backend: str, limit: float, weights: KnitWeights) -> str:
    a, b = pair(rows, cols)
    problem = make_problem(a, b, n_yarns=2, kind=kind, weights=weights)
    t0 = time.perf_counter()
    model = build_model(problem)
    build = time.perf_counter() - t0
    # the DP optimum; for model (b) a block descent taking up to half the limit
    policy = "auto"
    try:
        sol = solve(model, solver=backend, warm_start=policy, time_limit=limit)
    except SolverError as e:
        return f"{kind:<10} {rows:>3}x{cols:<3} {backend:<7} skipped: {e}"
    ws = sol.stats.get("warm_start", {})
    gap = "-" if sol.gap is None else f"{100 * sol.gap:.1f}%"
    bound = "-" if sol.bound is None else f"{sol.bound:g}"
    start = f", warm start {ws.get('method', 'none')} {ws.get('objective', '')}, found by {sol.found_by}"
    return (
        f"{kind:<10} {rows:>3}x{cols:<3} {backend:<7} {sol.status.value:<8} "
        f"obj {sol.objective!s:>6}  bound {bound:>7}  gap {gap:>6}  "
        f"solve {sol.wall_time:7.3f} s  (build {build:.3f} s, {model.num_vars} vars{start})"
    )


def _knit_numbers(pattern) -> tuple[str, int]:
    from illuknit.knitting import knit_pattern

    s = knit_pattern(pattern).summary()
    return str(s["time"]), int(s["passes"])


def sweep(limit: float, size: tuple[int, int]) -> None:
    """Model (b) across colour-change weights: error vs colour changes vs knitting time."""
    from illuknit.core.views import can_see

    a, b = pair(*size)
    print(
        f"# knit-aware model (b), heart/ECG {size[0]}x{size[1]}, view=4 transfer=1, "
        f"descent {limit:g} s (weight 0 = the MaxSAT optimum, by the DP)"
    )
    print(
        "# color_change  objective  bound(DP)  error A   error B   changes/course  "
        "rows w/ bumps  passes  est. knit time"
    )
    for wc in (0, 1, 2, 4, 8):
        problem = make_problem(a, b, n_yarns=2, kind="knit-aware", weights=KnitWeights(4, wc, 1))
        model = build_model(problem)
        sol = solve(model, solver="descent", time_limit=limit)
        pat = pattern_from_solution(problem, sol, yarns=default_yarns(2))
        ea = float((can_see(pat, "A") != a).mean())
        eb = float((can_see(pat, "B") != b).mean())
        cc = float((pat.yarn[:, 1:] != pat.yarn[:, :-1]).sum(axis=1).mean())
        rows_b = int(np.asarray(pat.raised).any(axis=1).sum())
        t, passes = _knit_numbers(pat)
        print(
            f"  {wc:>12}  {sol.objective:>9}  {sol.bound:>9g}  {100 * ea:6.1f}%  {100 * eb:6.1f}%"
            f"  {cc:>14.2f}  {rows_b:>13}  {passes:>6}  {t}",
            flush=True,
        )


def single(size: tuple[int, int]) -> None:
    """Model (c) (one yarn per course) against the push-button compiler on the heart."""
    from illuknit.core.views import can_see
    from illuknit.design.models.backends.dp import values_from_pattern
    from illuknit.design.single_view import compile_single_view

    t = draw_heart(size).astype(np.int16)
    yarns = default_yarns(2)
    print(f"# single-view model (c), heart {size[0]}x{size[1]}: optimum vs push-button compiler")
    comp = compile_single_view(t, yarns=yarns)
    for alt in (False, True):
        problem = make_problem(t, None, n_yarns=2, kind="single", alternate_rows=alt)
        model = build_model(problem)
        t0 = time.perf_counter()
        sol = solve(model, solver="dp")
        dt = time.perf_counter() - t0
        pat = pattern_from_solution(problem, sol, yarns=yarns)
        err = int((can_see(pat, "A") != t).sum() + (can_see(pat, "B") != t).sum())
        kt, passes = _knit_numbers(pat)
        print(
            f"  model (c){' alternating rows' if alt else '                 '}  "
            f"{sol.status.value}  mismatched cells {err:>5}  ({100 * err / (2 * t.size):.1f}%)  "
            f"passes {passes}  {kt}  solve {1000 * dt:.0f} ms"
        )
    _, comp_cost = model.evaluate(values_from_pattern(model, comp.yarn, comp.raised))
    kt, passes = _knit_numbers(comp)
    print(
        f"  push-button compiler                 mismatched cells {comp_cost:>5}  "
        f"({100 * comp_cost / (2 * t.size):.1f}%)  passes {passes}  {kt}"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--time-limit", type=float, default=60.0)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--sections", default=",".join(SECTIONS))
    args = ap.parse_args()
    sections = [s.strip() for s in args.sections.split(",") if s.strip()]
    limit = 10.0 if args.quick else args.time_limit
    sizes = [(50, 50)] if args.quick else [(50, 50), (100, 100), (330, 200)]
    have = available_backends()
    print(
        f"# illuknit solver benchmark on {platform.processor() or platform.machine()}, limit {limit:g} s"
    )
    print("# targets: DP < 1 s at 330x200; RC2/CP-SAT optimal on (a) at 100x100 within 60 s")
    if "logical" in sections:
        w_a = KnitWeights()
        for rows, cols in sizes:
            for backend in ("dp", "cpsat", "rc2", "lsu"):
                if backend in have:
                    print(run("logical", rows, cols, backend, limit, w_a), flush=True)
    if "knit-aware" in sections:
        w_b = KnitWeights(view=4, color_change=1, transfer=1)
        for rows, cols in sizes[:2]:
            for backend in ("descent", "cpsat", "rc2"):
                if backend in have:
                    print(run("knit-aware", rows, cols, backend, limit, w_b), flush=True)
    if "sweep" in sections:
        sweep(limit / 3, sizes[0] if args.quick else (100, 100))
    if "single" in sections:
        single(sizes[0] if args.quick else (100, 100))


if __name__ == "__main__":
    main()
