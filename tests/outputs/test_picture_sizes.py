"""Every picture command works at every pattern size it accepts (issue 33, item 6).

``illuknit render`` once refused every pattern under about 60 units on its long side (its
automatic scale asked the renderer for more than 8 bands a unit row); these properties run
``render`` and ``view`` (previews, chart.png, chart.svg, pattern.pdf) over small and large sizes,
odd aspect ratios and single rows and columns.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from PIL import Image

from illuknit.cli import main
from illuknit.core.pattern import LogicalPattern, Yarn, save_pattern

YARNS = (Yarn("Dark", (27, 27, 27)), Yarn("Light", (244, 240, 232)))
SIZES = st.tuples(st.integers(1, 48), st.integers(1, 48))
SLOW = settings(
    max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=True
)


def _pattern_file(folder: Path, shape: tuple[int, int], seed: int = 0) -> Path:
    rng = np.random.default_rng(seed)
    pattern = LogicalPattern(
        rng.integers(0, 2, shape).astype(np.int16), rng.random(shape) < 0.3, YARNS
    )
    save_pattern(pattern, folder / "pattern.json")
    return folder / "pattern.json"


@SLOW
@given(SIZES)
@example((1, 1))
@example((1, 90))
@example((90, 1))
@example((7, 59))  # just under the size the automatic scale once broke at
def test_render_works_at_every_size(shape):
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out"
        main(["render", str(_pattern_file(Path(tmp), shape)), "--frames", "2", "-o", str(out)])
        for name in ("view_a", "view_b", "headon", "contact"):
            with Image.open(out / f"{name}.png") as img:
                assert min(img.size) >= 1
        with Image.open(out / "headon.png") as img:
            assert img.size[0] % shape[1] == 0  # whole pixels per unit across


@SLOW
@given(SIZES)
@example((1, 1))
@example((1, 70))
@example((70, 1))
def test_view_writes_previews_chart_and_pdf_at_every_size(shape):
    from pypdf import PdfReader

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out"
        main(["view", str(_pattern_file(Path(tmp), shape)), "-o", str(out)])
        for name in ("headon", "view_a", "view_b", "contact", "chart"):
            with Image.open(out / f"{name}.png") as img:
                assert min(img.size) >= 1
        assert "<svg" in (out / "chart.svg").read_text()
        assert len(PdfReader(out / "pattern.pdf").pages) >= 3
