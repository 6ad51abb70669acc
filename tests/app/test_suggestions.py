"""Suggested edits in the app: the list, before/after pictures, accept, refuse, and bad ids."""

from __future__ import annotations

import io
from typing import Any

import numpy as np
import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")

from fastapi.testclient import TestClient
from PIL import Image

from illuknit.app import create_app
from illuknit.app.server import AppConfig


@pytest.fixture()
def suggested(client, api, pictures):
    """(session id, suggestions answer): two words, double view, 24 units, suggestions made."""
    r = client.post("/api/sessions")
    sid = r.json()["id"]
    for slot, text in (("a", "UP"), ("b", "ON")):
        files = {"file": (f"{text}.png", pictures.word(text), "image/png")}
        assert client.put(f"/api/sessions/{sid}/images/{slot}", files=files).status_code == 200
    r = client.put(f"/api/sessions/{sid}/settings", json={"mode": "double", "width_units": 24})
    assert r.status_code == 200
    assert api.run_job(client, sid, "candidates")["status"] == "done"
    job = api.run_job(client, sid, "suggestions")
    assert job["status"] == "done", job
    got = client.get(f"/api/sessions/{sid}/suggestions").json()
    assert got["suggestions"], "the ragged words must get at least one suggested edit"
    return sid, got


def test_suggestions_list_their_effect_and_pictures(client, suggested):
    sid, got = suggested
    assert got["set"] and got["revision"] >= 0 and got["refused"] == 0
    for s in got["suggestions"]:
        assert s["id"].startswith(got["set"] + ".")
        assert s["description"] and s["edit"]
        assert s["slots"] and all(s["units_changed"][x.upper()] > 0 for x in s["slots"])
        assert s["readability_before"] == got["readability"]
        assert s["ghosting_before"] == got["ghosting"]
        assert -1 <= s["readability_after"] <= 1
        # improves: a gain --simplify would keep the edit for (MIN_GAIN, 1e-4)
        if s["improves"]:
            assert s["readability_after"] > s["readability_before"]
        else:
            assert s["readability_after"] <= s["readability_before"] + 2e-4
        for slot in s["slots"]:
            shown = {}
            for which in ("before", "after"):
                url = s["previews"][slot][which]
                r = client.get(f"/api/sessions/{sid}/{url}")
                assert r.status_code == 200 and r.headers["content-type"] == "image/png"
                shown[which] = np.asarray(Image.open(io.BytesIO(r.content)).convert("RGB"))
            assert shown["before"].shape == shown["after"].shape
            assert (shown["before"] != shown["after"]).any(), "an edit changes its picture"


def test_suggestions_are_listed_most_helpful_first(client, suggested):
    _, got = suggested
    rank = {"better": 0, "same": 1, "mixed": 2, "worse": 3}
    keys = [(rank[s["verdict"]], -s["benefit"]) for s in got["suggestions"]]
    assert keys == sorted(keys)
    for s in got["suggestions"]:
        assert "majority" not in s["description"]  # plain words, no image-processing jargon
        assert s["effect"].startswith("the worse side's correlation")


@pytest.mark.parametrize(
    ("before", "after", "verdict"),
    [
        ((0.90, 0.10), (0.95, 0.10), "better"),
        ((0.90, 0.10), (0.90, 0.05), "better"),
        ((0.90, 0.164), (0.90, 0.185), "worse"),  # more ghosting, nothing gained: never green
        ((0.981, 0.10), (0.664, 0.05), "mixed"),
        ((0.981, 0.10), (0.664, 0.10), "worse"),
        ((0.90, 0.10), (0.95, 0.20), "mixed"),
        ((0.90, 0.10), (0.90, 0.10), "same"),
    ],
)
def test_a_suggestion_says_whether_it_helps(before, after, verdict):
    from illuknit.app.suggestions import SuggestedEdit

    e = SuggestedEdit("s.1", "k", "n", "d", {"a": 1}, {}, before, after)
    assert e.verdict == verdict
    assert e.to_json()["verdict"] == verdict
    if verdict == "better":
        assert e.benefit > 0
    if verdict == "worse":
        words = e.effect_words()
        assert e.benefit < 0 and (
            ("correlation" in words and "lower" in words) or "more ghosting" in words
        )


