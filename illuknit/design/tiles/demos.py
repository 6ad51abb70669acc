"""The two double-view demonstrations of the tile framework, drawn or loaded by code.

* :func:`text_pair_demo`: "ILLUSION" seen from above, "KNITTING" from below, two yarns (paper
  Fig. 18 (b)); the words are drawn by :func:`illuknit.pictures.drawings.draw_text`, no stored picture.
* :func:`skimage_pair_demo`: two of scikit-image's bundled photographs quantised to three
  colours, knit with three yarns chosen from both pictures (like the paper's Van Gogh pair).

Both return the ranked candidates and the compiled default, so tests (small sizes), benchmarks
(330 x 200 units) and users can run them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from illuknit.core.pattern import LogicalPattern, Yarn, parse_yarns
from illuknit.design.tiles.assign import TileAssignment, assign_tiles
from illuknit.design.tiles.bank import canonical_bank
from illuknit.design.tiles.compile import TileReport, compile_tiles

__all__ = ["DemoResult", "skimage_pair_demo", "text_pair_demo"]

TEXT_YARNS = "black=#1b1b1b,white=#f4f0e8"


@dataclass(frozen=True)
class DemoResult:
    """Inputs (index maps and colours), ranked candidates, and the default compiled."""

    inputs: tuple[tuple[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]
    yarns: tuple[Yarn, ...]
    candidates: list[TileAssignment]
    pattern: LogicalPattern
    report: TileReport


def text_pair_demo(
    shape: tuple[int, int] = (200, 330),
    *,
    words: tuple[str, str] = ("ILLUSION", "KNITTING"),
    yarns: str = TEXT_YARNS,
    candidates: int = 3,
    solver: str = "cpsat",
) -> DemoResult:
    """Dark words on a light ground, one word per side, with two yarns."""
    from illuknit.pictures.drawings import draw_text

    cols = np.array([[240, 240, 240], [25, 25, 25]], dtype=np.uint8)  # 0 = ground, 1 = ink
    ia = draw_text(words[0], shape=shape).astype(np.int16)
    ib = draw_text(words[1], shape=shape).astype(np.int16)
    ys = parse_yarns(yarns)
    found = assign_tiles(
        (ia, cols), (ib, cols), bank=canonical_bank(ys), candidates=candidates, solver=solver
    )
    pattern, report = compile_tiles(found[0])
    return DemoResult(((ia, cols), (ib, cols)), ys, found, pattern, report)


def skimage_pair_demo(
    shape: tuple[int, int] = (200, 330),
    *,
    names: tuple[str, str] = ("astronaut", "coffee"),
    n_colors: int = 3,
    candidates: int = 3,
    solver: str = "cpsat",
) -> DemoResult:
    """Two bundled scikit-image pictures, each quantised to ``n_colors`` colours, knit with
    ``n_colors`` yarns chosen from both pictures together."""
    from illuknit.pictures.drawings import skimage_image
    from illuknit.pictures.images import quantise_image

    a = skimage_image(names[0], shape)
    b = skimage_image(names[1], shape)
    ys = quantise_image(np.concatenate([a, b], axis=0), n_colors=n_colors).yarns
    qa = quantise_image(a, n_colors=n_colors)
    qb = quantise_image(b, n_colors=n_colors)
    found = assign_tiles(qa, qb, bank=canonical_bank(ys), candidates=candidates, solver=solver)
    pattern, report = compile_tiles(found[0])
    return DemoResult(
        ((qa.indices, qa.colors), (qb.indices, qb.colors)), ys, found, pattern, report
    )
