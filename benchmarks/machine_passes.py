"""Machine passes: what illuknit reports against what the SWG machine really runs (issue 14).

For every bundled double-view instance (``instances/manifest.toml``) this designs three
mixed-colourwork patterns -- the tile pattern (``illuknit double``), a head-on pattern of view A on
a plain side (``illuknit headon``) and the exact MaxSAT optimum of model (a) (``illuknit solve``,
per-wale DP), plus the knit-aware model (b) with ``--knit-aware`` -- compiles each to knitout
(``illuknit.knit.knit_pattern``, what ``--knitout`` runs), converts it with the reference SWG
backend (``node <oracles>/swg/knitout-to-dat.js``; the ``.dat`` raster has one row per carriage
pass plus 19 fixed rows) and prints per program:

``reported``  passes illuknit reports (``knit.json``'s ``"passes"``)
``dat``       passes in the reference ``.dat`` -- what the machine knits
``today``     ``.dat`` passes measured once on main at commit 5c69a21 (2026-12-01), see TODAY
``bound``     illuknit's lower bound on passes
``float``     longest float in the program (needle slots crossed, illuknit's simulator), against
              the machine's float limit (``met`` when every program is within it)
``block``     blocking findings of ``illuknit check``
``min``       estimated knitting time in minutes (illuknit's time model on the machine passes)
``err``       logical error of views A / B in % (wrongly seen units, ``bench.metrics``)
``read``      readability of views A / B: correlation of the 30-degree render with its target
              (``design.measures.picture_scores``), so a design cannot win passes by a worse picture

Targets (issue 14): ``dat <= 0.5 x today`` on 3- and 4-yarn instances, ``<= 0.7 x today`` on
2-yarn ones; moonshot ``dat <= 1.2 x bound``; longest float <= the machine's float limit.

Run: ``python benchmarks/machine_passes.py [--all] [--knit-aware] [--jobs N] [--record]
[--machine NAME] [--model]``; ``--model`` also prints the passes
:func:`illuknit.formats.machine_passes` counts (the bench's count), which must equal ``dat``.
Without ``--all`` the paper-scale instances (no ``quick`` tag, except ``logos-4``, the only
4-yarn one) are left out. ``--record`` prints the measured ``.dat`` passes as a ``TODAY`` literal.
Needs ``node`` (Node.js 16+) and the reference backend (``--oracle``; by default ``swg/knitout-to-dat.js``
in ``ILLUKNIT_ORACLES``, else in ``shared/oracles`` beside the checkout).
"""

from __future__ import annotations

import argparse
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

ORACLES = Path(
    os.environ.get("ILLUKNIT_ORACLES") or Path(__file__).resolve().parents[2] / "shared" / "oracles"
)
DEFAULT_ORACLE = ORACLES / "swg" / "knitout-to-dat.js"

#: ``.dat`` passes of each (instance, design) on main at 5c69a21 (2026-12-01), before the
#: machine-aware scheduler: the baseline the issue's targets are relative to. Measured with
#: ``python benchmarks/machine_passes.py --all --knit-aware --record`` (generic540 bed).
TODAY: dict[tuple[str, str], int] = {
    ("plus-circle", "tiles"): 353,
    ("plus-circle", "headon"): 541,
    ("plus-circle", "dp"): 827,
    ("plus-circle", "knit-aware"): 719,
    ("heart-ecg", "tiles"): 757,
    ("heart-ecg", "headon"): 619,
    ("heart-ecg", "dp"): 1821,
    ("heart-ecg", "knit-aware"): 1519,
    ("illusion-knitting-small", "tiles"): 976,
    ("illusion-knitting-small", "headon"): 906,
    ("illusion-knitting-small", "dp"): 1115,
    ("illusion-knitting-small", "knit-aware"): 1917,
    ("heart-ecg-100", "tiles"): 2451,
    ("heart-ecg-100", "headon"): 1700,
    ("heart-ecg-100", "dp"): 9492,
    ("heart-ecg-100", "knit-aware"): 4475,
    ("illusion-knitting", "tiles"): 4431,
    ("illusion-knitting", "headon"): 5277,
    ("illusion-knitting", "dp"): 8546,
    ("illusion-knitting", "knit-aware"): 8724,
    ("coffee-chelsea-3", "tiles"): 2057,
    ("coffee-chelsea-3", "headon"): 2030,
    ("coffee-chelsea-3", "dp"): 6431,
    ("coffee-chelsea-3", "knit-aware"): 4679,
    ("logos-4", "tiles"): 2158,
    ("logos-4", "headon"): 2063,
    ("logos-4", "dp"): 6170,
    ("logos-4", "knit-aware"): 3833,
    ("astronaut-coffee-3", "tiles"): 27038,
    ("astronaut-coffee-3", "headon"): 26932,
    ("astronaut-coffee-3", "dp"): 71059,  # .dat header wrapped: 5523 + 65536
    ("astronaut-coffee-3", "knit-aware"): 63832,
}

