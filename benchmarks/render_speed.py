"""Renderer speed: forward render, value + gradient, and gradient-descent design.

Targets (renderer issue): forward render of 330 x 200 units < 50 ms; value + gradient < 300 ms;
200 optimisation steps on 100 x 100 units < 60 s on 2 cores. "330 x 200" is the paper's largest
piece (660 x 400 stitches); it is timed both as 200 rows x 330 wales and 330 rows x 200 wales.

    python benchmarks/render_speed.py
"""

from __future__ import annotations

import os
import time

import numpy as np

from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.design.render.grad import render_value_and_grad
from illuknit.design.render.optimise import optimise_design
from illuknit.design.render.params import RenderParams
from illuknit.design.render.raycast import render_pattern
from illuknit.pictures.drawings import draw_text


def best_of(fn, repeat=11):
    """Best wall-clock and best CPU time of ``repeat`` runs (CPU time shows the cost when other
    processes share the cores)."""
    walls, cpus = [], []
    for _ in range(repeat):
        t, c = time.perf_counter(), time.process_time()
        fn()
        walls.append(time.perf_counter() - t)
        cpus.append(time.process_time() - c)
    return min(walls), min(cpus)


def line(what: str, seconds: tuple[float, float] | float, target: float) -> None:
    wall, cpu = seconds if isinstance(seconds, tuple) else (seconds, None)
    ok = "ok" if wall < target else "SLOW"
    extra = f" (cpu {cpu * 1e3:.1f} ms)" if cpu is not None else ""
    print(f"{what:<50} {wall * 1e3:9.1f} ms{extra:<18} target < {target * 1e3:6.0f} ms  {ok}")


def main() -> None:
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    rng = np.random.default_rng(0)
    yarns = parse_yarns("#1b1b1b,#f4f0e8,#c8102e")
    params = RenderParams()
    for rows, cols in ((200, 330), (330, 200)):
        pattern = LogicalPattern(
            rng.integers(0, 3, (rows, cols)), rng.random((rows, cols)) < 0.4, yarns
        )
        t = best_of(lambda p=pattern: render_pattern(p, params=params, view="A"))
        line(f"forward render, one view, {rows} x {cols} (uint8 sRGB)", t, 0.050)
        h = params.flat_height + rng.random((rows, cols)) * params.relief
        col = rng.random((rows, cols, 3))
        target = rng.random((rows, cols, 3))
        t = best_of(
            lambda h=h, col=col, target=target: render_value_and_grad(h, col, target, params=params)
        )
        line(f"value + gradient, one view, {rows} x {cols}", t, 0.300)

    a = draw_text("ILLUSION", shape=(100, 100)).astype(int)
    b = draw_text("KNIT", shape=(100, 100)).astype(int)
    two = parse_yarns("#f4f0e8,#1b1b1b")
    t0, c0 = time.perf_counter(), time.process_time()
    res = optimise_design(a, b, two, params=params.with_angle(params.exact_angle), steps=200)
    t = (time.perf_counter() - t0, time.process_time() - c0)
    line("200 design steps (2 views each), 100 x 100", t, 60.0)
    for part in ("before", "after"):
        r = res.report[part]
        print(
            f"  {part:<6} binarisation: loss {r['loss']:.4f}, render error {r['render_error']:.4f}, "
            f"logical error {r['logical_error']:.3f}"
        )


if __name__ == "__main__":
    main()
