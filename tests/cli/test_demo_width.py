"""``illuknit demo --width`` is bounded where it is parsed to what the demo can knit: width 1 was
accepted and then refused by the pipeline ("rgb is 1 x 1 pixels"); 2 is the least that knits."""

from __future__ import annotations

import subprocess
import sys


def _demo(tmp_path, width):
    return subprocess.run(
        [
            sys.executable,
            "-m",
            "illuknit",
            "demo",
            "--width",
            str(width),
            "-o",
            str(tmp_path / "d"),
        ],
        capture_output=True,
        text=True,
    )


def test_width_1_is_refused_where_it_is_parsed(tmp_path):
    run = _demo(tmp_path, 1)
    assert run.returncode == 2
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1, run.stderr
    assert "--width" in lines[0] and "2<=x<=1000" in lines[0], lines[0]
    assert "illuknit demo:" not in run.stdout  # refused before any work starts
    assert not (tmp_path / "d").exists()


def test_width_2_knits(tmp_path):
    run = _demo(tmp_path, 2)
    assert run.returncode == 0, run.stderr
    assert (tmp_path / "d" / "pattern.json").exists()
