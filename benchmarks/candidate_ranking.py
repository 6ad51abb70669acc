"""Issue #16 target: the default double-view candidate reads at least as well as every other.

For every bundled double-view instance (``instances/manifest.toml``; ``--small`` leaves out
the 330 x 200 piece) five tile candidates are assigned, compiled, rendered and ranked as
``illuknit double`` ranks them by default (:func:`illuknit.tiles.perception.rank_designs`).
Printed per instance: the worse-view readability, contrast and worst ghosting of the default
candidate, of the candidate the assignment's score alone would have picked, and of the best
other candidate; and whether the default reads at least as well (worse-view readability, then
ghosting) as every other candidate written.

    python benchmarks/candidate_ranking.py [--small] [--candidates 5]
"""

from __future__ import annotations

import argparse
import time

from illuknit.bench.instances import instance_targets, load_manifest
from illuknit.tiles.assign import assign_tiles
from illuknit.tiles.perception import rank_designs


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--small", action="store_true", help="leave out the 330 x 200 piece")
    ap.add_argument("--candidates", type=int, default=5)
    args = ap.parse_args()
    insts = [i for i in load_manifest().instances if i.kind == "double"]
    if args.small:
        insts = [i for i in insts if i.size[0] * i.size[1] <= 20_000]
    print(
        f"{'instance':<26} {'default (read/contr/ghost)':>27} {'score pick':>19} "
        f"{'best other read':>15}  at least as well?  seconds"
    )
    failed = []
    for inst in insts:
        t0 = time.perf_counter()
        t = instance_targets(inst)
        cands = assign_tiles(
            (t.a, t.palette), (t.b, t.palette), yarns=inst.yarns, candidates=args.candidates
        )
        ranked = rank_designs(cands, [t.rgb("A"), t.rgb("B")])
        best, others = ranked[0], ranked[1:]
        m = best.measures
        score_pick = next(r for r in ranked if r.score_rank == 1).measures
        top_other = max((r.measures.worse_readability for r in others), default=float("nan"))
        ok = all(
            (m.worse_readability, -m.worst_ghosting)
            >= (r.measures.worse_readability, -r.measures.worst_ghosting)
            for r in others
        )
        if not ok:
            failed.append(inst.name)
        print(
            f"{inst.name:<26} {m.worse_readability:>9.3f}/{m.worse_contrast:.3f}/{m.worst_ghosting:.3f}"
            f" {score_pick.worse_readability:>9.3f}/{score_pick.worst_ghosting:.3f}"
            f" {top_other:>15.3f}  {'yes' if ok else 'NO':>17}  {time.perf_counter() - t0:7.1f}"
        )
    verdict = "met" if not failed else f"NOT met on {', '.join(failed)}"
    print(f"target: the default reads at least as well as every other candidate -> {verdict}")


if __name__ == "__main__":
    main()
