"""Pages of pattern.pdf's chart (issue 37): one square a ridge (``--chart units``, the default)
against one square a stitch (``--chart stitches``), for the sizes the issue names.

Prints, per design size in stitches x rows, the chart pages (A4, tiled as
``illuknit.outputs.pattern_pdf.chart_tiles``) of both charts, at the default machine's gauge
(rows 0.7 of a stitch: 3.15 mm chart rows) and at the hand illusion-fabric estimate of 22
stitches a 10 cm (1.8 rows a stitch). With ``--pdf`` it also writes the whole PDF of a random
2-yarn pattern of each size (the worst case for the written rows) and counts its pages: slow
(about 10-40 s a size on a shared 2-core machine).

    python benchmarks/hand_chart_pages.py [--pdf]
"""

from __future__ import annotations

import io
import sys

import numpy as np

from illuknit.core.gauge import hand_illusion_gauge
from illuknit.core.machine import DEFAULT_MACHINE
from illuknit.core.pattern import LogicalPattern, parse_yarns
from illuknit.outputs.pattern_pdf import CELL_MM, chart_tiles, pattern_pdf

SIZES = ((96, 138), (200, 286))  # stitches x rows


def main(pdf: bool = False) -> None:
    gauges = {"machine 5:7": DEFAULT_MACHINE.fabric_gauge, "hand 22 sts": hand_illusion_gauge(22)}
    print(f"{'design':>12} {'gauge':>12} {'stitch chart':>13} {'ridge chart':>12}")
    for w, h in SIZES:
        for label, g in gauges.items():
            row = CELL_MM * g.unit_aspect
            stitches = len(chart_tiles(w, h, row_mm=row))
            units = len(chart_tiles(w // 2, h // 2, row_mm=row))
            print(f"{f'{w}x{h}':>12} {label:>12} {stitches:>13} {units:>12}")
    if not pdf:
        return
    from pypdf import PdfReader

    rng = np.random.default_rng(0)
    for w, h in SIZES:
        shape = (h // 2, w // 2)
        p = LogicalPattern(
            rng.integers(0, 2, shape), rng.random(shape) < 0.3, parse_yarns("black,#808080")
        )
        for kind in ("stitches", "units"):
            data = pattern_pdf(p, gauge=DEFAULT_MACHINE.fabric_gauge, chart=kind)
            pages = len(PdfReader(io.BytesIO(data)).pages)
            print(f"{w}x{h} random 2-yarn, --chart {kind}: whole PDF {pages} pages")


if __name__ == "__main__":
    main(pdf="--pdf" in sys.argv[1:])