def test_accept_replaces_the_pictures_and_designs_again(client, api, suggested):
    sid, got = suggested
    edit = got["suggestions"][0]
    before = client.get(f"/api/sessions/{sid}").json()
    old_inputs = {
        slot: client.get(f"/api/sessions/{sid}/inputs/{slot}.png").content for slot in ("a", "b")
    }
    after_png = {
        slot: client.get(f"/api/sessions/{sid}/{edit['previews'][slot]['after']}").content
        for slot in edit["slots"]
    }
    r = client.post(f"/api/sessions/{sid}/suggestions/{edit['id']}/accept")
    assert r.status_code == 200, r.text
    answer = r.json()
    state = answer["state"]
    assert answer["accepted"] == edit["id"]
    assert state["revision"] > before["revision"]
    for slot in edit["slots"]:
        assert "suggested edit accepted" in " ".join(state["images"][slot]["notes"])
        # the new input picture is the suggestion's "after" picture, at the piece's grid
        shown = np.asarray(Image.open(io.BytesIO(after_png[slot])).convert("RGB"))
        r = client.get(f"/api/sessions/{sid}/images/{slot}")
        new = np.asarray(Image.open(io.BytesIO(r.content)).convert("RGB"))
        # kept in the fabric's proportions (8 pixels a unit across, 0.7 of that down), so
        # sizing it again at 24 units gives the edited grid back
        from illuknit.pictures.sizing import size_pair

        assert new.shape[1] == 24 * 8
        k = shown.shape[1] // 24
        again = np.round(size_pair(new, width=24, smooth=False).a * 255).astype(np.uint8)
        assert np.array_equal(shown[::k, ::k], again)
        assert client.get(f"/api/sessions/{sid}/inputs/{slot}.png").content != old_inputs[slot]
    # the design is made again: a candidates job was started by the accept
    assert answer["job"]["kind"] == "candidates"
    assert api.wait_job(client, sid, answer["job"]["id"])["status"] == "done"
    cands = client.get(f"/api/sessions/{sid}/candidates").json()
    assert cands["revision"] == state["revision"] and cands["candidates"]
    # the accepted set belongs to the earlier design now
    assert client.get(f"/api/sessions/{sid}/suggestions").json()["set"] is None


def test_a_suggestion_of_a_superseded_design_answers_410_with_its_successor(client, api, suggested):
    sid, got = suggested
    old = got["suggestions"][0]["id"]
    r = client.put(f"/api/sessions/{sid}/settings", json={"width_units": 25})
    assert r.status_code == 200
    for method, path in (
        ("post", f"/suggestions/{old}/accept"),
        ("post", f"/suggestions/{old}/refuse"),
        ("get", f"/suggestions/{old}/a/after.png"),
    ):
        r = getattr(client, method)(f"/api/sessions/{sid}{path}")
        assert r.status_code == 410, r.text
        e = r.json()["error"]
        assert e["code"] == "superseded" and e["field"] == "suggestions"
        assert "earlier design" in e["message"] and e["successor"] is None
    # once new suggestions exist, the old id names them as its successor
    assert api.run_job(client, sid, "suggestions")["status"] == "done"
    new_set = client.get(f"/api/sessions/{sid}/suggestions").json()["set"]
    r = client.post(f"/api/sessions/{sid}/suggestions/{old}/accept")
    assert r.status_code == 410 and r.json()["error"]["successor"] == new_set


def test_refuse_hides_a_suggestion(client, suggested):
    sid, got = suggested
    first = got["suggestions"][0]["id"]
    r = client.post(f"/api/sessions/{sid}/suggestions/{first}/refuse")
    assert r.status_code == 200
    body = r.json()
    assert first not in [s["id"] for s in body["suggestions"]]
    assert body["refused"] == 1
    listed = client.get(f"/api/sessions/{sid}/suggestions").json()
    assert first not in [s["id"] for s in listed["suggestions"]]
    # refusing changes nothing else: same design, same pictures
    assert listed["revision"] == got["revision"]


@pytest.mark.parametrize("bad", ["nonsense", "abc.1", "", "1.2.3", "x" * 300])
def test_unknown_suggestion_ids_are_404_with_a_message(client, api, suggested, bad):
    sid, _ = suggested
    for path in (f"/suggestions/{bad}/accept", f"/suggestions/{bad}/refuse"):
        r = client.post(f"/api/sessions/{sid}{path}")
        assert 400 <= r.status_code < 500, r.text
        e = api.error_of(r)
        assert "Traceback" not in e["message"]
        if bad:
            assert e["code"] == "no_suggestion" and r.status_code == 404


def test_a_missing_number_in_the_current_set_is_404_and_lists_the_real_ones(client, api, suggested):
    sid, got = suggested
    r = client.post(f"/api/sessions/{sid}/suggestions/{got['set']}.99/accept")
    assert r.status_code == 404
    e = api.error_of(r)
    assert e["code"] == "no_suggestion" and got["suggestions"][0]["id"] in e["message"]


