"""Mixed-colourwork scheduler benchmark: passes against the lower bound, speed, and knit times.

Prints three tables (targets from the issue):

1. **passes / lower bound** on the bundled double-view instances (``instances/manifest.toml``,
   tile patterns; ``--all`` adds the paper-scale ones): target ratio <= 1.15. ``body`` is the
   same ratio for the pattern courses alone (cast-on and bind-off excluded); ``+swg`` is the pass
   count plus the kickback passes the SWG backend would add on its own; each instance is shown
   at the default catch spacing (once per unit row) and catching every course (the paper);
2. **speed**: scheduling + writing 660 x 400 stitches (both orientations): target < 10 s;
3. **tiles vs an unconstrained solver** (exact per-wale DP, the MaxSAT model's optimum) for the
   same pair: passes and estimated knitting time side by side (paper 8.3: 2 h vs 12 h).

Run: ``python benchmarks/knit_mixed.py [--all]``.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace

from illuknit.core.machine import get_machine
from illuknit.knit import estimate_knit_time, lower_to_stitches, write_knitout
from illuknit.knit.mixed import schedule_mixed
from illuknit.knit.options import KnitOptions
from illuknit.knit.timing import format_duration

#: The scheduler's defaults, keeping floats that stay long (they are counted, not refused).
KEEP = KnitOptions(allow_long_floats=True)


def pass_table(include_all: bool) -> list[float]:
    from illuknit.bench.instances import load_manifest
    from illuknit.bench.methods import run_tiles

    print("1. passes / lower bound (target <= 1.15), tile patterns of the bundled instances")
    head = (
        f"{'instance':26} {'units':>9} {'passes':>6} {'knit':>5} {'xfer':>5} {'moves':>5} "
        f"{'+swg':>5} {'bound':>6} {'ratio':>6} {'body':>6} {'plated':>6} {'carr':>4} {'time':>10}"
    )
    print(head)
    ratios = []
    for inst in load_manifest().instances:
        if inst.kind != "double" or (not include_all and "quick" not in inst.tags):
            continue
        pattern, _ = run_tiles(inst, inst.time_limit)
        n, m = pattern.shape
        machine = get_machine()
        machine = machine.with_width(max(machine.needles, 2 * m + 20))
        stitches = lower_to_stitches(pattern, machine=machine)
        for every in (2, 1):
            sch = schedule_mixed(
                stitches, machine=machine, options=replace(KEEP, catch_every=every)
            )
            s = sch.stats
            mixed = sch.mixed
            assert mixed is not None
            t = estimate_knit_time(sch)
            if every == 2:
                ratios.append(s.ratio)
            name = inst.name if every == 2 else "  (catch every course)"
            print(
                f"{name:26} {n:>4}x{m:<4} {s.passes:>6} {s.knit_passes:>5} "
                f"{s.transfer_passes:>5} {s.miss_passes:>5} "
                f"{s.passes + s.kickbacks:>5} {s.lower_bound:>6} {s.ratio:>6.3f} "
                f"{s.body_passes / s.body_lower_bound:>6.3f} {mixed.plated_stitches:>6} "
                f"{mixed.carriers:>4} {t!s:>10}"
            )
    if ratios:
        print(f"   worst ratio at the default catch spacing {max(ratios):.3f} (target <= 1.15)")
    return ratios


def speed_table() -> None:
    from illuknit.design.tiles.demos import text_pair_demo

    print("\n2. scheduling + writing 660 x 400 stitches (target < 10 s)")
    for rows, cols, needles in ((330, 200, 540), (200, 330, 700)):
        pattern = text_pair_demo((rows, cols), candidates=1).pattern
        machine = get_machine().with_width(needles)
        stitches = lower_to_stitches(pattern, machine=machine)
        t0 = time.perf_counter()
        sch = schedule_mixed(stitches, machine=machine, options=KEEP)
        t1 = time.perf_counter()
        text = write_knitout(sch)
        t2 = time.perf_counter()
        s = sch.stats
        print(
            f"   {rows}x{cols} units = {stitches.wales} wales x {stitches.courses} courses: "
            f"schedule {t1 - t0:.2f} s + write {t2 - t1:.2f} s = {t2 - t0:.2f} s; "
            f"{s.passes} passes, ratio {s.ratio:.3f}, {len(text) / 1e6:.1f} MB"
        )


def tiles_vs_solver() -> None:
    from illuknit.bench.instances import load_manifest
    from illuknit.bench.methods import get_method, run_tiles
    from illuknit.design.models.illusion_models import color_changes_per_course

    print("\n3. tile pattern vs unconstrained DP pattern of the same pair (estimated knit time)")
    print(
        f"   {'instance':26} {'method':6} {'changes/course':>14} {'passes':>6} {'bound':>6} "
        f"{'ratio':>6} {'time':>10}"
    )
    dp = get_method("dp")
    for inst in load_manifest().instances:
        if inst.kind != "double" or "quick" not in inst.tags:
            continue
        for name, runner in (("tiles", run_tiles), ("dp", dp.run)):
            pattern, _ = runner(inst, inst.time_limit)
            sch = schedule_mixed(lower_to_stitches(pattern), options=KEEP)
            s = sch.stats
            t = estimate_knit_time(sch)
            changes = color_changes_per_course(pattern).mean()
            print(
                f"   {inst.name:26} {name:6} {changes:>14.2f} {s.passes:>6} {s.lower_bound:>6} "
                f"{s.ratio:>6.3f} {format_duration(t.seconds):>10}"
            )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--all", action="store_true", help="include the paper-scale instances")
    args = parser.parse_args()
    pass_table(args.all)
    speed_table()
    tiles_vs_solver()


if __name__ == "__main__":
    main()
