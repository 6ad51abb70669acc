"""Sessions through the JSON API: lifecycle, the store's cap, settings, isolation
(``routers/sessions.py``).
"""

from __future__ import annotations

import io
import threading

import numpy as np
import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")

from fastapi.testclient import TestClient
from PIL import Image

from illuknit.app import create_app
from illuknit.app.server import AppConfig


def test_session_lifecycle_and_unknown_session(client, api):
    sid = api.new_session(client)
    s = client.get(f"/api/sessions/{sid}").json()
    assert s["id"] == sid and s["images"] == {} and s["candidates"] == 0
    assert client.delete(f"/api/sessions/{sid}").status_code == 200
    r = client.get(f"/api/sessions/{sid}")
    assert r.status_code == 404
    assert api.error_of(r)["code"] == "no_session"
    r = client.get("/api/sessions/nope/inputs")
    assert r.status_code == 404 and api.error_of(r)["field"] == "session"


def test_session_store_caps_live_sessions(api):
    app = create_app(AppConfig(max_sessions=2))
    with TestClient(app) as c:
        first = api.new_session(c)
        api.new_session(c)
        api.new_session(c)
        r = c.get(f"/api/sessions/{first}")
        assert r.status_code == 410 and api.error_of(r)["code"] == "evicted"
        assert "more than 2 sessions" in api.error_of(r)["message"]
        assert len(app.state.store) == 2


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"width_units": 0}, "width_units"),
        ({"width_units": 5000}, "width_units"),
        ({"width_units": "wide"}, "width_units"),
        ({"width_cm": -3}, "width_cm"),
        ({"gauge": 0}, "gauge"),
        ({"n_colors": 9}, "n_colors"),
        ({"candidates": 0}, "candidates"),
        ({"mode": "triple"}, "mode"),
        ({"yarns": ["#000000"]}, "yarns"),
        ({"yarns": ["#000000", "not-a-colour"]}, "yarns"),
        ({"yarns": ["#000000", "#000"]}, "yarns"),
    ],
)
def test_settings_out_of_range_name_their_field(client, change, field, api):
    sid = api.new_session(client)
    before = client.get(f"/api/sessions/{sid}").json()["settings"]
    r = client.put(f"/api/sessions/{sid}/settings", json=change)
    assert r.status_code == 422, r.text
    assert api.error_of(r)["field"] == field
    assert client.get(f"/api/sessions/{sid}").json()["settings"] == before


def test_concurrent_sessions_do_not_mix_state(client, api, pictures):
    """Two tabs upload different pictures with different settings at the same time."""
    pics = {
        "left": (
            pictures.box_picture(24, 36),
            {"mode": "single", "width_units": 18, "yarns": ["#102030", "#f0e0d0"]},
        ),
        "right": (
            pictures.box_picture(40, 40, top=4),
            {"mode": "single", "width_units": 10, "yarns": ["#400000", "#e0ffe0"]},
        ),
    }
    sids = {k: api.new_session(client) for k in pics}
    results: dict[str, dict] = {}
    errors: list[BaseException] = []
    barrier = threading.Barrier(2)

    def tab(key: str) -> None:
        try:
            sid = sids[key]
            data, settings = pics[key]
            barrier.wait(10)
            for _ in range(3):
                assert api.upload(client, sid, "a", data).status_code == 200
                assert client.put(f"/api/sessions/{sid}/settings", json=settings).status_code == 200
            job = api.run_job(client, sid, "candidates")
            assert job["status"] == "done", job
            results[key] = {
                "inputs": client.get(f"/api/sessions/{sid}/inputs").json(),
                "pattern": client.get(f"/api/sessions/{sid}/download/pattern.json").json(),
                "image": client.get(f"/api/sessions/{sid}/images/a").content,
            }
        except BaseException as e:  # surfaced below
            errors.append(e)

    threads = [threading.Thread(target=tab, args=(k,)) for k in pics]
    for t in threads:
        t.start()
    for t in threads:
        t.join(60)
    assert not errors, errors
    for key, (data, settings) in pics.items():
        got = results[key]
        kept = np.asarray(Image.open(io.BytesIO(got["image"])))
        assert np.array_equal(kept, np.asarray(Image.open(io.BytesIO(data))))
        assert got["inputs"]["cols"] == settings["width_units"]
        assert [y["rgb"] for y in got["pattern"]["yarns"]] == settings["yarns"]
        assert got["pattern"]["cols"] == settings["width_units"]
