"""``illuknit view --border N --chart ...``: the hand documents framed in garter stitch, the
design itself (pattern.json) unchanged; without ``--border`` the documents are the design's."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from illuknit.core.pattern import LogicalPattern, load_pattern, parse_yarns, save_pattern


def test_view_writes_the_border_into_the_hand_documents_only(tmp_path: Path) -> None:
    from illuknit.cli import main

    rng = np.random.default_rng(3)
    pattern = LogicalPattern(
        rng.integers(0, 2, (5, 6)), rng.random((5, 6)) < 0.3, parse_yarns("black,linen")
    )
    save_pattern(pattern, tmp_path / "p.json")
    for border, outdir in ((0, tmp_path / "plain"), (2, tmp_path / "framed")):
        main(["view", str(tmp_path / "p.json"), "--border", str(border), "-o", str(outdir)])
    plain = (tmp_path / "plain" / "instructions.txt").read_text()
    framed = (tmp_path / "framed" / "instructions.txt").read_text()
    assert "Row 10 (WS)" in plain and "Row 11 (RS)" not in plain
    assert "(12 sts)" in plain and "(20 sts)" in framed  # 2 units: 8 stitches more
    assert "Row 18 (WS)" in framed and "Row 19 (RS)" not in framed  # and 8 rows more
    assert load_pattern(tmp_path / "framed" / "pattern.json") == pattern