def test_bad_preview_requests(client, api, suggested):
    sid, got = suggested
    s = got["suggestions"][0]
    assert client.get(f"/api/sessions/{sid}/suggestions/{s['id']}/c/after.png").status_code == 404
    r = client.get(f"/api/sessions/{sid}/suggestions/{s['id']}/a/during.png")
    assert r.status_code == 422 and api.error_of(r)
    unchanged = [slot for slot in ("a", "b") if slot not in s["slots"]]
    for slot in unchanged:
        r = client.get(f"/api/sessions/{sid}/suggestions/{s['id']}/{slot}/after.png")
        assert r.status_code == 404 and api.error_of(r)["code"] == "unchanged"


def test_suggestions_are_for_double_view_only(client, api, pictures):
    sid = client.post("/api/sessions").json()["id"]
    files = {"file": ("UP.png", pictures.word("UP"), "image/png")}
    assert client.put(f"/api/sessions/{sid}/images/a", files=files).status_code == 200
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 24})
    r = client.post(f"/api/sessions/{sid}/jobs", json={"kind": "suggestions"})
    assert r.status_code == 409
    e = api.error_of(r)
    assert e["code"] == "not_double" and e["field"] == "suggestions"
    assert client.get(f"/api/sessions/{sid}/suggestions").json()["suggestions"] == []


def test_suggestions_count_in_the_session_memory(client, suggested):
    sid, _ = suggested
    s = client.app.state.store.get(sid)
    with s.lock:
        kept = s.suggestions
        held = kept.nbytes()
        with_them = s.nbytes()
        s.suggestions = None
        without = s.nbytes()
        s.suggestions = kept
    pictures = list(kept.originals.values()) + [p for e in kept.edits for p in e.pictures.values()]
    assert held == sum(p.nbytes for p in pictures) > 0
    assert with_them - without == held


def test_accepting_a_requantisation_changes_the_colour_count_with_it(client, api, pictures):
    """Three-colour pictures read with two colours, three yarns: the library suggests reading
    them with three; accepting it sets Colours per picture to 3, and the quantised inputs are
    exactly the edited pictures (quantising them again does not undo the edit)."""
    sid = client.post("/api/sessions").json()["id"]
    for slot, text, rows in (("a", "UP", slice(0, 12)), ("b", "ON", slice(36, 48))):
        files = {"file": (f"{text}.png", pictures.word(text, rows), "image/png")}
        assert client.put(f"/api/sessions/{sid}/images/{slot}", files=files).status_code == 200
    yarns = ["#1b1b1b", "#8a8a8a", "#f4f0e8"]
    r = client.put(
        f"/api/sessions/{sid}/settings",
        json={"mode": "double", "width_units": 24, "yarns": yarns, "n_colors": 2},
    )
    assert r.status_code == 200
    assert api.run_job(client, sid, "suggestions")["status"] == "done"
    got = client.get(f"/api/sessions/{sid}/suggestions").json()["suggestions"]
    more = [s for s in got if s["kind"] == "requantise"]
    assert more, [s["edit"] for s in got]
    edit = more[0]
    assert "3 colours" in edit["description"]
    after = {
        slot: np.asarray(
            Image.open(
                io.BytesIO(
                    client.get(f"/api/sessions/{sid}/{edit['previews'][slot]['after']}").content
                )
            ).convert("RGB")
        )
        for slot in edit["slots"]
    }
    r = client.post(f"/api/sessions/{sid}/suggestions/{edit['id']}/accept")
    assert r.status_code == 200, r.text
    assert r.json()["state"]["settings"]["n_colors"] == 3
    inputs = client.get(f"/api/sessions/{sid}/inputs").json()
    for slot in edit["slots"]:
        assert len(inputs["legend"][slot]) == 3
        s = client.app.state.store.get(sid)
        q = s.prepared.quantised[slot]
        shown = after[slot]
        k = shown.shape[1] // q.shape[1]
        assert np.array_equal(q.colors[q.indices], shown[::k, ::k])
    assert api.wait_job(client, sid, r.json()["job"]["id"])["status"] == "done"


def test_kept_suggestions_make_room_under_the_memory_bound(api, pictures):
    """Suggestions count in the sessions' memory bound when they are kept: storing them closes
    the least recently used session (told so with 410 ``evicted``), never the one at work."""
    with TestClient(create_app(AppConfig(isolate_knit=False))) as client:
        _fill_until_suggestions_evict(client, api, pictures)