#: Instances run without ``--all``.
DEFAULT_INSTANCES = ("quick", "logos-4")

#: Fixed raster rows of a SWG ``.dat`` beyond one row per carriage pass (oracles' README).
DAT_FIXED_ROWS = 19


@dataclass(frozen=True)
class Row:
    instance: str
    design: str
    yarns: int
    units: tuple[int, int]
    reported: int
    dat: int | None
    bound: int
    longest_float: int
    float_limit: int
    blocking: int
    error: str = ""
    seconds: float = 0.0
    model: int | None = None
    knit_minutes: float = 0.0
    view_error: tuple[float, float] = (0.0, 0.0)
    readability: tuple[float, float] = (0.0, 0.0)


def dat_passes(data: bytes) -> int:
    """Carriage passes of a SWG ``.dat``: raster height minus the fixed rows."""
    _xmin, ymin, _xmax, ymax = struct.unpack_from("<4H", data, 0)
    return ymax - ymin + 1 - DAT_FIXED_ROWS


#: The ``.dat`` header stores the raster height as uint16: the backend asserts (and only logs)
#: ``height < 0xffff`` and the stored value wraps. Such a program cannot go to the machine as one
#: file; the benchmark still counts its passes by undoing the wrap.
DAT_MAX_ROWS = 0x10000


def run_oracle(text: str, oracle: Path, *, at_least: int = 0) -> tuple[int | None, str]:
    """``(.dat passes, note)``, or ``(None, error)`` when the backend refuses the program.

    ``at_least`` (the passes the program itself has; the backend only adds passes) undoes the
    wrap of a raster taller than the header can hold, noted as ``"dat>65535 rows"``.
    """
    with tempfile.TemporaryDirectory() as tmp:
        k, dat = Path(tmp) / "program.k", Path(tmp) / "program.dat"
        k.write_text(text)
        proc = subprocess.run(
            ["node", str(oracle), str(k), str(dat)], capture_output=True, text=True, check=False
        )
        if proc.returncode != 0 or not dat.exists():
            last = (proc.stderr or proc.stdout).strip().splitlines()
            return None, (last[-1] if last else f"exit {proc.returncode}")[:80]
        passes = dat_passes(dat.read_bytes())
        if "Assertion failed" not in proc.stderr + proc.stdout:
            return passes, ""
        while passes < at_least:
            passes += DAT_MAX_ROWS
        return passes, "dat>65535 rows"


def design(instance: Any, kind: str) -> Any:
    """The pattern of ``instance`` by design ``kind`` (tiles / headon / dp / knit-aware)."""
    from illuknit.bench.instances import instance_targets
    from illuknit.bench.methods import get_method

    if kind == "headon":
        from illuknit.design.tiles.compile import compile_tiles
        from illuknit.design.tiles.headon import assign_headon

        t = instance_targets(instance)
        cands = assign_headon((t.a, t.palette), yarns=instance.yarns, candidates=1)
        return compile_tiles(cands[0])[0]
    pattern, _ = get_method(kind).run(instance, instance.time_limit)
    return pattern


