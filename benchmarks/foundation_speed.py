"""can_see and single-view compile times at 330 x 200 units (the paper's largest piece).

Targets (foundation issue): can_see < 10 ms (all three views), single-view compile < 200 ms
(quantised picture -> pattern; also shown: the whole picture -> pattern path incl. resize and
k-means quantisation).

    python benchmarks/foundation_speed.py
"""

from __future__ import annotations

import time

import numpy as np

from illuknit.core.pattern import parse_yarns
from illuknit.core.views import can_see
from illuknit.design.single_view import compile_single_view, prepare_single_view_image
from illuknit.pictures.sizing import prepare_image


def best_of(fn, repeat=7):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> None:
    rows, cols = 200, 330
    rng = np.random.default_rng(0)
    yarns = parse_yarns("#1b1b1b,#f4f0e8")
    pic = rng.integers(0, 2, (rows, cols)).astype(np.int16)
    pattern = compile_single_view(pic, yarns=yarns)
    t_view = best_of(lambda: [can_see(pattern, v) for v in ("A", "B", "headon")])
    t_compile = best_of(lambda: compile_single_view(pic, yarns=yarns))
    photo = rng.random((400, 660, 3))
    t_full = best_of(
        lambda: prepare_single_view_image(photo, yarns=yarns, width=cols, height=rows), 3
    )
    t_quant = best_of(lambda: prepare_image(photo, width=cols, height=rows, n_colors=3), 3)
    print(f"size: {rows} x {cols} units")
    print(
        f"can_see, 3 views      {1e3 * t_view:8.2f} ms   target < 10 ms   {'OK' if t_view < 0.010 else 'MISSED'}"
    )
    print(
        f"single-view compile   {1e3 * t_compile:8.2f} ms   target < 200 ms  {'OK' if t_compile < 0.2 else 'MISSED'}"
    )
    print(
        f"picture -> quantised  {1e3 * t_quant:8.2f} ms   (resize + CIELAB k-means, 3 colours; no target)"
    )
    print(f"picture -> pattern    {1e3 * t_full:8.2f} ms   (no target)")


if __name__ == "__main__":
    main()