def _fill_until_suggestions_evict(client: TestClient, api: Any, pictures: Any) -> None:
    store = client.app.state.store
    idle = client.post("/api/sessions").json()["id"]
    files = {"file": ("UP.png", pictures.word("UP"), "image/png")}
    assert client.put(f"/api/sessions/{idle}/images/a", files=files).status_code == 200
    sid = client.post("/api/sessions").json()["id"]
    for slot, text in (("a", "UP"), ("b", "ON")):
        files = {"file": (f"{text}.png", pictures.word(text), "image/png")}
        assert client.put(f"/api/sessions/{sid}/images/{slot}", files=files).status_code == 200
    r = client.put(f"/api/sessions/{sid}/settings", json={"mode": "double", "width_units": 24})
    assert r.status_code == 200 and client.get(f"/api/sessions/{sid}/inputs").status_code == 200
    limit = store.max_bytes
    store.max_bytes = store.nbytes() + 1  # everything fits now, not one more picture
    try:
        assert api.run_job(client, sid, "suggestions")["status"] == "done"
    finally:
        store.max_bytes = limit
    assert client.get(f"/api/sessions/{sid}/suggestions").json()["suggestions"]
    r = client.get(f"/api/sessions/{idle}")
    assert r.status_code == 410 and api.error_of(r)["code"] == "evicted"


def test_suggestions_report_the_library_review_progress_and_cancel_through_it(pictures):
    """The job's progress is the library review's (:func:`review_edits`' hook): finding the
    edits, then each measurement by name; a cancelled job raises out of the review."""
    from illuknit.app import design
    from illuknit.app.jobs import JobCancelled
    from illuknit.app.schemas import DesignSettings
    from illuknit.app.sessions import UploadedImage
    from illuknit.app.suggestions import suggest_edits_for

    images = {
        slot: UploadedImage(
            f"{text}.png", 0, np.asarray(Image.open(io.BytesIO(pictures.word(text))))
        )
        for slot, text in (("a", "UP"), ("b", "ON"))
    }
    settings = DesignSettings(mode="double", width_units=24)
    prepared = design.prepare_inputs(images, settings)
    sources, _ = design.size_inputs(images, settings)
    seen: list[tuple[float, str]] = []
    got = suggest_edits_for(
        prepared,
        sources=sources,
        set_id="s",
        revision=0,
        count=2,
        progress=lambda f, m: seen.append((f, m)),
    )
    assert got.edits
    fractions = [f for f, _ in seen]
    assert fractions == sorted(fractions) and fractions[0] >= 0.02 and fractions[-1] < 1
    assert [m for _, m in seen] == [
        "finding edits",
        "measuring the pictures as they are",
        *(f"measuring {e.description}" for e in got.edits),
    ]

    def cancelled_at_the_second_measurement(fraction: float, message: str) -> None:
        if message != "finding edits" and message != "measuring the pictures as they are":
            raise JobCancelled

    with pytest.raises(JobCancelled):
        suggest_edits_for(
            prepared,
            sources=sources,
            set_id="t",
            revision=0,
            count=2,
            progress=cancelled_at_the_second_measurement,
        )


def test_suggestions_in_their_own_process_report_progress_and_cancel_at_once(api):
    """Served as by default (the measurements in a worker process): the job's progress comes
    from the worker as each edit is measured, and Cancel kills it within 2 s."""
    import time

    from skimage import data

    def crop(rgb: Any) -> bytes:
        h, w = rgb.shape[:2]
        buf = io.BytesIO()
        top, left = (h - 300) // 2, (w - 300) // 2
        Image.fromarray(np.ascontiguousarray(rgb[top : top + 300, left : left + 300])).save(
            buf, format="PNG"
        )
        return buf.getvalue()

    with TestClient(create_app(AppConfig(isolate_knit=False, isolate_search=True))) as client:
        sid = client.post("/api/sessions").json()["id"]
        for slot, name in (("a", "astronaut"), ("b", "coffee")):
            files = {"file": (f"{name}.png", crop(getattr(data, name)()), "image/png")}
            assert client.put(f"/api/sessions/{sid}/images/{slot}", files=files).status_code == 200
        body = {
            "width_units": 120,
            "n_colors": 3,
            "yarns": ["#1b1b1b", "#8a8a8a", "#f4f0e8"],
            "machine": "generic540",
        }
        assert client.put(f"/api/sessions/{sid}/settings", json=body).status_code == 200
        job = client.post(f"/api/sessions/{sid}/jobs", json={"kind": "suggestions"}).json()
        deadline = time.monotonic() + 120
        while not job["message"].startswith("measuring"):
            assert job["status"] in ("queued", "running"), job
            assert time.monotonic() < deadline, job
            time.sleep(0.1)
            job = client.get(f"/api/sessions/{sid}/jobs/{job['id']}").json()
        assert job["progress"] >= 0.02
        t0 = time.monotonic()
        r = client.delete(f"/api/sessions/{sid}/jobs/{job['id']}")
        assert r.json()["status"] == "cancelled" and time.monotonic() - t0 < 2.0
