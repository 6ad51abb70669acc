"""The Kniterate's passes and floats: every bundled instance knitted with ``--machine kniterate``.

For every bundled instance (``instances/manifest.toml``) this designs the patterns a Kniterate
owner would knit -- the tile pattern (``illuknit double``) and a head-on pattern of view A
(``illuknit headon``) of each double-view instance, the push-button pattern of each single-view
one -- at a width that fits the Kniterate's bed (instances wider than its 123 units are scaled
down to 120 units wide, keeping their aspect), knits each for the Kniterate
(:func:`illuknit.knitting.knit_pattern`, what ``illuknit knit --machine kniterate`` runs), converts it
with the reference backend (``node <oracles>/kniterate/knitout-to-kcode.js``) and prints per
program:

``kc``        carriage passes of the reference ``.kc`` (its ``>>`` and ``<<`` rows): what the
              machine runs, waste section included
``before``    the same, measured on main at 318c044 (2026-12-03), before the yarns' entry into
              the piece was planned (see BEFORE); ``-`` where main refused the pattern
``kc/bef``    the ratio (target: at most ~1.02, the cost of the entry tucks)
``warn``      warnings of ``illuknit check`` (target 0)
``float``     longest float of the program as ``illuknit check`` measures it (needles crossed,
              the waste section's yarn-in tucks included; target <= the float limit, 20)
``same``      ``yes`` when ``knit``'s ``long_floats`` / ``longest_float`` equal ``check``'s
``block``     blocking findings of ``illuknit check`` (target 0)

Run: ``python benchmarks/kniterate_passes.py [--quick] [--jobs N] [--record] [--patterns DIR]``;
``--quick`` only the instances tagged quick; ``--record`` prints the measured ``.kc`` passes as a
``BEFORE`` literal; ``--patterns DIR`` reads each design's pattern from DIR (designing and saving
it there the first time), so that a run on another commit knits the very same patterns (the tile
search is time-limited and its pick varies a little under load). Needs ``node`` and the reference backend (``--oracle`` or ``ILLUKNIT_KNITERATE_ORACLE``;
default ``../shared/oracles/kniterate/knitout-to-kcode.js`` beside the checkout).
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
import warnings
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

# the same designs as the Shima pass benchmark beside this script
from machine_passes import design

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_ORACLE = ROOT.parent / "shared" / "oracles" / "kniterate" / "knitout-to-kcode.js"

#: Widest pattern in units the benchmark knits (the Kniterate's bed holds 123).
FIT_UNITS = 120

#: ``.kc`` passes of each (instance, design) on main at 318c044 (2026-12-03), measured with this
#: script's ``--record --patterns DIR`` on that commit; None: main refused the pattern (3-yarn
#: tile patterns whose later yarn found every carrier taken). The instances wider than the bed
#: are scaled to FIT_UNITS as here. Compare with ``--patterns`` on the same DIR.
BEFORE: dict[tuple[str, str], int | None] = {
    ("plus-circle", "tiles"): 493,
    ("plus-circle", "headon"): 533,
    ("heart-ecg", "tiles"): 663,
    ("heart-ecg", "headon"): 719,
    ("illusion-knitting-small", "tiles"): 893,
    ("illusion-knitting-small", "headon"): 883,
    ("heart-ecg-100", "tiles"): 1457,
    ("heart-ecg-100", "headon"): 1719,
    ("illusion-knitting", "tiles"): 1159,
    ("illusion-knitting", "headon"): 1163,
    ("coffee-chelsea-3", "tiles"): None,
    ("coffee-chelsea-3", "headon"): 1153,
    ("logos-4", "tiles"): 1171,
    ("logos-4", "headon"): 1195,
    ("astronaut-coffee-3", "tiles"): None,
    ("astronaut-coffee-3", "headon"): 3785,
    ("camera-single", "single"): 577,
    ("astronaut-single-3", "single"): 1429,
}


@dataclass(frozen=True)
class Row:
    instance: str
    design: str
    units: tuple[int, int]
    kc: int | None
    warnings: int
    blocking: int
    longest: int
    limit: int
    same: bool
    error: str = ""
    seconds: float = 0.0


def kc_passes(text: str, oracle: Path) -> tuple[int | None, str]:
    """``(.kc passes, "")``, or ``(None, error)`` when the backend refuses the program."""
    with tempfile.TemporaryDirectory() as tmp:
        k, kc = Path(tmp) / "program.k", Path(tmp) / "program.kc"
        k.write_text(text)
        proc = subprocess.run(
            ["node", str(oracle), str(k), str(kc)], capture_output=True, text=True, check=False
        )
        log = proc.stdout + proc.stderr
        if proc.returncode != 0 or "Assertion failed" in log or not kc.exists():
            last = log.strip().splitlines()
            return None, (last[-1] if last else f"exit {proc.returncode}")[:80]
        body = kc.read_text()
        return body.count("\n>>") + body.count("\n<<"), ""


def fitted(instance: Any) -> Any:
    """``instance`` scaled to at most FIT_UNITS units wide (aspect kept)."""
    rows, cols = instance.size
    if cols <= FIT_UNITS:
        return instance
    return replace(instance, size=(max(2, round(rows * FIT_UNITS / cols)), FIT_UNITS))


def pattern_for(instance: Any, kind: str, patterns: Path | None) -> Any:
    """The design's pattern, kept in (or read back from) ``patterns`` when given: the tile
    search is time-limited, so before/after comparisons knit the same saved patterns."""
    from illuknit.core.pattern import load_pattern, save_pattern

    if patterns is None:
        return design(instance, kind)
    path = patterns / f"{instance.name}.{kind}.json"
    if path.exists():
        return load_pattern(path)
    pattern = design(instance, kind)
    patterns.mkdir(parents=True, exist_ok=True)
    save_pattern(pattern, path)
    return pattern


def measure(instance: Any, kind: str, oracle: Path, patterns: Path | None = None) -> Row:
    from illuknit.check import check_knitout
    from illuknit.check.simulate import simulate_program
    from illuknit.core.machine import KNITERATE
    from illuknit.knitout.parse import parse_knitout
    from illuknit.knitting import knit_pattern

    t0 = time.perf_counter()
    inst = fitted(instance)
    units = (int(inst.size[0]), int(inst.size[1]))
    try:
        pattern = pattern_for(inst, kind, patterns)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # kept long floats are measured below, not hidden
            result = knit_pattern(pattern, machine=KNITERATE, allow_long_floats=True)
    except Exception as e:  # a design or scheduling failure is a row, not a crash
        return Row(inst.name, kind, units, None, 0, 0, 0, 0, False, f"{e}"[:120])
    report = check_knitout(result.text, machine=KNITERATE)
    warned = [f for f in report.findings if f.code == "long-float"]
    over = [int(f.message.split(" floats across ")[1].split()[0]) for f in warned]
    s = result.summary()
    same = s["long_floats"] == len(over) and s["longest_float"] == max(over, default=0)
    floats = simulate_program(parse_knitout(result.text)).floats  # the checker's floats
    longest = max((f.length for f in floats), default=0)
    kc, err = kc_passes(result.text, oracle)
    return Row(
        inst.name,
        kind,
        units,
        kc,
        sum(f.severity == "warning" for f in report.findings),
        len(report.blocking),
        longest,
        KNITERATE.float_limit,
        same,
        err,
        time.perf_counter() - t0,
    )


def print_table(rows: list[Row]) -> bool:
    """Print the table and the verdicts; True when every target is met."""
    print(
        f"{'instance':24} {'design':7} {'units':>8} {'kc':>6} {'before':>6} {'kc/bef':>6} "
        f"{'warn':>4} {'float':>5} {'same':>4} {'block':>5} {'s':>5}"
    )
    ok = True
    for r in rows:
        before = BEFORE.get((r.instance, r.design))
        ratio = f"{r.kc / before:.3f}" if r.kc and before else "-"
        met = not r.warnings and not r.blocking and r.same and r.longest <= r.limit
        ok &= met and r.kc is not None and (before is None or r.kc <= 1.02 * before)
        units = f"{r.units[0]}x{r.units[1]}"
        print(
            f"{r.instance:24} {r.design:7} {units:>8} {r.kc if r.kc is not None else 'REFUSED':>6} "
            f"{before if before is not None else '-':>6} {ratio:>6} {r.warnings:>4} "
            f"{r.longest:>5} {'yes' if r.same else 'NO':>4} {r.blocking:>5} {r.seconds:>5.0f}"
            + (f"  {r.error}" if r.error else "")
        )
    pairs: list[tuple[int, int]] = []
    for r in rows:
        before = BEFORE.get((r.instance, r.design))
        if r.kc is not None and before is not None:
            pairs.append((r.kc, before))
    total = sum(a for a, _ in pairs), sum(b for _, b in pairs)
    print(
        f"\nprograms: {len(rows)}; accepted by the reference backend: "
        f"{sum(r.kc is not None for r in rows)}; 0 warnings: {sum(not r.warnings for r in rows)}; "
        f"longest float <= limit: {sum(r.longest <= r.limit for r in rows)}; knit's floats = "
        f"check's: {sum(r.same for r in rows)}; .kc passes against before on {len(pairs)} "
        f"programs: {total[0]} / {total[1]} = {total[0] / max(1, total[1]):.4f}; "
        f"all targets met: {'yes' if ok else 'no'}"
    )
    return ok


def _selected(quick: bool) -> list[tuple[Any, str]]:
    from illuknit.bench.instances import load_manifest

    jobs = []
    for inst in load_manifest().instances:
        if quick and "quick" not in inst.tags:
            continue
        kinds = ["tiles", "headon"] if inst.kind == "double" else ["single"]
        jobs += [(inst, k) for k in kinds]
    return jobs


def _job(args: tuple[Any, str, Path, Path | None]) -> Row:
    return measure(*args)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="only the instances tagged quick")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--record", action="store_true", help="print the .kc passes as BEFORE")
    ap.add_argument(
        "--oracle",
        type=Path,
        default=Path(os.environ.get("ILLUKNIT_KNITERATE_ORACLE", DEFAULT_ORACLE)),
        help="path of the reference knitout-to-kcode.js",
    )
    ap.add_argument(
        "--patterns",
        type=Path,
        help="folder of saved patterns: read them from there, or design and save them there",
    )
    args = ap.parse_args(argv)
    if shutil.which("node") is None or not args.oracle.exists():
        print(f"needs node and the Kniterate backend ({args.oracle})", file=sys.stderr)
        return 2
    jobs = [(inst, kind, args.oracle, args.patterns) for inst, kind in _selected(args.quick)]
    if args.jobs > 1:
        with ProcessPoolExecutor(args.jobs) as pool:
            rows = list(pool.map(_job, jobs))
    else:
        rows = [_job(j) for j in jobs]
    ok = print_table(rows)
    if args.record:
        print("BEFORE = {")
        for r in rows:
            print(f"    ({r.instance!r}, {r.design!r}): {r.kc},")
        print("}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
