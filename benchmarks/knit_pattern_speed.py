"""knit_pattern at 660 x 400 stitches, before and after a change, in one run, with the text
parses counted.

The current checkout and a git ref (``--before``, default 862e583: before the program became
data) each knit the same deterministic pattern in a subprocess whose ``PYTHONPATH`` puts that
checkout first (the ref is checked out with ``git worktree add --detach`` under /tmp and removed
afterwards). In the subprocess every binding of ``parse_knitout`` in the loaded illuknit modules
is wrapped to count the knitout texts parsed inside ``knit_pattern``.

The pattern: 330 x 200 units (660 courses x 400 wales), two yarns in alternating rows (one
colour per course, so the course scheduler), 40 % bumps from a seeded generator. Printed: the
best of ``--repeat`` seconds for each side, the speed-up, the parses, and the seconds the after
side then takes to format its text at the file edge (``KnitResult.text``); CPU time too (the
process's, less shaken than the wall clock by a shared machine's load). The sides alternate. The Kniterate's bed
(252 needles) does not hold 400 wales; with ``--kniterate`` the same comparison runs on a
660 x 200-stitch pattern on it (what fits, waste section included).

Target (issue #36): 0 parses inside ``knit_pattern``, at least 1.5x faster end to end.

    python benchmarks/knit_pattern_speed.py [--before REF] [--repeat N] [--kniterate]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TARGET_SPEEDUP = 1.5

#: Run in the subprocess: knit the pattern ``repeat`` times, count the parses, print JSON.
CHILD = r"""
import json, sys, time, warnings
import numpy as np
import illuknit.check, illuknit.formats.dat, illuknit.formats.kc
import illuknit.formats.kc_passes, illuknit.formats.swg_passes, illuknit.knitting.carriage
import illuknit.knitting.pipeline, illuknit.knitout.parse
from illuknit.core.pattern import LogicalPattern, Yarn
from illuknit.knitting import knit_pattern

rows, cols, machine, repeat = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
original = illuknit.knitout.parse.parse_knitout
parses = [0]

def counted(*args, **kwargs):
    parses[0] += 1
    return original(*args, **kwargs)

for name, module in list(sys.modules.items()):
    if name.startswith("illuknit") and getattr(module, "parse_knitout", None) is original:
        module.parse_knitout = counted

yarns = (Yarn("dark", (27, 27, 27)), Yarn("light", (244, 240, 232)))
yarn = np.repeat((np.arange(rows) % 2)[:, None], cols, axis=1)
raised = np.random.default_rng(0).random((rows, cols)) < 0.4
pattern = LogicalPattern(yarn, raised, yarns)
times, cpu = [], []
warnings.simplefilter("ignore")
for _ in range(repeat):
    parses[0] = 0
    t, c = time.perf_counter(), time.process_time()
    result = knit_pattern(pattern, machine=machine, allow_long_floats=True)
    times.append(time.perf_counter() - t)
    cpu.append(time.process_time() - c)
t = time.perf_counter()
text = result.text
edge = time.perf_counter() - t
print(json.dumps({"seconds": min(times), "cpu": min(cpu), "parses": parses[0], "text_seconds": edge,
                  "lines": text.count("\n"), "chars": len(text)}))
"""


def run(checkout: Path, rows: int, cols: int, machine: str, repeat: int) -> dict[str, float]:
    """Knit in a subprocess with ``checkout`` first on the path."""
    env = {**os.environ, "PYTHONPATH": str(checkout)}
    out = subprocess.run(
        [sys.executable, "-c", CHILD, str(rows), str(cols), machine, str(repeat)],
        env=env,
        cwd=checkout,
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def compare(before: Path, rows: int, cols: int, machine: str, repeat: int) -> None:
    """Print one comparison: the two sides alternate ``repeat`` times (a shared machine's load
    then weighs on both alike); each side's best run is kept."""
    bs, as_ = [], []
    for _ in range(repeat):
        bs.append(run(before, rows, cols, machine, 1))
        as_.append(run(ROOT, rows, cols, machine, 1))
    b = min(bs, key=lambda r: r["seconds"]) | {"cpu": min(r["cpu"] for r in bs)}
    a = min(as_, key=lambda r: r["seconds"]) | {"cpu": min(r["cpu"] for r in as_)}
    same = "same" if (a["lines"], a["chars"]) == (b["lines"], b["chars"]) else "DIFFERENT"
    speedup = b["seconds"] / a["seconds"]
    print(f"{machine}, {2 * rows} x {2 * cols} stitches ({a['lines']} lines, {same} text size):")
    print(f"  before {b['seconds']:.2f} s, after {a['seconds']:.2f} s, speed-up {speedup:.2f}x")
    print(
        f"  CPU time: before {b['cpu']:.2f} s, after {a['cpu']:.2f} s, "
        f"speed-up {b['cpu'] / a['cpu']:.2f}x"
    )
    print(f"  parses inside knit_pattern: before {b['parses']}, after {a['parses']}")
    print(
        f"  after, formatting the text at the edge (KnitResult.text): {a['text_seconds']:.2f} s;"
        f" speed-up counting it {b['seconds'] / (a['seconds'] + a['text_seconds']):.2f}x"
    )
    for what, x in (("wall", speedup), ("CPU", b["cpu"] / a["cpu"])):
        ok = a["parses"] == 0 and x >= TARGET_SPEEDUP
        print(f"  target 0 parses and >= {TARGET_SPEEDUP}x ({what}): {'met' if ok else 'NOT met'}")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", default="862e583", help="git ref to compare with")
    ap.add_argument(
        "--repeat", type=int, default=2, help="alternating timed runs per side (best kept)"
    )
    ap.add_argument("--kniterate", action="store_true", help="also 660 x 200 on the Kniterate")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="knit-before-") as tmp:
        before = Path(tmp) / "checkout"
        subprocess.run(
            ["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(before), args.before],
            check=True,
        )
        try:
            compare(before, 330, 200, "generic540", args.repeat)
            if args.kniterate:
                compare(before, 330, 100, "kniterate", args.repeat)
            else:
                print("kniterate: its 252-needle bed does not hold 400 wales (--kniterate: 200)")
        finally:
            subprocess.run(
                ["git", "-C", str(ROOT), "worktree", "remove", "--force", str(before)], check=True
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
