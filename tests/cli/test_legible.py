"""``illuknit legible`` and the reader's verdict in ``double``'s summary (issue 38)."""

from __future__ import annotations

import shutil
from typing import Any

import numpy as np
import pytest
from PIL import Image

from illuknit.cli.design_files import reads_cells, summary_text, verdict_lines


def _row(rank: int, default: bool, verdict: dict[str, Any] | None) -> dict[str, Any]:
    return {
        "rank": rank, "default": default, "perceptual_score": 0.95, "readability": [0.96, 0.94],
        "contrast": [0.3, 0.3], "ghosting": [0.1, 0.2], "visible_ghosting": [0.02, 0.05],
        "knit_minutes": None, "score": 12.0, "fills_a": ["black"], "fills_b": ["white"],
        "legibility": verdict,
    }  # fmt: skip


def _verdict(a: bool, b: bool, *, picture: bool = False) -> dict[str, Any]:
    sides = [
        {"view": v, "reads": ok, "judge": "shapes" if picture else "reader"}
        for v, ok in (("A", a), ("B", b))
    ]
    return {
        "reader": "tesseract", "angle": 30.0, "distance_m": 3.0, "all_read": a and b,
        "sides": sides, "sentence": f"side B {'reads' if b else 'does not read'} FROG",
    }  # fmt: skip


def _summary(rows: list[dict[str, Any]]) -> dict[str, Any]:
    return {
        "mode": "double", "size": {"rows": 20, "cols": 60},
        "yarns": [{"name": "black", "rgb": "#000000"}], "bank": {"name": "canonical", "tiles": 9},
        "solver": "cpsat", "searched": 9, "ranked_by": "perception", "candidates": rows,
    }  # fmt: skip


def test_summary_says_the_correlation_is_one_and_which_side_does_not_read():
    rows = [_row(1, True, _verdict(True, False)), _row(2, False, _verdict(True, True))]
    text = summary_text(_summary(rows), [])
    assert "corr A  corr B" in text and "read A  read B" not in text
    assert "not a legibility scale" in text
    first = text.splitlines()[3]
    assert first.startswith("default candidate, read by tesseract from 3 m at 30 degrees")
    assert "side B does not read FROG" in first
    assert "read on both: candidate(s) 2" in text
    pictures = _summary([_row(1, True, _verdict(True, True, picture=True))])
    assert verdict_lines(pictures)[0].startswith("default candidate, judged by its shapes from 3 m")


def test_summary_says_plainly_when_nothing_was_read():
    text = "\n".join(verdict_lines(_summary([_row(1, True, None)])))
    assert text.startswith("not read:") and "not a legibility scale" in text
    assert reads_cells(_row(1, True, None)) == ("-", "-")
    assert reads_cells(_row(1, True, _verdict(True, False, picture=True))) == ("yes*", "no*")


def test_legible_refuses_bad_widths_in_one_line(run_cli, tmp_path):
    pic = tmp_path / "a.png"
    Image.fromarray(np.full((20, 40, 3), 200, np.uint8)).save(pic)
    got = run_cli(["legible", pic, pic, "--widths", "40,x"])
    assert got.code == 2 and "--widths" in got.err and len(got.err.strip().splitlines()) == 1


def test_legible_without_the_reader_says_what_to_install(run_cli, tmp_path, monkeypatch):
    pic = tmp_path / "a.png"
    Image.fromarray(np.full((20, 40, 3), 200, np.uint8)).save(pic)
    real = shutil.which
    monkeypatch.setattr(shutil, "which", lambda name: None if name == "tesseract" else real(name))
    got = run_cli(["legible", pic, pic, "--widths", "20"])
    assert got.code == 2 and "apt-get install tesseract-ocr" in got.err
    assert len(got.err.strip().splitlines()) == 1 and "Traceback" not in got.err


def test_rank_by_legibility_without_the_reader_stops_before_writing(run_cli, tmp_path, monkeypatch):
    pic = tmp_path / "a.png"
    Image.fromarray(np.full((20, 40, 3), 200, np.uint8)).save(pic)
    real = shutil.which
    monkeypatch.setattr(shutil, "which", lambda name: None if name == "tesseract" else real(name))
    out = tmp_path / "out"
    got = run_cli(["double", pic, pic, "--rank-by", "legibility", "--width", "12", "-o", out])
    assert got.code == 2 and "tesseract" in got.err
    assert not out.exists() or not any(out.iterdir())


@pytest.mark.parametrize("flag", ["--no-read"])
def test_double_without_reading_writes_that_it_did_not_read(run_cli, tmp_path, flag):
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    img = np.full((20, 30, 3), 240, np.uint8)
    img[5:15, 5:12] = 20
    Image.fromarray(img).save(a)
    Image.fromarray(img[:, ::-1].copy()).save(b)
    out = tmp_path / "out"
    got = run_cli(["double", a, b, flag, "--candidates", "1", "--pool", "1", "-o", out])
    assert got.code == 0, got.err
    assert (out / "summary.txt").read_text().startswith(
        "double-view tile design"
    ) and "not read:" in (out / "summary.txt").read_text()
