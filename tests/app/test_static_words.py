"""What the app's pages say about numbers and views (issue 33, item 7), run in Node.js: the
scripts are plain, so their functions can be called without a browser."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

STATIC = Path(__file__).resolve().parents[2] / "illuknit" / "app" / "static"


def _run(script: str, expr: str) -> object:
    if shutil.which("node") is None:
        pytest.skip("node is not installed")
    source = (STATIC / script).read_text() + f"\nconsole.log(JSON.stringify({expr}));\n"
    run = subprocess.run(["node", "-"], input=source, capture_output=True, text=True, check=True)
    return json.loads(run.stdout)


MEASURES = {
    "views": ["A", "B"],
    "readability": [0.91, -0.14],
    "worse_contrast": -0.08,
    "ghosting": [None, None],
    "knit_minutes": None,
    "knit_note": "",
}


def test_a_negative_readability_is_explained():
    bad, good = _run(
        "candidates.js",
        f"[measuresText({json.dumps(MEASURES)}), "
        f"measuresText({json.dumps({**MEASURES, 'readability': [0.9, 0.8], 'worse_contrast': 0.5})})]",
    )
    assert "B -0.14" in bad and "in negative (light and dark swapped)" in bad
    assert "negative" not in good


def test_head_on_captions_say_what_head_on_shows():
    shows = _run("candidates.js", "HEADON_SHOWS")
    assert shows["single"] == "stripes (no picture)"
    assert "both pictures show, mixed" in shows["double"] and "stripes" not in shows["double"]


def test_a_card_says_what_the_reader_read_and_the_first_why_its_order():
    order = "ranked by the reader (legibility): both pictures are words (MILK, HAZE)"
    reads = "side B does not read HAZE (the reader saw nothing); side A reads MILK"
    first, other, plain = _run(
        "candidates.js",
        "[readerLine({rank: 1, details: "
        + json.dumps({"order": order, "reads": reads, "all_read": False})
        + "}), readerLine({rank: 2, details: "
        + json.dumps({"order": order, "reads": "side A reads MILK", "all_read": True})
        + "}), readerLine({rank: 1, details: {}})]",
    )
    assert first == {"text": f"{reads} · {order}", "warn": True}
    assert other == {"text": "side A reads MILK", "warn": False}  # the order: on the first only
    assert plain is None
