"""Which measure should rank tile designs: the ranking's readability against the candidates.

For every bundled double-view instance (``instances/manifest.toml``; ``--small`` leaves out the
330 x 200 piece), and for the head-on design of each instance's first picture, the designs are
made as ``illuknit double`` / ``headon`` make them (:func:`illuknit.pipeline.stages.design_double`
/ :func:`~illuknit.pipeline.stages.design_headon`, the default pool and ranking) and every
candidate written is judged by three measures, on the worse view:

* ``ranking``: the perceptual score the candidates are ranked by (readability: correlation of
  luminance blurred by the fixed 1.5 units, less the contrast shortfall);
* ``eye``: the same correlation at what a 20/20 eye resolves from ``--distance`` metres
  (:func:`~illuknit.design.tiles.perception.eye_blur_units` at 7 stitches per inch);
* ``ms-ssim``: multi-scale SSIM in CIELAB at that blur (:func:`illuknit.design.measures.multiscale_ssim`).

Printed per instance: each measure's value for the default and for the best other candidate
written, and whether the default is at least as good by it; then the candidate each measure
would make the default. ``--pictures DIR`` writes, per instance where a measure disagrees with
the ranking, the pictures and side A / side B (or head-on / side) at 30 degrees of the default
and of each disagreeing pick, one row each, for a person to judge (docs/tiles.md shows them).

    python benchmarks/measure_choice.py [--small] [--distance 3] [--pictures DIR]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

import numpy as np

from illuknit.bench.instances import instance_targets, load_manifest
from illuknit.design.measures import angled_renders, multiscale_ssim, render_correlation
from illuknit.design.tiles.perception import eye_blur_units
from illuknit.pipeline.stages import design_double, design_headon

MEASURES = ("ranking", "eye", "ms-ssim")


def _float(img: Any) -> np.ndarray:
    a = np.asarray(img)
    return a.astype(np.float64) / 255.0 if a.dtype == np.uint8 else a.astype(np.float64)


def judge(design: Any, sigma: float) -> list[dict[str, float]]:
    """Per candidate written: the worse view's value by each measure (higher is better)."""
    targets = [_float(t) for t in design.targets]
    # which render each view is seen in: a head-on design's side is seen from both ends
    seen = {"A": ["A"], "B": ["B"], "headon": ["headon"], "side": ["A", "B"]}
    out = []
    for d in design.designs:
        renders, _ = angled_renders(d.pattern)
        pairs = [
            (renders[r], t) for v, t in zip(design.views, targets, strict=True) for r in seen[v]
        ]
        plain = [float(np.ptp(t)) < 1e-9 for _, t in pairs]
        eye = [
            render_correlation(r, t, sigma=sigma)
            for (r, t), p in zip(pairs, plain, strict=True)
            if not p
        ]
        out.append(
            {
                "ranking": d.measures.perceptual_score,
                "eye": min(eye, default=float("nan")),
                "ms-ssim": min(multiscale_ssim(r, t, sigma=sigma) for r, t in pairs),
            }
        )
    return out


def picture_rows(design: Any, picks: list[int], path: Path, scale: int = 4) -> None:
    """The pictures, then the two views of each picked candidate at 30 degrees, one row each."""
    from illuknit.design.render.raycast import render_pattern
    from illuknit.outputs.previews import save_png, upscale

    def side_by_side(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        gap = np.full((a.shape[0], 2 * scale, 3), 255, np.uint8)
        return np.concatenate([a, gap, b], axis=1)

    pics = [np.asarray(upscale(np.asarray(t, np.uint8), scale)) for t in design.targets]
    rows = [side_by_side(*pics)]
    views = ("A", "B") if design.mode == "double" else ("headon", "A")
    for k in picks:
        p = design.designs[k].pattern
        ims = [
            np.repeat(render_pattern(p, view=v, angle=30.0, supersample=scale), scale, axis=1)
            for v in views
        ]
        rows.append(side_by_side(*ims))
    gap = np.full((2 * scale, rows[0].shape[1], 3), 255, np.uint8)
    sheet = [r for row in rows for r in (row, gap)][:-1]
    save_png(np.concatenate(sheet, axis=0), path)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--small", action="store_true", help="leave out the 330 x 200 piece")
    ap.add_argument("--distance", type=float, default=3.0, help="viewing distance (m)")
    ap.add_argument("--pictures", type=Path, help="write the disagreements' pictures here")
    args = ap.parse_args()
    sigma = eye_blur_units(args.distance, gauge=7.0)
    insts = [i for i in load_manifest().instances if i.kind == "double"]
    if args.small:
        insts = [i for i in insts if i.size[0] * i.size[1] <= 20_000]
    print(
        f"worse view of the default / of the best other candidate written, by each measure "
        f"(eye and ms-ssim from {args.distance:g} m: blur {sigma:.3f} units); "
        "'ok' = the default is at least as good"
    )
    head = "  ".join(f"{m:>20}" for m in MEASURES)
    print(f"{'instance':<30} {head}  {'pick by eye, ms-ssim':>20}  seconds")
    failed: dict[str, list[str]] = {m: [] for m in MEASURES}
    for inst in insts:
        t = instance_targets(inst)
        a = np.round(_float(t.rgb("A")) * 255).astype(np.uint8)
        b = np.round(_float(t.rgb("B")) * 255).astype(np.uint8)
        kw: dict[str, Any] = dict(n_colors=len(inst.yarns), yarns=inst.yarns, width=inst.size[1])
        for label, pictures in ((inst.name, (a, b)), (f"{inst.name} head-on", (a,))):
            t0 = time.perf_counter()
            design = (
                design_double(*pictures, **kw) if len(pictures) == 2 else design_headon(a, **kw)
            )
            values = judge(design, sigma)
            cells = []
            for m in MEASURES:
                best_other = max((v[m] for v in values[1:]), default=float("nan"))
                ok = all(values[0][m] >= v[m] for v in values[1:])
                if not ok:
                    failed[m].append(label)
                cells.append(f"{values[0][m]:.3f} / {best_other:.3f} {'ok' if ok else 'NO':>3}")
            picks = [
                max(range(len(values)), key=lambda k: values[k][m]) for m in ("eye", "ms-ssim")
            ]
            print(
                f"{label:<30} {'  '.join(f'{c:>20}' for c in cells)}  "
                f"{', '.join(str(p + 1) for p in picks):>20}  {time.perf_counter() - t0:7.1f}"
            )
            if args.pictures is not None and any(picks):
                shown = [0, *sorted({p for p in picks if p})]
                name = label.replace(" ", "_")
                picture_rows(design, shown, args.pictures / f"measure_{name}.png")
                print(f"{'':<30} pictures: candidates {', '.join(str(k + 1) for k in shown)}")
    for m in MEASURES:
        verdict = "met" if not failed[m] else f"NOT met on {', '.join(failed[m])}"
        print(f"by {m}: the default is at least as good as every other candidate -> {verdict}")


if __name__ == "__main__":
    main()
