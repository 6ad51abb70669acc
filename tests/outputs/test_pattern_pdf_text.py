"""pattern.pdf read back with pdftotext (as a knitter's PDF reader sees it), page by page: page
numbers, the verdict, the hand gauge, the swatch size and the schematic's finished size, for a
2-yarn and a 3-yarn double view (issue 37 items 4 and 5)."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from illuknit.core.gauge import finished_size, hand_illusion_gauge
from illuknit.core.machine import DEFAULT_MACHINE
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.outputs.pattern_pdf import pattern_pdf

pytestmark = pytest.mark.skipif(
    shutil.which("pdftotext") is None, reason="pdftotext (poppler-utils) is not installed"
)


def pdftotext_pages(data: bytes, tmp_path: Path) -> list[str]:
    (tmp_path / "p.pdf").write_bytes(data)
    out = subprocess.run(
        ["pdftotext", "-layout", str(tmp_path / "p.pdf"), "-"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return [" ".join(page.split()) for page in out.split("\f") if page.strip()]


@pytest.mark.parametrize("k", [2, 3])
def test_every_page_reads_as_a_bought_pattern(k: int, tmp_path: Path) -> None:
    rng = np.random.default_rng(k)
    shape = (24, 30)
    yarns = parse_yarns("black,firebrick,linen")[:k]
    pattern = LogicalPattern(rng.integers(0, k, shape), rng.random(shape) < 0.3, yarns)
    gauge = DEFAULT_MACHINE.fabric_gauge  # unmeasured: the hand estimate is printed
    pages = pdftotext_pages(pattern_pdf(pattern, gauge=gauge, title="Owl"), tmp_path)
    for n, text in enumerate(pages, 1):
        assert f"page {n} of {len(pages)}" in text and "Owl" in text, n
    assert "By hand:" in pages[0]  # the verdict on the cover
    text = " ".join(pages)
    hand = hand_illusion_gauge(round(gauge.stitches_per_10cm, 1))
    assert hand.describe() in text
    assert "Gauge swatch (about 15 x 15 cm)" in text
    schematic = next(p for p in pages if "Schematic" in p)
    size = finished_size(shape, hand)
    assert f"Finished size: {size.describe()} (width x height) after blocking" in schematic
    assert f"{size.width_cm:.1f} cm ({size.width_in:.1f} in), 60 sts" in schematic
    assert re.search(rf"{size.height_cm:.1f} cm .*\({size.height_in:.1f} in\)", schematic)
    for words in ("cast-on edge", "bind-off edge", "seen from above", "seen from below"):
        assert words in schematic, words
    # one finished size in the whole pattern: the cover says the schematic's (by hand)
    assert f"Finished size by hand: about {size.describe()}" in pages[0]
