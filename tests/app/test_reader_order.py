"""The app's search ranks as ``illuknit double`` does by default (issue 38): two pictures of
words by the reader, and its cards carry the order and the reader's verdict.

The words here are never the benchmark's (benchmarks/legibility_words.py).
"""

from __future__ import annotations

from importlib.resources import files

import numpy as np
import pytest
from PIL import Image, ImageDraw, ImageFont


def _word(text: str) -> np.ndarray:
    font = ImageFont.truetype(str(files("illuknit") / "data" / "DejaVuSans-Bold.ttf"), 100)
    box = ImageDraw.Draw(Image.new("L", (1, 1))).textbbox((0, 0), text, font=font)
    im = Image.new("RGB", (360, 130), "white")
    at = ((360 - box[2] + box[0]) // 2 - box[0], (130 - box[3] + box[1]) // 2 - box[1])
    ImageDraw.Draw(im).text(at, text, font=font, fill="black")
    return np.asarray(im)


def test_a_word_pair_is_ranked_by_the_reader_in_the_app(tmp_path, api, pictures, reader):
    pytest.importorskip("fastapi", reason="the app extra is not installed")
    from fastapi.testclient import TestClient

    from illuknit.app import create_app
    from illuknit.app.server import AppConfig

    with TestClient(create_app(AppConfig(isolate_knit=False, data_dir=tmp_path))) as c:
        sid = api.new_session(c)
        assert api.upload(c, sid, "a", pictures.png(_word("MILK"))).status_code == 200
        assert api.upload(c, sid, "b", pictures.png(_word("HAZE"))).status_code == 200
        settings = {"mode": "double", "width_units": 40, "candidates": 2}
        assert c.put(f"/api/sessions/{sid}/settings", json=settings).status_code == 200
        assert api.run_job(c, sid, "candidates")["status"] == "done"
        got = c.get(f"/api/sessions/{sid}/candidates").json()["candidates"]
    first = got[0]["details"]
    assert first["order"].startswith("ranked by the reader (legibility): both pictures are words")
    assert first["ranked_by"] == "legibility"
    for cand in got:
        verdict = cand["details"]["legibility"]
        assert "MILK" in verdict["sentence"] and isinstance(verdict["all_read"], bool)
    read = [int(c["details"]["legibility"]["all_read"]) for c in got]
    assert read == sorted(read, reverse=True)  # the reader's order: both sides first