def measure(
    instance: Any, kind: str, oracle: Path, machine_name: str, with_model: bool = False
) -> Row:
    from illuknit.check import check_knitout
    from illuknit.check.simulate import simulate_program
    from illuknit.core.machine import get_machine
    from illuknit.knitout import parse_knitout
    from illuknit.knitting import knit_pattern

    t0 = time.perf_counter()
    n_yarns = len(instance.yarns)
    units = (int(instance.size[0]), int(instance.size[1]))
    machine = get_machine(machine_name)
    try:
        pattern = design(instance, kind)
        # allowed, so the longest float is measured and printed against the target, not hidden
        # behind a refusal
        result = knit_pattern(pattern, machine=machine, allow_long_floats=True)
    except Exception as e:  # a design or scheduling failure is a row, not a crash
        return Row(instance.name, kind, n_yarns, units, 0, None, 0, 0, 0, 0, f"{e}"[:80])
    text = result.program
    sim = simulate_program(parse_knitout(text), max_racking=machine.max_racking)
    longest = max((f.length for f in sim.floats), default=0)
    report = check_knitout(text, machine=machine)
    dat, err = run_oracle(text, oracle, at_least=result.stats.passes)
    model = None
    if with_model:
        from illuknit.formats import machine_passes

        model = len(machine_passes(text))
    view_error, readability = picture_measures(instance, pattern)
    return Row(
        instance.name,
        kind,
        n_yarns,
        units,
        result.stats.passes,
        dat,
        result.stats.lower_bound,
        longest,
        machine.float_limit,
        len(report.blocking),
        err,
        time.perf_counter() - t0,
        model,
        result.time.seconds / 60,
        view_error,
        readability,
    )


def picture_measures(
    instance: Any, pattern: Any
) -> tuple[tuple[float, float], tuple[float, float]]:
    """(logical error of views A and B in %, readability of A and B) of ``pattern``."""
    from illuknit.bench.instances import instance_targets
    from illuknit.bench.metrics import logical_errors
    from illuknit.design.measures import angled_renders, picture_scores

    t = instance_targets(instance)
    err = logical_errors(pattern, t)
    renders, _ = angled_renders(pattern)
    sc = picture_scores(renders, t.rgb("A"), t.rgb("B"), double=True)
    read = (float(sc["render_corr_a"] or 0.0), float(sc["render_corr_b"] or 0.0))
    return (100 * err["A"], 100 * err["B"]), read


def _fmt_err(r: Row | None) -> str:
    return f"{r.view_error[0]:.1f}/{r.view_error[1]:.1f}%" if r else "-"


def _fmt_ratio(num: int | None, den: int | None) -> str:
    return f"{num / den:.2f}" if num and den else "-"


