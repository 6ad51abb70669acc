"""Sessions keep pictures small, are bounded together by bytes, and say when they were evicted;
a job replaced by a newer one answers with its successor."""

from __future__ import annotations

import io
import time

import numpy as np
import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")

from fastapi.testclient import TestClient
from PIL import Image

from illuknit.app import create_app
from illuknit.app.server import AppConfig
from illuknit.app.sessions import SessionStore, UploadedImage


def png(h: int, w: int, seed: int = 0) -> bytes:
    rgb = np.random.default_rng(seed).integers(0, 256, (h, w, 3), dtype=np.uint8)
    buf = io.BytesIO()
    Image.fromarray(rgb).save(buf, format="PNG")
    return buf.getvalue()


def upload(c: TestClient, sid: str, slot: str, data: bytes, name: str = "p.png"):
    return c.put(f"/api/sessions/{sid}/images/{slot}", files={"file": (name, data, "image/png")})


def test_pictures_are_kept_as_uint8_at_the_working_grid():
    app = create_app(AppConfig(isolate_knit=False))
    with TestClient(app) as c:
        sid = c.post("/api/sessions").json()["id"]
        buf = io.BytesIO()
        Image.new("RGB", (3000, 1500), (10, 200, 30)).save(buf, format="JPEG", quality=95)
        assert upload(c, sid, "a", buf.getvalue(), "big.jpg").status_code == 200
        im = app.state.store.get(sid).images["a"]
        assert im.rgb.dtype == np.uint8 and im.rgb.shape == (750, 1500, 3)
        assert im.sent_bytes == len(buf.getvalue()) and not hasattr(im, "data")
        assert np.abs(im.rgb.astype(int) - (10, 200, 30)).max() <= 3


def test_uploaded_image_refuses_floats():
    with pytest.raises(ValueError, match="uint8"):
        UploadedImage("x.png", 10, np.zeros((4, 4, 3)))


def test_all_sessions_are_bounded_by_bytes_least_recently_used_first():
    # each 100 x 100 picture is 30 000 bytes: two fit, the third evicts the oldest session
    app = create_app(AppConfig(isolate_knit=False, max_session_bytes=70_000))
    with TestClient(app) as c:
        sids = [c.post("/api/sessions").json()["id"] for _ in range(3)]
        for k, sid in enumerate(sids[:2]):
            assert upload(c, sid, "a", png(100, 100, k)).status_code == 200
            time.sleep(0.01)
        c.get(f"/api/sessions/{sids[0]}")  # used again: now sids[1] is the least recent
        assert upload(c, sids[2], "a", png(100, 100, 2)).status_code == 200
        r = c.get(f"/api/sessions/{sids[1]}")
        assert r.status_code == 410
        err = r.json()["error"]
        assert err["code"] == "evicted" and err["field"] == "session"
        assert "closed to make room for newer work" in err["message"]
        assert c.get(f"/api/sessions/{sids[0]}").status_code == 200
        assert app.state.store.nbytes() <= 70_000


def test_the_session_being_worked_on_is_never_evicted():
    app = create_app(AppConfig(isolate_knit=False, max_session_bytes=10_000))
    with TestClient(app) as c:
        sid = c.post("/api/sessions").json()["id"]
        assert upload(c, sid, "a", png(100, 100)).status_code == 200
        assert c.get(f"/api/sessions/{sid}").status_code == 200


def test_deleted_and_unknown_sessions_are_not_called_evicted():
    store = SessionStore(max_bytes=1)
    s = store.create()
    store.delete(s.id)
    from illuknit.core.errors import AppRequestError

    for sid in (s.id, "never-was"):
        with pytest.raises(AppRequestError) as e:
            store.get(sid)
        assert e.value.code == "no_session" and e.value.status == 404


def test_expired_session_says_it_expired():
    store = SessionStore(ttl=0.0)
    s = store.create()
    time.sleep(0.01)
    from illuknit.core.errors import AppRequestError

    with pytest.raises(AppRequestError) as e:
        store.get(s.id)
    assert e.value.code == "evicted" and "expired" in str(e.value)


def test_a_replaced_job_answers_with_its_successor():
    app = create_app(AppConfig(isolate_knit=False, workers=1))
    with TestClient(app) as c:
        sid = c.post("/api/sessions").json()["id"]
        data = png(24, 36)
        assert upload(c, sid, "a", data).status_code == 200
        c.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 12})
        first = c.post(f"/api/sessions/{sid}/jobs", json={"kind": "candidates"}).json()
        second = c.post(f"/api/sessions/{sid}/jobs", json={"kind": "candidates"}).json()
        third = c.post(f"/api/sessions/{sid}/jobs", json={"kind": "candidates"}).json()
        for old in (first, second):
            r = c.get(f"/api/sessions/{sid}/jobs/{old['id']}")
            assert r.status_code == 200, r.text
            assert r.json()["id"] == third["id"] and r.json()["superseded"] == old["id"]
            # cancelling a replaced job leaves its successor alone
            r = c.delete(f"/api/sessions/{sid}/jobs/{old['id']}")
            assert r.status_code == 200 and r.json()["id"] == third["id"]
        deadline = time.monotonic() + 60
        while (job := c.get(f"/api/sessions/{sid}/jobs/{third['id']}").json())["status"] in (
            "queued",
            "running",
        ):
            assert time.monotonic() < deadline
            time.sleep(0.05)
        assert job["status"] == "done" and "superseded" not in job
        # another session's job ids stay unknown here
        other = c.post("/api/sessions").json()["id"]
        r = c.get(f"/api/sessions/{other}/jobs/{first['id']}")
        assert r.status_code == 404 and r.json()["error"]["code"] == "no_job"
