"""Each candidate's readability, ghosting and knitting time, and candidates re-ranked by them."""

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
from illuknit.app.measures import ORDERS, order_candidates
from illuknit.app.server import AppConfig
from illuknit.bench.metrics import angled_renders, picture_scores


def box(top: int, left: int) -> bytes:
    rgb = np.full((24, 36, 3), 240, np.uint8)
    rgb[top : top + 12, left : left + 18] = 20
    buf = io.BytesIO()
    Image.fromarray(rgb).save(buf, format="PNG")
    return buf.getvalue()


@pytest.fixture(scope="module")
def app():
    return create_app(AppConfig(isolate_knit=False))


@pytest.fixture(scope="module")
def client(app):
    with TestClient(app) as c:
        yield c


def run(client, sid, kind):
    r = client.post(f"/api/sessions/{sid}/jobs", json={"kind": kind})
    assert r.status_code == 202, r.text
    job = r.json()
    deadline = time.monotonic() + 120
    while job["status"] in ("queued", "running"):
        assert time.monotonic() < deadline
        time.sleep(0.05)
        job = client.get(f"/api/sessions/{sid}/jobs/{job['id']}").json()
    return job


@pytest.fixture(scope="module")
def measured(client, app):
    sid = client.post("/api/sessions").json()["id"]
    for slot, pic in (("a", box(6, 8)), ("b", box(2, 2))):
        client.put(
            f"/api/sessions/{sid}/images/{slot}", files={"file": ("p.png", pic, "image/png")}
        )
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "double", "width_units": 18})
    assert run(client, sid, "candidates")["status"] == "done"
    assert not client.get(f"/api/sessions/{sid}/candidates").json()["measured"]
    assert run(client, sid, "measures")["status"] == "done"
    return sid


def test_every_candidate_is_measured_with_the_benchmarks_numbers(client, app, measured):
    body = client.get(f"/api/sessions/{measured}/candidates").json()
    assert body["measured"] and len(body["candidates"]) >= 2
    session = app.state.store.get(measured)
    for c, cand in zip(body["candidates"], session.candidates, strict=True):
        m = c["measures"]
        # recomputed here from the bench's own functions: the app shows the same numbers
        renders, _ = angled_renders(cand.pattern)
        ta, tb = (session.prepared.quantised[k].rgb() / 255.0 for k in ("a", "b"))
        s = picture_scores(renders, ta, tb, double=True)
        assert m["readability_a"] == pytest.approx(s["render_corr_a"], abs=1e-4)
        assert m["readability_b"] == pytest.approx(s["render_corr_b"], abs=1e-4)
        assert m["readability"] == min(m["readability_a"], m["readability_b"])
        assert m["ghosting"] == max(abs(m["ghosting_a"]), abs(m["ghosting_b"]))
        assert m["knit_minutes"] > 0 and m["machine_passes"] > 0 and m["knit_note"] == ""


@pytest.mark.parametrize("order", ORDERS)
def test_candidates_re_rank_by_any_measure(client, measured, order):
    cands = client.get(f"/api/sessions/{measured}/candidates", params={"order": order}).json()
    got = cands["candidates"]
    assert sorted(c["rank"] for c in got) == list(range(1, len(got) + 1))
    key = {
        "rank": lambda c: c["rank"],
        "readability": lambda c: -c["measures"]["readability"],
        "ghosting": lambda c: c["measures"]["ghosting"],
        "knit_time": lambda c: c["measures"]["knit_minutes"],
    }[order]
    values = [key(c) for c in got]
    assert values == sorted(values)


def test_bad_order_and_measuring_nothing_are_refused(client):
    sid = client.post("/api/sessions").json()["id"]
    r = client.get(f"/api/sessions/{sid}/candidates", params={"order": "beauty"})
    assert r.status_code == 422 and r.json()["error"]["field"] == "order"
    assert r.json()["error"]["message"].startswith("Order must be one of: rank, readability")
    r = client.post(f"/api/sessions/{sid}/jobs", json={"kind": "measures"})
    assert r.status_code == 409 and r.json()["error"]["field"] == "candidates"


def test_unmeasured_candidates_go_last():
    class C:
        def __init__(self, rank, measures):
            self.rank, self.measures = rank, measures

    cs = [C(1, None), C(2, {"readability": 0.5, "ghosting": 0.1}), C(3, {"readability": 0.9})]
    assert [c.rank for c in order_candidates(cs, "readability")] == [3, 2, 1]
    assert [c.rank for c in order_candidates(cs, "knit_time")] == [1, 2, 3]
