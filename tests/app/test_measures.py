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
from illuknit.design.measures import angled_renders, picture_scores
from illuknit.design.tiles import perception


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


def test_every_candidate_is_measured_with_the_librarys_numbers(client, app, measured):
    body = client.get(f"/api/sessions/{measured}/candidates").json()
    assert body["measured"] and len(body["candidates"]) >= 2
    session = app.state.store.get(measured)
    q = session.prepared.quantised
    for c, cand in zip(body["candidates"], session.candidates, strict=True):
        m = c["measures"]
        # recomputed here with the library's function, from the ranking's viewpoint (30
        # degrees, 3 m at the session machine's gauge): the app shows the same numbers
        from illuknit.core.machine import resolve_machine

        blur = perception.seen_blur(3.0, gauge=resolve_machine(session.settings.machine).gauge)
        ref = perception.measure_candidate(
            cand.pattern, [q["a"].rgb(), q["b"].rgb()], angle=30.0, blur=blur
        )
        assert m["readability"] == pytest.approx(list(ref.readability), abs=1e-4)
        assert m["worst_ghosting"] == pytest.approx(ref.worst_ghosting, abs=1e-4)
        assert m["visible_ghosting"] == pytest.approx(list(ref.visible_ghosting), abs=1e-4)
        assert m["perceptual_score"] == pytest.approx(ref.perceptual_score, abs=1e-4)
        # and the readability is the bench's render correlation
        renders, _ = angled_renders(cand.pattern)
        s = picture_scores(
            renders, q["a"].rgb() / 255.0, q["b"].rgb() / 255.0, double=True, sigma=blur
        )
        assert m["readability"][0] == pytest.approx(s["render_corr_a"], abs=1e-4)
        assert m["knit_minutes"] > 0 and m["machine_passes"] > 0 and m["knit_note"] == ""


@pytest.mark.parametrize("order", ORDERS)
def test_candidates_re_rank_by_any_measure(client, measured, order):
    cands = client.get(f"/api/sessions/{measured}/candidates", params={"order": order}).json()
    got = cands["candidates"]
    assert sorted(c["rank"] for c in got) == list(range(1, len(got) + 1))
    key = {
        "rank": lambda c: c["rank"],
        "perception": lambda c: -c["measures"]["perceptual_score"],
        "legibility": lambda c: (-_sides_read(c), -c["measures"]["perceptual_score"]),
        "readability": lambda c: -c["measures"]["worse_readability"],
        "contrast": lambda c: -c["measures"]["worse_contrast"],
        "ghosting": lambda c: c["measures"]["worst_visible_ghosting"],
        "knit_time": lambda c: c["measures"]["knit_minutes"],
        "hand_time": lambda c: c["measures"]["hand"]["hours"],
    }[order]
    values = [key(c) for c in got]
    assert values == sorted(values)


def _sides_read(card):
    """The sides a card's verdict says read (none when the reader was not asked)."""
    verdict = card["details"].get("legibility") or {}
    return sum(s["reads"] for s in verdict.get("sides", []))


def test_bad_order_and_measuring_nothing_are_refused(client):
    sid = client.post("/api/sessions").json()["id"]
    r = client.get(f"/api/sessions/{sid}/candidates", params={"order": "beauty"})
    assert r.status_code == 422 and r.json()["error"]["field"] == "order"
    assert r.json()["error"]["message"].startswith(
        "Order must be one of: rank, perception, legibility, readability"
    )
    r = client.post(f"/api/sessions/{sid}/jobs", json={"kind": "measures"})
    assert r.status_code == 409 and r.json()["error"]["field"] == "candidates"


def test_candidates_stay_in_rank_order_until_measured():
    class C:
        def __init__(self, rank, measured):
            self.rank, self.measured, self.score = rank, measured, float(rank)

    cs = [C(2, None), C(1, object())]
    assert [c.rank for c in order_candidates(cs, "perception")] == [1, 2]


