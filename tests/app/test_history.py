"""Undo and redo of every change (uploads, settings, tile edits, accepted suggested edits): the
design before the change comes back exactly, empty histories and closed sessions answer plainly,
and the history counts in the memory bound."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")

from fastapi.testclient import TestClient

from illuknit.app import create_app
from illuknit.app.history import STEPS_KEPT
from illuknit.app.server import AppConfig


@pytest.fixture(scope="module")
def two_words(pictures: Any) -> Callable[..., str]:
    """``two_words(client, **settings)``: a double-view session of "UP" over "ON" at 24 units
    (or ``settings``; ``grey_a``: rows of "UP" on a third colour)."""

    def make(client: TestClient, **settings: Any) -> str:
        sid = client.post("/api/sessions").json()["id"]
        for slot, text, grey in (("a", "UP", settings.pop("grey_a", None)), ("b", "ON", None)):
            files = {"file": (f"{text}.png", pictures.word(text, grey), "image/png")}
            r = client.put(f"/api/sessions/{sid}/images/{slot}", files=files)
            assert r.status_code == 200
        body = {"mode": "double", "width_units": 24, **settings}
        assert client.put(f"/api/sessions/{sid}/settings", json=body).status_code == 200
        return sid

    return make


def design_seen(client: TestClient, sid: str) -> dict[str, Any]:
    """Everything the page shows of a design, revision numbers aside: the pictures (PNG bytes),
    the quantised inputs, settings, candidates with their measures, the pick, the suggestions."""
    base = f"/api/sessions/{sid}"
    state = client.get(base).json()
    inputs = client.get(f"{base}/inputs").json()
    cands = client.get(f"{base}/candidates").json()
    suggs = client.get(f"{base}/suggestions").json()
    return {
        "settings": state["settings"],
        "images": {k: {**v, "url": None} for k, v in state["images"].items()},
        "pictures": {slot: client.get(f"{base}/images/{slot}").content for slot in ("a", "b")},
        "quantised": {slot: client.get(f"{base}/inputs/{slot}.png").content for slot in ("a", "b")},
        "legend": inputs["legend"],
        "candidates": cands["candidates"],
        "selected": cands["selected"],
        "suggestions": {k: v for k, v in suggs.items() if k != "revision"},
    }


def test_undo_brings_back_the_design_before_the_accept_and_redo_the_one_after(
    client, api, two_words
):
    sid = two_words(client)
    base = f"/api/sessions/{sid}"
    assert api.run_job(client, sid, "candidates")["status"] == "done"
    assert api.run_job(client, sid, "measures")["status"] == "done"
    assert api.run_job(client, sid, "suggestions")["status"] == "done"
    before = design_seen(client, sid)
    assert before["candidates"] and all(c["measures"] for c in before["candidates"])
    edit = before["suggestions"]["suggestions"][0]

    r = client.post(f"{base}/suggestions/{edit['id']}/accept")
    assert r.status_code == 200, r.text
    assert api.wait_job(client, sid, r.json()["job"]["id"])["status"] == "done"
    assert api.run_job(client, sid, "measures")["status"] == "done"
    after = design_seen(client, sid)
    assert after["pictures"] != before["pictures"]
    state = client.get(base).json()
    assert state["history"]["undo"][0] == edit["description"] and state["history"]["redo"] == []
    # below it, the changes that made the design: the settings, then the two uploads
    # (sized from picture A until then: 72 px wide, 72 units by the sizing policy)
    assert (
        state["history"]["undo"][1] == "change of size by picture -> units, width (units) 72 -> 24"
    )
    assert state["history"]["undo"][2:] == [
        "upload of picture B (ON.png)",
        "upload of picture A (UP.png)",
    ]

    r = client.post(f"{base}/history/undo")
    assert r.status_code == 200, r.text
    answer = r.json()
    assert answer["undone"] == edit["description"]
    assert answer["job"] is None  # the candidates come back with the design: no new search
    assert answer["state"]["revision"] > state["revision"]
    assert answer["state"]["history"]["redo"] == [edit["description"]]
    assert answer["state"]["history"]["undo"] == state["history"]["undo"][1:]
    # byte-identical pictures, the same quantised inputs, candidates, measures, suggestions
    assert design_seen(client, sid) == before
    assert client.get(f"{base}/candidates").json()["revision"] == answer["state"]["revision"]
    # the suggestions of that design are live again: their previews answer, not 410
    assert client.get(f"{base}/{edit['previews'][edit['slots'][0]]['after']}").status_code == 200

    r = client.post(f"{base}/history/redo")
    assert r.status_code == 200, r.text
    assert r.json()["redone"] == edit["description"] and r.json()["job"] is None
    assert design_seen(client, sid) == after
    # the ids of the design left behind are superseded again
    r = client.post(f"{base}/suggestions/{edit['id']}/accept")
    assert r.status_code == 410 and api.error_of(r)["code"] == "superseded"

    # undo, then another change: what was undone cannot be redone any more
    assert client.post(f"{base}/history/undo").status_code == 200
    assert client.put(f"{base}/settings", json={"width_units": 25}).status_code == 200
    now = client.get(f"{base}/history").json()
    assert now["redo"] == [] and now["undo"][0] == "change of width (units) 24 -> 25"


def test_undo_of_a_requantisation_gives_back_the_colour_count(client, api, two_words):
    sid = two_words(
        client, grey_a=slice(0, 12), yarns=["#1b1b1b", "#8a8a8a", "#f4f0e8"], n_colors=2
    )
    base = f"/api/sessions/{sid}"
    assert api.run_job(client, sid, "suggestions")["status"] == "done"
    before = design_seen(client, sid)
    edit = next(s for s in before["suggestions"]["suggestions"] if s["edit"] == "requantise-3")
    r = client.post(f"{base}/suggestions/{edit['id']}/accept")
    assert r.status_code == 200 and r.json()["state"]["settings"]["n_colors"] == 3
    r = client.post(f"{base}/history/undo")
    assert r.status_code == 200
    # no candidates had been found before the accept: the search starts again, as after one
    assert r.json()["job"]["kind"] == "candidates"
    assert r.json()["state"]["settings"]["n_colors"] == 2
    assert api.wait_job(client, sid, r.json()["job"]["id"])["status"] == "done"
    now = design_seen(client, sid)
    assert {k: now[k] for k in ("settings", "pictures", "quantised", "legend", "suggestions")} == {
        k: before[k] for k in ("settings", "pictures", "quantised", "legend", "suggestions")
    }


def test_nothing_to_undo_or_redo_is_409_with_a_message(client, api):
    sid = client.post("/api/sessions").json()["id"]
    for what in ("undo", "redo"):
        r = client.post(f"/api/sessions/{sid}/history/{what}")
        assert r.status_code == 409
        e = api.error_of(r)
        assert e["code"] == f"nothing_to_{what}" and e["field"] == "suggestions"
        assert f"nothing to {what}" in e["message"]
    assert client.get(f"/api/sessions/{sid}/history").json() == {"undo": [], "redo": []}


def test_undo_in_a_closed_session_says_what_happened(client, api, two_words):
    store = client.app.state.store
    sid = two_words(client)
    api.evict(store, sid)
    r = client.post(f"/api/sessions/{sid}/history/undo")
    assert r.status_code == 410 and api.error_of(r)["code"] == "evicted"
    r = client.post("/api/sessions/nonsense/history/redo")
    assert r.status_code == 404 and api.error_of(r)["code"] == "no_session"


def held(arrays: list[np.ndarray]) -> dict[int, int]:
    return {id(a): a.nbytes for a in arrays}


def design_arrays(images, prepared, candidates, suggestions) -> list[np.ndarray]:
    out = [im.rgb for im in images.values()]
    out += [] if prepared is None else [q.indices for q in prepared.quantised.values()]
    out += [a for c in candidates for a in (c.pattern.yarn, c.pattern.raised)]
    if suggestions is not None:
        out += list(suggestions.originals.values())
        out += [p for e in suggestions.edits for p in e.pictures.values()]
    return out


def test_the_history_counts_in_the_session_memory_once(api, two_words):
    """After an accept the session holds the design before it too: the pictures the edit
    replaced, its quantised inputs, candidates and suggestions; a picture the edit left alone is
    the same array in both and counts once. The bound sees it: keeping it closes the least
    recently used session."""
    with TestClient(create_app(AppConfig(isolate_knit=False))) as client:
        store = client.app.state.store
        idle = client.post("/api/sessions").json()["id"]
        sid = two_words(client)
        assert api.run_job(client, sid, "candidates")["status"] == "done"
        assert api.run_job(client, sid, "suggestions")["status"] == "done"
        s = store.get(sid)
        edit = s.suggestions.edits[0]
        limit = store.max_bytes
        store.max_bytes = store.nbytes() + 1  # everything fits now, nothing more
        try:
            r = client.post(f"/api/sessions/{sid}/suggestions/{edit.id}/accept")
            assert r.status_code == 200
            with s.lock:
                total = s.nbytes()
                steps, s.undo_steps = s.undo_steps, []
                without = s.nbytes()
                s.undo_steps = steps
                now = held(design_arrays(s.images, s.prepared, s.candidates, s.suggestions))
            old = steps[-1]  # the design before the accept (the uploads' steps below it)
            kept = held(design_arrays(old.images, old.prepared, old.candidates, old.suggestions))
        finally:
            store.max_bytes = limit
        only_kept = {k: v for k, v in kept.items() if k not in now}
        assert total - without == sum(only_kept.values())
        for slot in ("a", "b"):
            replaced = slot in edit.changed
            assert (old.images[slot] is s.images[slot]) != replaced
            assert (id(old.images[slot].rgb) in only_kept) == replaced
        assert sum(old.images[slot].nbytes for slot in edit.changed) > 0
        r = client.get(f"/api/sessions/{idle}")
        assert r.status_code == 410 and api.error_of(r)["code"] == "evicted"


def test_the_history_is_bounded():
    from illuknit.app.sessions import Session

    s = Session(id="x")
    for k in range(STEPS_KEPT + 3):
        s.remember(f"step {k}")
        s.bump()
    assert [st.label for st in s.undo_steps] == [f"step {k}" for k in range(3, STEPS_KEPT + 3)]
    for _ in range(STEPS_KEPT):
        s.undo()
    assert len(s.redo_steps) == STEPS_KEPT and not s.undo_steps


def test_undo_while_the_accepted_design_is_searched_keeps_the_design_before(client, api, two_words):
    """Undo right after an accept: the search for the edited pictures is cancelled (or, if it
    already ended, its candidates belong to the state left behind), and whenever it ends the
    session shows the candidates of before."""
    sid = two_words(client)
    base = f"/api/sessions/{sid}"
    assert api.run_job(client, sid, "candidates")["status"] == "done"
    assert api.run_job(client, sid, "suggestions")["status"] == "done"
    before = design_seen(client, sid)
    edit = before["suggestions"]["suggestions"][0]
    r = client.post(f"{base}/suggestions/{edit['id']}/accept")
    search = r.json()["job"]["id"]
    r = client.post(f"{base}/history/undo")
    assert r.status_code == 200 and r.json()["job"] is None
    assert api.wait_job(client, sid, search)["status"] in ("cancelled", "done")
    assert design_seen(client, sid) == before


def test_undo_takes_back_a_tile_edit_an_upload_and_a_setting(client, api, two_words, pictures):
    sid = two_words(client)
    base = f"/api/sessions/{sid}"
    assert api.run_job(client, sid, "candidates")["status"] == "done"
    before = design_seen(client, sid)
    pairs = client.get(f"{base}/pairs").json()
    row = pairs["pairs"][0]
    other = next(o["id"] for o in row["options"] if o["id"] != row["tile"])
    r = client.put(f"{base}/pairs/{row['a']}/{row['b']}", json={"tile": other})
    assert r.status_code == 200
    label = client.get(f"{base}/history").json()["undo"][0]
    assert label.startswith("tile edit: A colour") and other in label
    r = client.post(f"{base}/history/undo")
    assert r.status_code == 200 and r.json()["undone"] == label and r.json()["job"] is None
    assert r.json()["state"]["overrides"] == []
    assert design_seen(client, sid) == before
    r = client.post(f"{base}/history/redo")
    assert r.json()["state"]["overrides"] == [{"a": row["a"], "b": row["b"], "tile": other}]
    assert client.post(f"{base}/history/undo").status_code == 200

    # a new picture B, then a setting: each is undone in turn, the pictures byte for byte
    files = {"file": ("OK.png", pictures.word("OK"), "image/png")}
    assert client.put(f"{base}/images/b", files=files).status_code == 200
    assert client.put(f"{base}/settings", json={"n_colors": 3}).status_code == 200
    hist = client.get(f"{base}/history").json()["undo"]
    assert hist[:2] == [  # a third colour brings a third yarn, from the pictures
        "change of colours per picture 2 -> 3, yarns (2 -> 3)",
        "upload of picture B (OK.png)",
    ]
    r = client.post(f"{base}/history/undo")
    assert r.json()["state"]["settings"]["n_colors"] == 2
    r = client.post(f"{base}/history/undo")
    assert r.json()["undone"] == "upload of picture B (OK.png)"
    assert r.json()["state"]["images"]["b"]["filename"] == "ON.png"
    assert design_seen(client, sid)["pictures"] == before["pictures"]
