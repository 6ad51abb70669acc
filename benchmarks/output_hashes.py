"""Fingerprint of what the CLI writes: sha256 of every file a fixed set of commands writes.

A change that should not change any output (moving modules, splitting functions, renaming) is
checked by running this before and after and comparing the two listings (``diff``). The commands
cover every writer: the demo, a single-view design, double-view designs knitted for two machines
(knitout, Shima ``.dat``, Kniterate ``.kc``), a head-on design, a constraint solve, ``knit`` to each
machine format, ``view`` and ``tiles``. The input pictures are drawn here with Pillow, so nothing
depends on the package's own drawing code.

Paths and clocks differ between runs and are blanked before hashing: the folder the run wrote
into and the checkout it ran from (pattern files record the pictures' resolved paths; the demo's
picture is in the checkout), and the solver's clock readings in ``report.json`` (``wall_time``,
``found_at``, ``finished_at``). Everything else must match byte for byte.

Run: ``python benchmarks/output_hashes.py [--keep DIR]`` from the repository root (the commands run
``python -m illuknit`` with this checkout first on ``PYTHONPATH``).
"""

from __future__ import annotations

import argparse
import hashlib
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

from PIL import Image, ImageDraw

REPO = Path(__file__).resolve().parents[1]

# Clock readings a solve records; their values are blanked before hashing.
CLOCK = re.compile(rb'"(wall_time|found_at|finished_at)": [^,\n]*')


def pictures(folder: Path) -> tuple[Path, Path]:
    """A disc and a plus sign, 60 x 60 pixels, two colours each."""
    a = Image.new("RGB", (60, 60), (244, 240, 232))
    ImageDraw.Draw(a).ellipse((10, 10, 50, 50), fill=(27, 27, 27))
    b = Image.new("RGB", (60, 60), (244, 240, 232))
    draw = ImageDraw.Draw(b)
    draw.rectangle((24, 6, 36, 54), fill=(27, 27, 27))
    draw.rectangle((6, 24, 54, 36), fill=(27, 27, 27))
    pa, pb = folder / "disc.png", folder / "plus.png"
    a.save(pa)
    b.save(pb)
    return pa, pb


def commands(inputs: Path, out: Path) -> list[list[str]]:
    a, b = pictures(inputs)
    design = ["--width", "24", "--candidates", "2", "--pool", "2"]
    return [
        ["demo", "-o", str(out / "demo"), "--width", "24", "--format", "dat"],
        ["single", str(a), "--width", "24", "-o", str(out / "single"), "--knitout"],
        [
            "double",
            str(a),
            str(b),
            *design,
            "-o",
            str(out / "double-swg"),
            "--knitout",
            "--machine",
            "swg091n2",
            "--format",
            "dat",
        ],
        [
            "double",
            str(a),
            str(b),
            *design,
            "-o",
            str(out / "double-kn"),
            "--knitout",
            "--machine",
            "kniterate",
            "--format",
            "kc",
        ],
        ["headon", str(a), *design, "-o", str(out / "headon"), "--knitout"],
        [
            "solve",
            str(a),
            str(b),
            "--solver",
            "dp",
            "--width",
            "20",
            "-o",
            str(out / "solve"),
            "--knitout",
        ],
        [
            "knit",
            str(out / "double-swg" / "pattern.json"),
            "-o",
            str(out / "knit" / "swg.dat"),
            "--machine",
            "swg091n2",
            "--format",
            "dat",
        ],
        [
            "knit",
            str(out / "double-swg" / "pattern.json"),
            "-o",
            str(out / "knit" / "kn.k"),
            "--machine",
            "kniterate",
            "--format",
            "kc",
        ],
        ["view", str(out / "solve" / "pattern.json"), "-o", str(out / "view")],
        ["tiles", "-o", str(out / "tiles")],
        *machine_commands(a, b, out),
    ]


#: ``illuknit knit`` switches whose every value goes through the mixed-colourwork scheduler.
KNIT_SWITCHES: tuple[tuple[str, ...], ...] = (
    ("--plate", "--allow-long-floats"),
    ("--no-catching",),
    ("--no-float-avoidance",),
    ("--path-planning", "split"),
    ("--path-planning", "none"),
    ("--catch-every", "1"),
    ("--plate", "--tuck-passes", "--allow-long-floats"),
    ("--cast-on-courses", "0"),
    ("--float-limit", "6", "--allow-long-floats"),
)


def machine_commands(a: Path, b: Path, out: Path) -> list[list[str]]:
    """Every design command knitted for a Shima and the Kniterate (.dat, .kc), and ``knit`` with
    each scheduler switch for both machines, as knitout and as the machine's file (its JSON
    summary is kept too: passes, bound, time, the checker's findings)."""
    size = ["--width", "24"]
    design = [*size, "--candidates", "1", "--pool", "2"]
    solve = ["--solver", "dp", "--width", "20"]
    argv: list[list[str]] = []
    for machine, fmt in MACHINES:
        to = ["--knitout", "--machine", machine, "--format", fmt]
        argv += [
            ["single", str(a), *size, "-o", str(out / f"single-{machine}"), *to],
            ["headon", str(a), str(b), *design, "-o", str(out / f"headon-{machine}"), *to],
            ["solve", str(b), str(a), *solve, "-o", str(out / f"solve-{machine}"), *to],
        ]
    pattern = str(out / "double-swg" / "pattern.json")
    for i, switches in enumerate(KNIT_SWITCHES):
        for machine, fmt in MACHINES:
            target = out / "knit-switches" / f"{i}-{machine}"
            for suffix, as_format in ((".k", "knitout"), (f".{fmt}", fmt)):
                output = ["-o", str(target.with_suffix(suffix)), "--format", as_format]
                argv.append(["knit", pattern, *output, "--machine", machine, "--json", *switches])
    return argv


#: The machines every output is made for, with their machine file format.
MACHINES = (("swg091n2", "dat"), ("kniterate", "kc"))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--keep", type=Path, help="write the outputs here and keep them")
    args = parser.parse_args()
    env = dict(os.environ, PYTHONPATH=str(REPO) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    with tempfile.TemporaryDirectory() as tmp:
        root = args.keep or Path(tmp)
        inputs, out = root / "inputs", root / "out"
        inputs.mkdir(parents=True, exist_ok=True)
        out.mkdir(parents=True, exist_ok=True)
        failed = 0
        for i, argv in enumerate(commands(inputs, out)):
            run = subprocess.run(
                [sys.executable, "-m", "illuknit", *argv],
                env=env,
                cwd=root,
                capture_output=True,
                text=True,
            )
            print(f"# exit {run.returncode}: illuknit {argv[0]}", flush=True)
            if "--json" in argv:  # the summary: passes, bound, time, findings
                summary = out / "summaries" / f"{i:03d}-{argv[0]}.json"
                summary.parent.mkdir(exist_ok=True)
                summary.write_text(run.stdout)
            failed += run.returncode != 0
        for path in sorted(p for p in out.rglob("*") if p.is_file()):
            name = path.relative_to(out).as_posix()
            data = path.read_bytes().replace(str(root.resolve()).encode(), b"<root>")
            data = data.replace(str(REPO).encode(), b"<repo>")
            if path.suffix == ".json":
                data = CLOCK.sub(rb'"\1": _', data)
            print(f"{hashlib.sha256(data).hexdigest()}  {name}")
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