def test_sides_that_read_come_before_how_it_reads():
    from illuknit.design.legibility import Legibility, SideReading
    from illuknit.design.tiles.perception import CandidateMeasures

    def cand(rank, corr, reads):
        m = CandidateMeasures(
            views=("A", "B"), readability=(corr, corr), contrast=(0.4, 0.4), ghosting=(0.0, 0.0)
        )
        verdict = None
        if reads is not None:
            sides = tuple(
                SideReading(v, "OK", "OK", r, corr) for v, r in zip("AB", reads, strict=True)
            )
            verdict = Legibility(sides, 30.0, 3.0)
        return type("C", (), {"rank": rank, "measured": m, "score": 1.0, "legibility": verdict})

    cs = [cand(1, 0.97, (True, False)), cand(2, 0.90, (True, True)), cand(3, 0.95, None)]
    assert [c.rank for c in order_candidates(cs, "legibility")] == [2, 1, 3]
    assert [c.rank for c in order_candidates(cs, "perception")] == [1, 3, 2]


def test_diagnostic_overlay_of_each_side(client, app, measured):
    from illuknit.design.tiles.perception import diagnostic_rgb

    session = app.state.store.get(measured)
    q = session.prepared.quantised
    pattern = session.candidates[0].pattern
    for view, own, other in (("A", "a", "b"), ("B", "b", "a")):
        r = client.get(f"/api/sessions/{measured}/diagnostic.png", params={"view": view})
        assert r.status_code == 200 and r.headers["content-type"] == "image/png"
        got = np.asarray(Image.open(io.BytesIO(r.content)).convert("RGB"))
        ref, _ = diagnostic_rgb(pattern, q[own].rgb(), q[other].rgb(), view=view)
        s = got.shape[0] // ref.shape[0]
        assert np.array_equal(got[::s, ::s], ref)
    r = client.get(f"/api/sessions/{measured}/diagnostic.png", params={"view": "headon"})
    assert r.status_code == 409 and r.json()["error"]["field"] == "view"
    r = client.get(f"/api/sessions/{measured}/diagnostic.png", params={"view": "C"})
    assert r.status_code == 422 and r.json()["error"]["field"] == "view"


@pytest.mark.parametrize("with_side", [False, True])
def test_diagnostic_overlay_of_a_headon_design(client, app, with_side):
    """Head-on: the head-on view is judged against the front picture (the side picture must not
    show); at an angle each side against the side picture, or a plain field, with the front
    picture as what must have gone."""
    from illuknit.design.tiles.perception import diagnostic_rgb

    sid = client.post("/api/sessions").json()["id"]
    pics = [("a", box(6, 8))] + ([("b", box(2, 2))] if with_side else [])
    for slot, pic in pics:
        client.put(
            f"/api/sessions/{sid}/images/{slot}", files={"file": ("p.png", pic, "image/png")}
        )
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "headon", "width_units": 18})
    assert run(client, sid, "candidates")["status"] == "done"
    session = app.state.store.get(sid)
    q = session.prepared.quantised
    pattern = session.candidates[0].pattern
    front = q["a"].rgb()
    side = q["b"].rgb() if with_side else np.full_like(front, 128)
    expected = {
        "headon": (front, q["b"].rgb() if with_side else None),
        "A": (side, front),
        "B": (side, front),
    }
    for view, (own, other) in expected.items():
        r = client.get(f"/api/sessions/{sid}/diagnostic.png", params={"view": view})
        assert r.status_code == 200, r.text
        got = np.asarray(Image.open(io.BytesIO(r.content)).convert("RGB"))
        ref, stats = diagnostic_rgb(pattern, own, other, view=view)
        s = got.shape[0] // ref.shape[0]
        assert np.array_equal(got[::s, ::s], ref)
        if view != "headon":
            # at an angle a head-on design hides its front picture: most units pass
            assert stats["wrong"] + stats["ghost"] < 0.5, (view, stats)


