"""Split bumps and tall bumps (docs/split-bumps.md): how the pictures read and what the machine
pays, on every bundled double-view instance.

For each instance (``instances/manifest.toml``, kind ``double``) this designs the tile pattern
``illuknit double`` makes by default (``today``) and the one it makes with ``--split-bumps``
(``split``), and measures four variants:

``today``  the tile design, plain bumps
``split``  the tile design whose bank holds split bumps, plain bumps
``tall``   today's tile design knitted with tall bumps (``KnitOptions.tall_bumps``) and rendered
           with the tall bump height (``RenderParams.with_tall_bumps``), seen from where a tall
           bump hides exactly one unit (``--tall-angle``: 42 degrees with the estimates), as
           plain bumps are seen from where they do (the bench's 30 degrees)
``both``   the split design knitted and rendered with tall bumps

and prints per variant:

``read A/B``   readability of views A / B: correlation of the render at ``--angle`` degrees with
               the target (``design.tiles.perception.measure_candidate``, as the ranking)
``ghost A/B``  visible ghosting of views A / B: how much of the render's light/dark variation
               follows the *other* picture (``CandidateMeasures.visible_ghosting``)
``split``      split bumps in the pattern (of ``bumps`` raised units)
``dat``        carriage passes in the ``.dat`` the reference SWG backend makes of the program
               (``node <oracles>/swg/knitout-to-dat.js``), on the ``--machine`` bed; ``-`` with
               ``--no-knit``, ``REFUSED`` when the backend refuses it
``x today``    ``dat`` over today's design's ``dat``

Target (docs/split-bumps.md): worst visible ghosting at least halved on the photo pairs (the
instances drawn from photographs: ``coffee-chelsea-3``, ``astronaut-coffee-3``) at no more than
1.2 x the machine passes of today's tile design. The verdict line says per instance whether the
variant met it, and where it does not help.

Every design and render uses the split share (``--share``, default the ``RenderParams``
estimate 0.75: the tile fills and the ranking count a split bump's far course with the rest) and
the tall bump height (the estimate of ``RenderParams.tall_height`` unless ``--tall-height``):
both are estimates until a swatch is measured, so ``--shares 0.9,1`` also designs the split
variant at other shares and prints its worst visible ghosting there, to show what the result
depends on (and their machine passes over today's).

Passes of the split and tall variants are the machine's only where the knitting side lowers
split bumps (``LogicalPattern.upper``) and knows ``KnitOptions.tall_bumps``; otherwise the
column says ``n/a`` (``tall``) or counts a program without the second yarn.

Run: ``python benchmarks/split_bumps.py [--all] [--no-knit] [--jobs N] [--machine NAME]
[--angle DEG] [--share S] [--shares LIST]``. Without ``--all`` the paper-scale instances (no
``quick`` tag, except ``logos-4``) are left out. Timings are wall-clock on a loaded 2-core
machine.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import shutil
import sys
import time
import warnings
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

# the reference backend runner of the Shima pass benchmark beside this script
from machine_passes import DEFAULT_ORACLE, run_oracle

#: The instances drawn from photographs (the target is stated for them).
PHOTO_PAIRS = ("coffee-chelsea-3", "astronaut-coffee-3")
#: Instances run without ``--all``.
DEFAULT_INSTANCES = ("quick", "logos-4")
VARIANTS = ("today", "split", "tall", "both")


@dataclass(frozen=True)
class Row:
    instance: str
    variant: str
    readability: tuple[float, float]
    ghosting: tuple[float, float]
    split: int
    bumps: int
    dat: int | None
    note: str = ""
    seconds: float = 0.0
    shares: tuple[tuple[float, float, int, int | None], ...] = ()
    share_notes: tuple[tuple[float, str], ...] = ()


def _design(instance: Any, split: bool, time_limit: float, share: float) -> Any:
    from illuknit.bench.methods import run_tiles

    pattern, _ = run_tiles(instance, time_limit, split_bumps=split, split_share=share)
    return pattern


def _measures(
    instance: Any, pattern: Any, params: Any, angle: float
) -> tuple[tuple[float, float], tuple[float, float]]:
    """(readability of A and B, visible ghosting of A and B), measured as the ranking measures
    (:func:`illuknit.design.tiles.perception.measure_candidate`) with ``params``."""
    from illuknit.bench.instances import instance_targets
    from illuknit.design.tiles.perception import measure_candidate

    t = instance_targets(instance)
    m = measure_candidate(pattern, [t.palette[t.a], t.palette[t.b]], angle=angle, params=params)
    read = tuple(0.0 if r is None or r != r else float(r) for r in m.readability)
    ghost = tuple(0.0 if g is None else float(g) for g in m.visible_ghosting)
    return (read[0], read[1]), (ghost[0], ghost[1])


def _knit(pattern: Any, tall: bool, machine: str, oracle: Path) -> tuple[int | None, str]:
    from illuknit.knit.options import KnitOptions
    from illuknit.knitting import knit_pattern

    if tall and "tall_bumps" not in {f.name for f in dataclasses.fields(KnitOptions)}:
        return None, "no KnitOptions.tall_bumps in this checkout"
    opts = KnitOptions(tall_bumps=True) if tall else KnitOptions()
    with warnings.catch_warnings():  # kept, and said in the note instead
        warnings.simplefilter("ignore")
        result = knit_pattern(pattern, machine=machine, options=opts, allow_long_floats=True)
    dat, note = run_oracle(result.program, oracle, at_least=result.stats.passes)
    long = result.schedule.long_floats
    if long:
        longest = max(f.length for f in long)
        note = ", ".join(filter(None, [note, f"{len(long)} floats > limit, longest {longest}"]))
    return dat, note


def measure(
    args: tuple[Any, str, Path, bool, tuple[float, float], Any, tuple[float, ...]],
) -> list[Row]:
    instance, machine, oracle, knit, (angle, tall_angle), params, shares = args
    rows = []
    designs = {}
    for split in (False, True):
        t0 = time.perf_counter()
        pattern = _design(instance, split, instance.time_limit, params.split_share)
        designs[split] = (pattern, time.perf_counter() - t0)
    for variant in VARIANTS:
        split = variant in ("split", "both")
        tall = variant in ("tall", "both")
        pattern, seconds = designs[split]
        t0 = time.perf_counter()
        p = params.with_tall_bumps() if tall else params
        read, ghost = _measures(instance, pattern, p, tall_angle if tall else angle)
        dat, note = (None, "") if not knit else _knit(pattern, tall, machine, oracle)
        extra: list[tuple[float, float, int, int | None]] = []
        share_notes: list[tuple[float, str]] = []
        if variant == "split":  # designed, seen and knitted at other shares
            for share in shares:
                q = dataclasses.replace(p, split_share=share)
                other = _design(instance, True, instance.time_limit, share)
                dat_s, note_s = _knit(other, False, machine, oracle) if knit else (None, "")
                if note_s:
                    share_notes.append((share, note_s))
                ghost_s = max(_measures(instance, other, q, angle)[1])
                extra.append((share, ghost_s, int(other.split.sum()), dat_s))
        rows.append(
            Row(
                instance.name,
                variant,
                read,
                ghost,
                int(pattern.split.sum()),
                int(pattern.raised.sum()),
                dat,
                note,
                seconds + time.perf_counter() - t0,
                tuple(extra),
                tuple(share_notes),
            )
        )
    return rows


def _ratio(a: int | None, b: int | None) -> str:
    return f"{a / b:.2f}" if a and b else "-"


def print_table(rows: list[Row]) -> None:
    print(
        f"{'instance':24} {'variant':7} {'read A/B':>11} {'ghost A/B':>11} {'split':>11} "
        f"{'dat':>7} {'x today':>7} {'s':>5}  at other shares: worst ghost (split bumps, x passes)"
    )
    by = {(r.instance, r.variant): r for r in rows}
    for r in rows:
        base = by[r.instance, "today"]
        dat = r.dat if r.dat is not None else ("n/a" if r.note else "-")
        note = r.note + "".join(f"; at {s:g}: {d}" for s, d in r.share_notes)
        shares = "  ".join(
            f"{s:g}: {g:.3f} ({n} split, {_ratio(d, base.dat)} x)" for s, g, n, d in r.shares
        )
        print(
            f"{r.instance:24} {r.variant:7} {r.readability[0]:>5.3f}/{r.readability[1]:<5.3f} "
            f"{r.ghosting[0]:>5.3f}/{r.ghosting[1]:<5.3f} {f'{r.split}/{r.bumps}':>11} "
            f"{dat:>7} {_ratio(r.dat, base.dat):>7} {r.seconds:>5.0f}  {shares}"
            + (f"  ({note.lstrip('; ')})" if note else "")
        )
    print()
    for inst in dict.fromkeys(r.instance for r in rows):
        base = by[inst, "today"]
        worst0 = max(base.ghosting)
        verdicts = []
        for v in VARIANTS[1:]:
            r = by[inst, v]
            worst = max(r.ghosting)
            halved = worst <= 0.5 * worst0
            passes = (
                "passes unmeasured"
                if r.dat is None or base.dat is None
                else f"{r.dat / base.dat:.2f} x passes"
            )
            cheap = r.dat is not None and base.dat is not None and r.dat <= 1.2 * base.dat
            met = "MET" if halved and cheap else ("helps" if worst < worst0 else "does not help")
            verdicts.append(f"{v}: ghost {worst0:.3f} -> {worst:.3f}, {passes}: {met}")
        tag = " (photo pair)" if inst in PHOTO_PAIRS else ""
        print(f"{inst}{tag}: " + "; ".join(verdicts))


def _selected(include_all: bool) -> list[Any]:
    from illuknit.bench.instances import load_manifest

    return [
        inst
        for inst in load_manifest().instances
        if inst.kind == "double"
        and (include_all or "quick" in inst.tags or inst.name in DEFAULT_INSTANCES)
    ]


def main(argv: list[str] | None = None) -> int:
    from illuknit.design.measures import RENDER_ANGLE
    from illuknit.design.render.params import RenderParams

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--all", action="store_true", help="also the paper-scale instances")
    ap.add_argument("--no-knit", action="store_true", help="design and render only")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--machine", default="generic540", help="machine preset to knit on")
    ap.add_argument("--angle", type=float, default=RENDER_ANGLE, help="viewing elevation")
    ap.add_argument(
        "--tall-angle",
        type=float,
        default=None,
        help="viewing elevation of the tall variants (default: where a tall bump hides one unit)",
    )
    ap.add_argument("--share", type=float, default=None, help="split share of the renders")
    ap.add_argument("--tall-height", type=float, default=None, help="tall bump height")
    ap.add_argument("--shares", default="", help="also the split designs' ghosting at these")
    ap.add_argument("--oracle", type=Path, default=DEFAULT_ORACLE)
    args = ap.parse_args(argv)
    knit = not args.no_knit
    if knit and (shutil.which("node") is None or not args.oracle.exists()):
        print(f"needs node and the SWG backend ({args.oracle}); or --no-knit", file=sys.stderr)
        return 2
    params = RenderParams()
    if args.share is not None:
        params = dataclasses.replace(params, split_share=args.share)
    if args.tall_height is not None:
        params = dataclasses.replace(params, tall_bump_height=args.tall_height)
    shares = tuple(float(s) for s in args.shares.split(",") if s.strip())
    tall_angle = args.tall_angle or round(params.with_tall_bumps().exact_angle, 1)
    print(
        f"renders at {args.angle:g} degrees (tall variants at {tall_angle:g}); split share "
        f"{params.split_share:g}, bump height {params.bump_height:g}, tall {params.tall_height:g} (estimates unless measured); "
        f"machine {args.machine}"
    )
    jobs = [
        (i, args.machine, args.oracle, knit, (args.angle, tall_angle), params, shares)
        for i in _selected(args.all)
    ]
    if args.jobs > 1:
        with ProcessPoolExecutor(args.jobs) as pool:
            rows = [r for rs in pool.map(measure, jobs) for r in rs]
    else:
        rows = [r for j in jobs for r in measure(j)]
    print_table(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