def print_table(rows: list[Row]) -> bool:
    """Print the table and the verdicts; True when every target is met."""
    print(
        f"{'instance':24} {'design':10} {'y':>1} {'units':>8} {'reported':>8} {'dat':>6} "
        f"{'rep/dat':>7} {'today':>6} {'dat/tdy':>7} {'target':>6} {'bound':>6} {'dat/bnd':>7} "
        f"{'float':>5} {'block':>5} {'min':>5} {'err A/B %':>11} {'read A/B':>9} {'s':>5}"
    )
    ok = True
    for r in rows:
        if r.error and r.dat is None and not r.reported:
            print(f"{r.instance:24} {r.design:10} {r.yarns:>1} failed: {r.error}")
            ok = False
            continue
        today = TODAY.get((r.instance, r.design))
        target = 0.5 if r.yarns >= 3 else 0.7
        met = r.dat is not None and today is not None and r.dat <= target * today
        ok &= met and r.longest_float <= r.float_limit and r.blocking == 0
        units = f"{r.units[0]}x{r.units[1]}"
        print(
            f"{r.instance:24} {r.design:10} {r.yarns:>1} {units:>8} {r.reported:>8} "
            f"{r.dat if r.dat is not None else 'REFUSED':>6} {_fmt_ratio(r.reported, r.dat):>7} "
            f"{today if today is not None else '-':>6} {_fmt_ratio(r.dat, today):>7} "
            f"{target:>6.1f} {r.bound:>6} {_fmt_ratio(r.dat, r.bound):>7} "
            f"{r.longest_float:>5} {r.blocking:>5} {r.knit_minutes:>5.0f} "
            f"{r.view_error[0]:>5.1f}/{r.view_error[1]:<5.1f} "
            f"{r.readability[0]:>4.2f}/{r.readability[1]:<4.2f} {r.seconds:>5.0f}"
            + (f"  {r.error}" if r.error else "")
            + (f"  model {r.model}" if r.model is not None else "")
        )
    measured = [r for r in rows if r.dat is not None]
    within = [r for r in measured if abs(r.reported - r.dat) <= 0.01 * r.dat]
    moon = [r for r in measured if r.bound and r.dat <= 1.2 * r.bound]
    short = [r for r in rows if r.longest_float <= r.float_limit and not r.error]
    limits = sorted({r.float_limit for r in rows})
    floats = "met" if len(short) == len(rows) else "not met"
    print(
        f"\nreported within 1% of the .dat: {len(within)}/{len(rows)}; "
        f"longest float <= limit ({'/'.join(map(str, limits))}): {len(short)}/{len(rows)}, "
        f"{floats}; "
        f"moonshot (dat <= 1.2 x bound): {len(moon)}/{len(rows)}; "
        f"all targets met: {'yes' if ok else 'no'}"
    )
    by = {(r.instance, r.design): r for r in rows}
    pairs = [(inst, r, by.get((inst, "dp"))) for (inst, d), r in by.items() if d == "knit-aware"]
    if pairs:
        won = [i for i, k, d in pairs if k.dat is not None and d and d.dat and k.dat < d.dat]
        detail = ", ".join(
            f"{i} {k.dat} vs {d.dat if d else '-'} (error {_fmt_err(k)} vs {_fmt_err(d)})"
            for i, k, d in pairs
        )
        print(
            f"knit-aware in fewer machine passes than the MaxSAT optimum (dp): "
            f"{len(won)}/{len(pairs)} ({detail})"
        )
    return ok


def _selected(include_all: bool) -> list[Any]:
    from illuknit.bench.instances import load_manifest

    out = []
    for inst in load_manifest().instances:
        if inst.kind != "double":
            continue
        if include_all or "quick" in inst.tags or inst.name in DEFAULT_INSTANCES:
            out.append(inst)
    return out


def _job(args: tuple[Any, str, Path, str, bool]) -> Row:
    return measure(*args)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--all", action="store_true", help="also the paper-scale instances")
    ap.add_argument(
        "--knit-aware", action="store_true", help="also the knit-aware model (CP-SAT, slow)"
    )
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--machine", default="generic540", help="machine preset to knit on")
    ap.add_argument(
        "--model",
        action="store_true",
        help="also count the passes with illuknit's own SWG model (illuknit.formats)",
    )
    ap.add_argument("--record", action="store_true", help="print the .dat passes as TODAY")
    ap.add_argument(
        "--oracle",
        type=Path,
        default=DEFAULT_ORACLE,
        help="path of the reference knitout-to-dat.js",
    )
    args = ap.parse_args(argv)
    if shutil.which("node") is None or not args.oracle.exists():
        print(f"needs node and the SWG backend ({args.oracle})", file=sys.stderr)
        return 2
    kinds = ["tiles", "headon", "dp"] + (["knit-aware"] if args.knit_aware else [])
    jobs = [
        (inst, kind, args.oracle, args.machine, args.model)
        for inst in _selected(args.all)
        for kind in kinds
    ]
    if args.jobs > 1:
        with ProcessPoolExecutor(args.jobs) as pool:
            rows = list(pool.map(_job, jobs))
    else:
        rows = [_job(j) for j in jobs]
    ok = print_table(rows)
    if args.record:
        print("TODAY = {")
        for r in rows:
            if r.dat is not None:
                print(f"    ({r.instance!r}, {r.design!r}): {r.dat},")
        print("}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