@pytest.mark.parametrize("with_side", [False, True])
def test_headon_candidates_are_measured_and_ranked_on_all_three_views(client, app, with_side):
    """Head-on designs get readability and ghosting (head-on, and from above and below), not an
    empty measure: "rank by how it reads" ranks them by how they read."""
    sid = client.post("/api/sessions").json()["id"]
    pics = [("a", box(6, 8))] + ([("b", box(2, 2))] if with_side else [])
    for slot, pic in pics:
        client.put(
            f"/api/sessions/{sid}/images/{slot}", files={"file": ("p.png", pic, "image/png")}
        )
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "headon", "width_units": 18})
    assert run(client, sid, "candidates")["status"] == "done"
    assert run(client, sid, "measures")["status"] == "done"
    cands = client.get(f"/api/sessions/{sid}/candidates", params={"order": "perception"}).json()
    ms = [c["measures"] for c in cands["candidates"]]
    for m in ms:
        assert m["views"] == ["headon", "side"]
        assert m["readability"][0] is not None and -1 <= m["readability"][0] <= 1
        assert (m["readability"][1] is not None) == with_side  # a plain side has nothing to read
        assert m["ghosting"][1] is not None  # how much of the front is left at an angle
        assert m["perceptual_score"] != -0.25
    scores = [m["perceptual_score"] for m in ms]
    assert scores == sorted(scores, reverse=True)
    session = app.state.store.get(sid)
    from illuknit.core.machine import resolve_machine

    m = perception.measure_candidate(
        session.candidates[0].pattern,
        perception.seen_targets(
            session.prepared.quantised["a"], session.prepared.quantised.get("b")
        ),
        views=("headon", "side"),
        blur=perception.seen_blur(3.0, gauge=resolve_machine(session.settings.machine).gauge),
    )
    first = next(c for c in cands["candidates"] if c["rank"] == 1)["measures"]
    assert first["readability"] == [None if v is None else round(v, 4) for v in m.readability]


def test_how_it_reads_keeps_the_readers_order_when_the_search_read_every_candidate():
    from types import SimpleNamespace

    from illuknit.design.tiles.perception import CandidateMeasures

    class C:
        def __init__(self, rank, correlation, sides_read, by="legibility"):
            self.rank, self.score = rank, float(rank)
            self.measured = CandidateMeasures(
                views=("A", "B"), readability=(correlation, correlation), contrast=(0.4, 0.4),
                ghosting=(0.0, 0.0),
            )  # fmt: skip
            read = sides_read is not None
            self.legibility = SimpleNamespace(sides_read=sides_read) if read else None
            self.details = {"ranked_by": by}

    # the search's (the reader's) order: rank 1 reads on both sides, yet correlates less
    read = [C(1, 0.80, 2), C(2, 0.95, 1), C(3, 0.90, 1)]
    assert [c.rank for c in order_candidates(read, "perception")] == [1, 2, 3]
    assert [c.rank for c in order_candidates(read, "readability")] == [2, 3, 1]
    unread = [C(1, 0.80, None), C(2, 0.95, None), C(3, 0.90, None)]
    assert [c.rank for c in order_candidates(unread, "perception")] == [2, 3, 1]
    # one candidate not read: the reader's verdict is not complete, perception alone
    mixed = [C(1, 0.80, 2), C(2, 0.95, None), C(3, 0.90, 1)]
    assert [c.rank for c in order_candidates(mixed, "perception")] == [2, 3, 1]
    # pictures: read (estimates) but the search ranked by perception, so perception stays
    pictures = [
        C(1, 0.80, 2, "perception"),
        C(2, 0.95, 1, "perception"),
        C(3, 0.9, 1, "perception"),
    ]
    assert [c.rank for c in order_candidates(pictures, "perception")] == [2, 3, 1]
    # asked for: the sides that read first, whatever the search ranked by
    assert [c.rank for c in order_candidates(pictures, "legibility")] == [1, 2, 3]
