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


def test_the_first_card_says_which_order_the_search_used():
    order = "ranked by the reader (legibility): both pictures are words (MILK, HAZE)"
    first, other, plain = _run(
        "candidates.js",
        "[orderLine({rank: 1, details: "
        + json.dumps({"order": order})
        + "}), orderLine({rank: 2, details: "
        + json.dumps({"order": order})
        + "}), orderLine({rank: 1, details: {}})]",
    )
    assert first == order
    assert other is None and plain is None  # the order: on the first card only


def test_a_side_judged_by_its_shapes_says_it_is_an_estimate():
    """The reader's verdict on a card (issue 38): a word side is the reader's sentence, a
    picture side's shape agreement is said as an estimate, never as a reading."""
    word, picture, blurred = _run(
        "candidates.js",
        "[sideText({view: 'B', judge: 'reader', reads: false, shape_agreement: null, "
        "sentence: \"side B does not read ELM (the reader saw 'EIM')\"}), "
        "sideText({view: 'A', judge: 'shapes', reads: true, shape_agreement: 0.913, "
        "sentence: 'long'}), "
        "sideText({view: 'A', judge: 'shapes', reads: false, shape_agreement: 0.5, "
        "sentence: 'long'})]",
    )
    assert word == "✗ side B does not read ELM (the reader saw 'EIM')"
    assert picture == "≈ side A (a picture) likely reads: shapes agree on 91 %, an estimate"
    assert blurred.startswith("≈ side A (a picture) may not read") and "50 %" in blurred
