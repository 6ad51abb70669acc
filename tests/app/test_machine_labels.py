"""The app names the machine truthfully and says when a piece fits only the generic bed."""

from __future__ import annotations

import io

import numpy as np
import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")

from fastapi.testclient import TestClient
from PIL import Image

from illuknit.app import create_app
from illuknit.app.server import AppConfig


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(AppConfig(isolate_knit=False))) as c:
        yield c


def picture() -> bytes:
    rgb = np.full((24, 36, 3), 240, np.uint8)
    rgb[6:18, 8:26] = 20
    buf = io.BytesIO()
    Image.fromarray(rgb).save(buf, format="PNG")
    return buf.getvalue()


def test_selector_labels_say_what_each_machine_is(client):
    labels = {m["name"]: m["label"] for m in client.get("/api/info").json()["machines"]}
    assert labels["generic540"] == "generic 540-needle V-bed (SWG091N2 rules)"
    assert labels["swg091n2"] == "SWG091N2" and labels["kniterate"] == "Kniterate"


def test_a_piece_wider_than_the_real_swg091n2_gets_a_note(client):
    sid = client.post("/api/sessions").json()["id"]
    client.put(f"/api/sessions/{sid}/images/a", files={"file": ("a.png", picture(), "image/png")})
    r = client.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 130})
    assert r.status_code == 200, r.text
    notes = client.get(f"/api/sessions/{sid}/inputs").json()["notes"]
    assert [n for n in notes if "not a real SWG091N2" in n and "130 units" in n], notes
    client.put(f"/api/sessions/{sid}/settings", json={"width_units": 60})
    notes = client.get(f"/api/sessions/{sid}/inputs").json()["notes"]
    assert not [n for n in notes if "SWG091N2" in n], notes
