"""The reference SWG backend (``knitout-to-dat.js``) as a judge for the tests of this folder.

The backend's path comes from the ``swg_backend`` fixture (tests/conftest.py).
"""

from __future__ import annotations

import functools
import subprocess
import tempfile
from pathlib import Path

import numpy as np

CHECK_DATA = Path(__file__).parents[1] / "check" / "data"


#: assertions the backend prints on a-miss passes, with no effect on the file it writes
BENIGN = {
    "Assertion failed: Pass type must be one of the TYPE_* constants.",
    "Assertion failed: It only makes sense to ask knit-tuck passes if they have front stitches.",
    "Assertion failed: It only makes sense to ask knit-tuck passes if they have back stitches.",
}


def reference_dat(text: str, backend: Path) -> bytes | None:
    """The reference backend's .dat for ``text``; None when it refuses the program."""
    with tempfile.TemporaryDirectory() as tmp:
        k, dat = Path(tmp) / "in.k", Path(tmp) / "out.dat"
        k.write_text(text)
        run = subprocess.run(
            ["node", str(backend), str(k), str(dat)], capture_output=True, text=True, timeout=60
        )
        asserts = [ln for ln in run.stderr.splitlines() if "Assertion failed" in ln]
        if run.returncode != 0 or "ERROR" in run.stderr or any(a not in BENIGN for a in asserts):
            return None
        return dat.read_bytes()


def reference_pass_count(text: str, backend: Path) -> int | None:
    """Pass rows of the reference .dat (raster height - 19); None when it refuses the program."""
    data = reference_dat(text, backend)
    if data is None:
        return None
    return int(np.frombuffer(data[:8], "<u2")[3]) + 1 - 19


GENERATED = (
    "single",
    "double-2",
    "headon",
    "mixed-3",
    "mixed-4",
    "clean_stockinette",
    "clean_garter",
    "clean_intarsia_plated",
    "bad_wrong_side",
)


@functools.cache
def generated_programs() -> dict[str, str]:
    """A small corpus of programs from illuknit's own generators, by name."""
    from illuknit.core.pattern import LogicalPattern, parse_yarns
    from illuknit.design.single_view import compile_single_view
    from illuknit.design.tiles import assign_headon, assign_tiles, compile_tiles
    from illuknit.knitting import knit_pattern
    from illuknit.pictures.drawings import draw_shape, to_index_image

    yarns = parse_yarns("#1b1b1b,#f4f0e8,#c03030,#3050c0")
    cols = np.array([y.rgb for y in yarns], dtype=np.uint8)
    plus = to_index_image(draw_shape("plus", (6, 8)), ink=0, paper=1)
    circle = to_index_image(draw_shape("circle", (6, 8)), ink=0, paper=1)
    out: dict[str, str] = {}
    single = compile_single_view(plus.astype(np.int16), yarns=yarns[:2])
    out["single"] = knit_pattern(single).text
    found = assign_tiles((plus, cols[:2]), (circle, cols[:2]), yarns=yarns[:2], candidates=1)
    out["double-2"] = knit_pattern(compile_tiles(found[0])[0]).text
    head = assign_headon((plus, cols[:2]), yarns=yarns[:2], candidates=1)
    out["headon"] = knit_pattern(compile_tiles(head[0])[0]).text
    rng = np.random.default_rng(7)
    for k in (3, 4):
        yarn = rng.integers(0, k, (5, 7)).astype(np.int16)
        raised = rng.random((5, 7)) < 0.4
        out[f"mixed-{k}"] = knit_pattern(LogicalPattern(yarn, raised, yarns[:k])).text
    for name in ("clean_stockinette", "clean_garter", "clean_intarsia_plated", "bad_wrong_side"):
        out[name] = (CHECK_DATA / f"{name}.k").read_text()
    return out
