"""Issue #16 target: ``--simplify`` raises the worse view's readability on at least half of the
bundled photo instances and lowers it on none.

For every bundled double-view instance whose pictures are photographs (``image = ...`` in
``instances/manifest.toml``; ``--all`` adds the drawn ones), the suggested edits of
:mod:`illuknit.design.tiles.simplify` are tried as ``illuknit double --simplify`` tries them
(:func:`~illuknit.design.tiles.simplify.review_edits`: the tile designs ``double`` searches per design
-- ``--pool``, default :data:`~illuknit.design.tiles.perception.DEFAULT_POOL` -- ranked by perception,
judged against the original pictures; a photograph may also be re-read with one colour fewer,
or one more while that stays within the instance's yarns). Printed: the worse-view readability
and worst ghosting before and after, and each edit's verdict.

    python benchmarks/simplify_edits.py [--all] [--pool 20]
"""

from __future__ import annotations

import argparse
import time

from illuknit.bench.instances import instance_targets, load_manifest
from illuknit.design.tiles.perception import DEFAULT_POOL, POOL_SECONDS
from illuknit.design.tiles.simplify import MIN_GAIN, review_edits
from illuknit.pictures.drawings import skimage_image


def _is_photo(inst) -> bool:
    return all("image" in spec for spec in inst.inputs.values())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--all", action="store_true", help="also the drawn double-view instances")
    ap.add_argument("--pool", type=int, default=DEFAULT_POOL, help="tile designs searched")
    args = ap.parse_args()
    insts = [i for i in load_manifest().instances if i.kind == "double"]
    if not args.all:
        insts = [i for i in insts if _is_photo(i)]
    print(
        f"{'instance':<24} {'before (read/ghost)':>20} {'after':>14}  edits (+ kept, - refused)  seconds"
    )
    photos = [i for i in insts if _is_photo(i)]
    raised: list[str] = []
    lowered: list[str] = []
    for inst in insts:
        t0 = time.perf_counter()
        t = instance_targets(inst)
        sources = None
        if _is_photo(inst):
            sources = [skimage_image(inst.inputs[v]["image"], inst.size) for v in ("A", "B")]
        review = review_edits(
            (t.a, t.palette),
            (t.b, t.palette),
            apply=True,
            targets=[t.rgb("A"), t.rgb("B")],
            sources=sources,
            max_colors=len(inst.yarns),
            source_yarns=inst.yarns,
            candidates=5,  # as `double` writes by default
            pool=args.pool,
            pool_seconds=POOL_SECONDS,
            yarns=inst.yarns,
        )
        results = review.results
        if not results:
            print(f"{inst.name:<24} {'-':>20} {'-':>14}  (no edit applies)")
            continue
        before = results[0].before
        after = next((r.after for r in reversed(results) if r.accepted), before)
        if after[0] > before[0] + MIN_GAIN:
            raised.append(inst.name)
        if after[0] < before[0] - 1e-9:
            lowered.append(inst.name)
        verdicts = " ".join(
            f"{'+' if r.accepted else '-'}{r.suggestion.name}({r.after[0]:.3f})" for r in results
        )
        print(
            f"{inst.name:<24} {before[0]:>12.3f}/{before[1]:.3f} {after[0]:>8.3f}/{after[1]:.3f}"
            f"  {verdicts}  {time.perf_counter() - t0:.1f}"
        )
    up = sum(i.name in raised for i in photos)
    down = sum(i.name in lowered for i in photos)
    if len(insts) > len(photos):
        print(f"all {len(insts)} instances: raised on {len(raised)}, lowered on {len(lowered)}")
    print(
        f"target (photo instances): raised on >= half ({up}/{len(photos)}), lowered on none "
        f"({down}) -> {'met' if up * 2 >= len(photos) and down == 0 else 'NOT met'}"
    )


if __name__ == "__main__":
    main()
