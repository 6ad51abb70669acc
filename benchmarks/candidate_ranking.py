"""Issue #16 target: the default double-view candidate reads at least as well as every other.

For every bundled double-view instance (``instances/manifest.toml``; ``--small`` leaves out
the 330 x 200 piece) the tile designs ``illuknit double`` searches by default are assigned
(``--pool``, default :data:`~illuknit.design.tiles.perception.DEFAULT_POOL`), compiled, rendered and
ranked as it ranks them (:func:`illuknit.design.tiles.perception.rank_designs`), and the best
``--candidates`` are the ones written. Printed per instance: the worse-view readability,
contrast, worst ghosting and how much of it shows (visible ghosting) of the default; the
default's readability when only ``--candidates`` designs are searched (what the pool gains); the
readability and ghosting of the design the assignment's score alone would have picked, and of
the best-reading other candidate written; and whether the default reads at least as well
(worse-view readability, then ghosting) as every other candidate written.

    python benchmarks/candidate_ranking.py [--small] [--candidates 5] [--pool 20]
"""

from __future__ import annotations

import argparse
import time
from typing import Any

from illuknit.bench.instances import instance_targets, load_manifest
from illuknit.design.tiles.assign import assign_tiles
from illuknit.design.tiles.perception import (
    DEFAULT_POOL,
    POOL_SECONDS,
    CandidateMeasures,
    RankedCandidate,
    rank_designs,
)


def _read(m: CandidateMeasures) -> str:
    return f"{m.worse_readability:.3f}/{m.worst_ghosting:.3f}"


def _written(inst: Any, t: Any, candidates: int, pool: int) -> tuple[int, list[RankedCandidate]]:
    """How many designs were searched, and the ones written, best first."""
    found = assign_tiles(
        (t.a, t.palette),
        (t.b, t.palette),
        yarns=inst.yarns,
        candidates=candidates,
        pool=pool,
        pool_seconds=POOL_SECONDS,
    )
    return len(found), rank_designs(found, [t.rgb("A"), t.rgb("B")], keep=candidates)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--small", action="store_true", help="leave out the 330 x 200 piece")
    ap.add_argument("--candidates", type=int, default=5, help="candidates written")
    ap.add_argument("--pool", type=int, default=DEFAULT_POOL, help="tile designs searched")
    args = ap.parse_args()
    insts = [i for i in load_manifest().instances if i.kind == "double"]
    if args.small:
        insts = [i for i in insts if i.size[0] * i.size[1] <= 20_000]
    print(
        f"searching {args.pool} tile designs (past {args.candidates} within {POOL_SECONDS:g} s), "
        f"writing the best {args.candidates}; readability/contrast/ghosting (visible ghosting)"
    )
    print(
        f"{'instance':<24} {'searched':>8} {'default':>27} {'searching 5':>11} "
        f"{'score pick':>11} {'best other':>11}  at least as well?  seconds"
    )
    failed = []
    for inst in insts:
        t0 = time.perf_counter()
        t = instance_targets(inst)

        searched, ranked = _written(inst, t, args.candidates, args.pool)
        narrow_ranked = _written(inst, t, args.candidates, args.candidates)[1]
        narrow = narrow_ranked[0].measures
        best, others = ranked[0], ranked[1:]
        m = best.measures
        score_pick = next(r for r in narrow_ranked if r.score_rank == 1).measures
        top_other = max(others, key=lambda r: r.measures.worse_readability, default=None)
        ok = all(
            (m.worse_readability, -m.worst_ghosting)
            >= (r.measures.worse_readability, -r.measures.worst_ghosting)
            for r in others
        )
        if not ok:
            failed.append(inst.name)
        default = (
            f"{m.worse_readability:.3f}/{m.worse_contrast:.3f}/{m.worst_ghosting:.3f}"
            f" ({m.worst_visible_ghosting:.3f})"
        )
        other = "-" if top_other is None else _read(top_other.measures)
        print(
            f"{inst.name:<24} {searched:>8} {default:>27} {narrow.worse_readability:>11.3f} "
            f"{_read(score_pick):>11} {other:>11}  {'yes' if ok else 'NO':>17}  "
            f"{time.perf_counter() - t0:7.1f}"
        )
    verdict = "met" if not failed else f"NOT met on {', '.join(failed)}"
    print(f"target: the default reads at least as well as every other candidate -> {verdict}")


if __name__ == "__main__":
    main()
