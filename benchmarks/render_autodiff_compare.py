"""Hand-written VJP (numpy) vs PyTorch autograd on the same renderer: agreement and speed.

Why this exists: docs/render.md explains why the renderer's gradient is written by hand instead of
using an autodiff library as an optional extra. This script checks the claim: it re-implements the
view-A forward pass in PyTorch (float64, CPU), lets autograd differentiate it, checks that both
gradients agree, and times value + gradient of both at 330 x 200 units. It needs PyTorch
(``pip install torch``), which illuknit itself does not depend on; without it the script says so.

    python benchmarks/render_autodiff_compare.py
"""

from __future__ import annotations

import os
import time

import numpy as np

from illuknit.design.render.grad import render_value_and_grad
from illuknit.design.render.params import RenderParams


def torch_value_and_grad(torch, h_np, col_np, tgt_np, params: RenderParams):
    """The same geometry as illuknit.design.render.raycast, view A, supersample 1, in torch."""
    th = np.radians(params.theta)
    sin, cos = float(np.sin(th)), float(np.cos(th))
    h = torch.tensor(h_np, requires_grad=True)
    col = torch.tensor(col_np, requires_grad=True)
    n, m = h.shape
    ls = params.unit_length * sin
    a = (torch.arange(n, dtype=torch.float64) * ls)[:, None]
    e = a + h * cos
    b = e + ls
    c = torch.cummax(b, dim=0).values
    cprev = torch.cat([torch.zeros(1, m, dtype=torch.float64), c[:-1]], dim=0)
    d = torch.maximum(e, cprev)
    w = params.shading * (d - cprev) + (c - d)
    g = torch.cat(
        [torch.zeros(1, m, 3, dtype=torch.float64), torch.cumsum(col * w[..., None], dim=0)], dim=0
    )
    cc = torch.cat([torch.zeros(1, m, dtype=torch.float64), c], dim=0)
    p = params.flat_height * cos + torch.arange(n + 1, dtype=torch.float64) * ls
    unit = torch.searchsorted(cc.T.contiguous(), p.expand(m, n + 1).contiguous(), right=True).T - 1
    unit = unit.clamp(0, n - 1)
    pp = p[:, None]
    dj = torch.gather(d, 0, unit)
    phi = params.shading * (torch.minimum(pp, dj) - torch.gather(cprev, 0, unit)) + torch.clamp(
        pp - dj, min=0
    )
    idx3 = unit[..., None].expand(-1, -1, 3)
    f = torch.gather(g, 0, idx3) + torch.gather(col, 0, idx3) * phi[..., None]
    img = (f[1:] - f[:-1]) / ls
    loss = ((img - torch.tensor(tgt_np)) ** 2).mean()
    loss.backward()
    return float(loss.detach()), h.grad.numpy(), col.grad.numpy()


def best_of(fn, repeat=7):
    walls = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        walls.append(time.perf_counter() - t)
    return min(walls)


def main() -> None:
    try:
        import torch
    except ImportError:
        print("PyTorch is not installed; nothing to compare (pip install torch)")
        return
    torch.set_num_threads(2)
    print(
        f"torch {torch.__version__}, load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores"
    )
    rng = np.random.default_rng(0)
    params = RenderParams(theta=28, shading=0.8)
    n, m = 200, 330
    h = params.flat_height + rng.random((n, m)) * params.relief
    col = rng.random((n, m, 3))
    tgt = rng.random((n, m, 3))
    l1, _, gh1, gc1 = render_value_and_grad(h, col, tgt, params=params)
    l2, gh2, gc2 = torch_value_and_grad(torch, h, col, tgt, params)
    print(
        f"loss differs by {abs(l1 - l2):.1e}; gradients by {np.abs(gh1 - gh2).max():.1e} (heights), "
        f"{np.abs(gc1 - gc2).max():.1e} (colours)"
    )
    t_np = best_of(lambda: render_value_and_grad(h, col, tgt, params=params))
    t_torch = best_of(lambda: torch_value_and_grad(torch, h, col, tgt, params))
    print(
        f"value + gradient, {n} x {m}: numpy hand-written {t_np * 1e3:.1f} ms, torch autograd {t_torch * 1e3:.1f} ms"
    )


if __name__ == "__main__":
    main()
