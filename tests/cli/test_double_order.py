"""``illuknit double`` says which order it ranked by and why, and names ``illuknit legible``
when a word side does not read (issue 38).

The words here are never the benchmark's (benchmarks/legibility_words.py).
"""

from __future__ import annotations

import json
import shlex
import shutil
from importlib.resources import files
from pathlib import Path
from typing import Any

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from illuknit.cli.design_files import order_lines, summary_text, verdict_lines


def _word(path: Path, text: str) -> Path:
    font = ImageFont.truetype(str(files("illuknit") / "data" / "DejaVuSans-Bold.ttf"), 100)
    box = ImageDraw.Draw(Image.new("L", (1, 1))).textbbox((0, 0), text, font=font)
    im = Image.new("RGB", (360, 130), "white")
    at = ((360 - box[2] + box[0]) // 2 - box[0], (130 - box[3] + box[1]) // 2 - box[1])
    ImageDraw.Draw(im).text(at, text, font=font, fill="black")
    im.save(path)
    return path


def _shapes(tmp_path: Path) -> tuple[Path, Path]:
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    img = np.full((20, 30, 3), 240, np.uint8)
    img[5:15, 5:12] = 20
    Image.fromarray(img).save(a)
    Image.fromarray(img[:, ::-1].copy()).save(b)
    return a, b


def _written(out: Path) -> tuple[dict[str, Any], str]:
    return json.loads((out / "summary.json").read_text()), (out / "summary.txt").read_text()


# -- the summary's lines -----------------------------------------------------------------------


def _summary(**more: Any) -> dict[str, Any]:
    verdict = {
        "reader": "tesseract", "angle": 30.0, "distance_m": 3.0, "all_read": False,
        "sentence": "side B does not read TOAD (the reader saw nothing); side A reads FROG",
        "sides": [{"view": "A", "reads": True, "judge": "reader"},
                  {"view": "B", "reads": False, "judge": "reader"}],
    }  # fmt: skip
    row = {
        "rank": 1, "default": True, "perceptual_score": 0.9, "readability": [0.9, 0.9],
        "contrast": [0.3, 0.3], "ghosting": [0.1, 0.1], "visible_ghosting": [0.0, 0.0],
        "knit_minutes": None, "score": 1.0, "fills_a": ["black"], "fills_b": ["white"],
        "legibility": verdict,
    }  # fmt: skip
    return {
        "mode": "double", "size": {"rows": 10, "cols": 30}, "yarns": [], "searched": 9,
        "bank": {"name": "canonical", "tiles": 9}, "solver": "cpsat", "candidates": [row],
        "ranked_by": "legibility", "made_for": "machine", **more,
    }  # fmt: skip


def test_the_summary_names_the_order_and_why():
    order = {"by": "legibility", "asked": "auto", "sentence": "ranked by the reader "
             "(legibility): both pictures are words (FROG, TOAD)"}  # fmt: skip
    assert order_lines(_summary(order=order)) == [
        "order: ranked by the reader (legibility): both pictures are words (FROG, TOAD) "
        "[--rank-by auto, the default]"
    ]
    asked = {"by": "score", "asked": "score", "sentence": "ranked by score: as asked"}
    assert order_lines(_summary(order=asked)) == ["order: ranked by score: as asked"]
    assert order_lines(_summary()) == []  # a summary written before the order was kept
    assert "order: ranked by score: as asked" in summary_text(_summary(order=asked), [])


def test_a_word_side_that_does_not_read_names_the_width_search():
    step = {"why": "side B does not read TOAD at 30 units wide",
            "command": "illuknit legible a.png b.png --widths 40,50,60,70"}  # fmt: skip
    lines = verdict_lines(_summary(next_step=step))
    text = "\n".join(lines)
    assert "side B does not read TOAD at 30 units wide: a wider piece may read" in text
    assert "    illuknit legible a.png b.png --widths 40,50,60,70" in lines
    assert "not run here" in text and "--width N" in text
    # ranked by the reader alone, no design searched reads on both: no --rank-by advice
    assert "nor does any design searched" in text and "--rank-by" not in text
    hands = "\n".join(verdict_lines(_summary(next_step=step, made_for="hands")))
    assert "nor does any design searched" not in hands
    perception = "\n".join(verdict_lines(_summary(ranked_by="perception")))
    assert "try --rank-by legibility" in perception and "illuknit legible a.png" not in perception


# -- the command ---------------------------------------------------------------------------------


def test_double_ranks_words_by_the_reader_and_says_why(run_cli, tmp_path, reader):
    a, b = _word(tmp_path / "frog.png", "FROG"), _word(tmp_path / "toad.png", "TOAD")
    out = tmp_path / "out"
    got = run_cli(["double", a, b, "--width", "40", "--candidates", "2", "-o", out])
    assert got.code == 0, got.err
    summary, text = _written(out)
    assert summary["ranked_by"] == "legibility"
    assert summary["order"]["asked"] == "auto" and summary["order"]["words"] == ["FROG", "TOAD"]
    line = "order: ranked by the reader (legibility): both pictures are words (FROG, TOAD)"
    assert line in text and line in got.out
    assert not [n for n in summary["notes"] if "--no-read" in n]
    # --no-read cannot stop the reader's order from reading: the output says so
    quiet = run_cli(["double", a, b, "--width", "40", "--candidates", "2", "--no-read",
                     "-o", tmp_path / "quiet"])  # fmt: skip
    assert quiet.code == 0, quiet.err
    notes = _written(tmp_path / "quiet")[0]["notes"]
    assert any(n.startswith("--no-read changed nothing") for n in notes), notes
    assert "--no-read changed nothing" in quiet.out


def test_an_explicit_rank_by_wins_over_the_words(run_cli, tmp_path, reader):
    a, b = _word(tmp_path / "frog.png", "FROG"), _word(tmp_path / "toad.png", "TOAD")
    out = tmp_path / "out"
    got = run_cli(["double", a, b, "--width", "40", "--candidates", "2", "--rank-by",
                   "perception", "-o", out])  # fmt: skip
    assert got.code == 0, got.err
    summary, text = _written(out)
    assert summary["ranked_by"] == "perception"
    assert summary["order"] == {**summary["order"], "by": "perception", "asked": "perception"}
    assert "order: ranked by perception: as asked" in text


def test_without_the_reader_the_default_is_perception_and_says_so(run_cli, tmp_path, monkeypatch):
    real = shutil.which
    monkeypatch.setattr(shutil, "which", lambda name: None if name == "tesseract" else real(name))
    a, b = _shapes(tmp_path)
    out = tmp_path / "out"
    got = run_cli(["double", a, b, "--candidates", "1", "--pool", "2", "-o", out])
    assert got.code == 0, got.err
    summary, text = _written(out)
    assert summary["ranked_by"] == "perception" and summary["order"]["asked"] == "auto"
    assert "not installed" in summary["order"]["reason"]
    assert "order: ranked by perception: the reader (tesseract) is not installed" in text
    assert "next_step" not in summary  # nothing was read, nothing to say about widths


def test_a_side_that_does_not_read_names_a_legible_command_that_runs(run_cli, tmp_path, reader):
    a, b = _word(tmp_path / "frog.png", "FROG"), _word(tmp_path / "toad.png", "TOAD")
    out = tmp_path / "out"
    # 30 units is too narrow for four letters from 5 m (no design searched reads on both
    # sides), though the pictures, sharp, still read as words (at 16 they do not)
    got = run_cli(["double", a, b, "--width", "30", "--distance", "5", "--candidates", "2",
                   "-o", out])  # fmt: skip
    assert got.code == 0, got.err
    summary, text = _written(out)
    step = summary["next_step"]
    assert summary["ranked_by"] == "legibility"
    assert step["width"] == 30 and all(w > 30 for w in step["widths"])
    assert "does not read" in step["why"] and step["command"] in text and step["command"] in got.out
    argv = shlex.split(step["command"])
    assert argv[:4] == ["illuknit", "legible", str(a), str(b)]
    assert argv[argv.index("--distance") + 1] == "5"
    # the command is a real one: it runs (at its first width only, to stay quick)
    argv[argv.index("--widths") + 1] = str(step["widths"][0])
    ran = run_cli(argv[1:])
    assert ran.code == 0, ran.err
    assert "units" in ran.out
