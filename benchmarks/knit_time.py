"""Knitting time: the time model against the paper's two measured knits.

The paper (section 9) knitted on a 7-gauge Shima SWG091N2 and measured "between 50 minutes (ECG
pulse and heart, 200 x 200 stitches) to ten hours (Van Gogh, 660 x 400 stitches)". This script
designs the bundled pieces of those sizes with tiles (what ``illuknit double`` writes):
``heart-ecg-100`` (the paper's Fig. 18 (a) at full size) and ``astronaut-coffee-3`` (two photos
at the Van Gogh's size and 3 yarns: the Van Gogh paintings are not bundled), knits each for the
``generic540`` bed (the SWG091N2 as the reference backend models it, 540 needles: 400 stitches
fit no physical 252-needle SWG091N2) and prints per piece:

``passes``   the machine's carriage passes (the SWG backend's, as in its ``.dat``; transfers)
``model``    illuknit's estimate (:mod:`illuknit.knit.timing`) and its range from the spread of
             the documented carriage speeds and overrun
``bind-off`` of the estimate, the chain bind-off
``measured`` the paper's time; ``est/meas`` the ratio
``before``   the former untuned model (1.5 s a pass + 0.01 s a needle crossed)

then the out-of-sample check: the pass overhead fitted to one measured knit
(:func:`illuknit.knit.timing.calibrate_timing`, what ``illuknit calibrate time`` does) predicting
the other. The heart / ECG also fits the Kniterate (252 needles): its estimate on the ``.kc``'s
passes (waste section included) is printed too, unmeasured.

Run: ``python benchmarks/knit_time.py [--patterns DIR]``; ``--patterns DIR`` reads each design
from DIR (designing and saving it there the first time), so runs on other commits knit the very
same patterns (the tile search is time-limited and its pick varies a little under load).
"""

from __future__ import annotations

import argparse
import time
import warnings
from dataclasses import replace
from pathlib import Path

#: The paper's measured knitting times (section 9), in seconds, by the bundled piece of that size.
MEASURED = {
    "heart-ecg-100": ("heart / ECG, 200 x 200 sts", 50 * 60.0),
    "astronaut-coffee-3": ("Van Gogh size, 400 x 660 sts", 10 * 3600.0),
}


def pattern_of(name: str, patterns: Path | None):
    from illuknit.bench.instances import load_manifest, select_instances
    from illuknit.bench.methods import get_method
    from illuknit.core.pattern import load_pattern, save_pattern

    saved = patterns / f"{name}.json" if patterns else None
    if saved is not None and saved.exists():
        return load_pattern(saved)
    inst = select_instances(load_manifest(), name)[0]
    pattern, _ = get_method("tiles").run(inst, inst.time_limit)
    if saved is not None:
        saved.parent.mkdir(parents=True, exist_ok=True)
        save_pattern(pattern, saved)
    return pattern


def fmt(seconds: float) -> str:
    from illuknit.knit.timing import format_duration

    return format_duration(seconds)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--patterns", type=Path, default=None)
    args = ap.parse_args()

    from illuknit.core.machine import get_machine
    from illuknit.knit.timing import calibrate_timing, run_seconds
    from illuknit.knitting import knit_pattern
    from illuknit.knitting.stats import program_run

    bed = get_machine("generic540")
    before = replace(bed, seconds_per_needle=0.01, seconds_per_turn=1.5)
    print(f"bed: generic540 ({bed.description}); time model: {bed.timing.source}")
    print(
        f"{'piece':30} {'passes (xfer)':>14} {'model':>12} {'range':>26} {'bind-off':>14} "
        f"{'measured':>10} {'est/meas':>8} {'before':>12}"
    )
    runs = {}
    for name, (label, measured) in MEASURED.items():
        t0 = time.perf_counter()
        pattern = pattern_of(name, args.patterns)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = knit_pattern(pattern, machine=bed, allow_long_floats=True)
        run = program_run(result.text, bed)
        runs[name] = (run, measured, label, pattern)
        t = result.time
        share = 100 * t.bind_off_seconds / t.seconds
        print(
            f"{label:30} {run.passes:>7} ({sum(run.transfers):>4}) {fmt(t.seconds):>12} "
            f"{fmt(t.low_seconds) + ' - ' + fmt(t.high_seconds):>26} "
            f"{fmt(t.bind_off_seconds):>9} {share:3.0f}% {fmt(measured):>10} "
            f"{t.seconds / measured:8.2f} {fmt(run_seconds(run, before)):>12}"
            f"   ({time.perf_counter() - t0:.0f} s)"
        )
    print("\nout of sample: the pass overhead fitted to one measured knit predicts the other")
    for fit_on, (run, measured, label, _) in runs.items():
        fit = calibrate_timing(run, measured, bed, what=label)
        for other, (orun, omeasured, olabel, _) in runs.items():
            if other == fit_on:
                continue
            pred = run_seconds(orun, fit.machine)
            lo = run_seconds(orun, fit.machine, end="fast")
            hi = run_seconds(orun, fit.machine, end="slow")
            print(
                f"  fitted on {label} ({fit.machine.timing.pass_overhead_s:.2f} s a pass): "
                f"{olabel} {fmt(pred)} ({fmt(lo)} - {fmt(hi)}) against {fmt(omeasured)} "
                f"measured, ratio {pred / omeasured:.2f}"
            )
    knit = get_machine("kniterate")
    _, _, label, pattern = runs["heart-ecg-100"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = knit_pattern(pattern, machine=knit, allow_long_floats=True)
    from illuknit.outputs.machine_sheet import machine_sheet

    s = machine_sheet(result, name="heart.kc").summary
    print(
        f"\nKniterate (252 needles), {label}: {s['machine_passes']} passes of its .kc, "
        f"{s['machine_time']} ({s['machine_time_range']}), of which the bind-off "
        f"{fmt(s['machine_bind_off_time_seconds'])}; unmeasured ({knit.timing.source})"
    )


if __name__ == "__main__":
    main()
