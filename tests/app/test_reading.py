"""Does each side read? The reader's verdict on the app's cards, and the widths job that finds
how wide a double view must be for both sides to read (``illuknit/app/reading.py``, issue 38).

Tests that need tesseract take the ``reader`` fixture (tests/conftest.py): skipped with the
reason where it is missing, failed under ``CI=true``. The words are never the benchmark's.
"""

from __future__ import annotations

import shutil
from typing import Any

import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")

from illuknit.app.reading import NOT_INSTALLED, legibility_json
from illuknit.design.legibility import Legibility, SideReading


def _words(client: Any, api: Any, pictures: Any, a: str = "UP", b: str = "ON") -> str:
    """A double-view session of two words, 24 units wide (no search yet)."""
    sid = api.new_session(client)
    assert api.upload(client, sid, "a", pictures.word(a)).status_code == 200
    assert api.upload(client, sid, "b", pictures.word(b)).status_code == 200
    r = client.put(f"/api/sessions/{sid}/settings", json={"mode": "double", "width_units": 24})
    assert r.status_code == 200
    return sid


def _cards(client: Any, api: Any, sid: str) -> list[dict[str, Any]]:
    job = api.run_job(client, sid, "candidates")
    assert job["status"] == "done", job
    got = client.get(f"/api/sessions/{sid}/candidates").json()["candidates"]
    assert got
    return list(got)


def _no_reader(monkeypatch: pytest.MonkeyPatch) -> None:
    real = shutil.which
    monkeypatch.setattr(shutil, "which", lambda n, *a, **k: None if n == "tesseract" else real(n))


def _broken_reader(tmp_path: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    """A tesseract that fails as an install without its language data does."""
    fake = tmp_path / "tesseract"
    fake.write_text("#!/bin/sh\necho 'Error opening data file eng.traineddata' >&2\nexit 1\n")
    fake.chmod(0o755)
    monkeypatch.setenv("ILLUKNIT_READER", str(fake))


# -- the verdict's JSON (no reader needed) --------------------------------------------------------


def test_the_card_json_says_the_side_that_does_not_read_first():
    verdict = Legibility(
        (SideReading("A", "FIG", "FIG", True, 0.90), SideReading("B", "ELM", "EIM", False, 0.97)),
        35.0,
        4.0,
    )
    got = legibility_json(verdict, None)
    assert [s["view"] for s in got["sides"]] == ["B", "A"]
    assert got["sentence"].startswith("side B does not read ELM (the reader saw 'EIM')")
    assert got["read"] and not got["all_read"] and not got["estimate"]
    assert (got["angle"], got["distance_m"]) == (35.0, 4.0)
    # both read: the lower correlation first
    both = Legibility(
        (SideReading("A", "FIG", "FIG", True, 0.97), SideReading("B", "ELM", "ELM", True, 0.91)),
        30.0,
        3.0,
    )
    assert [s["view"] for s in legibility_json(both, None)["sides"]] == ["B", "A"]


def test_a_picture_side_is_labelled_an_estimate_and_an_unread_card_says_why():
    shapes = Legibility(
        (SideReading("A", None, None, True, 0.9, 0.93), SideReading("B", "ELM", "ELM", True, 0.95)),
        30.0,
        3.0,
    )
    got = legibility_json(shapes, None)
    assert got["estimate"] and got["sides"][0]["judge"] == "shapes"
    assert "an estimate, not a reader's verdict" in got["sentence"]
    unread = legibility_json(None, NOT_INSTALLED)
    assert unread == {
        "read": False,
        "why": NOT_INSTALLED,
        "sentence": f"not read: {NOT_INSTALLED}",
    }
    assert unread["sentence"].startswith("not read: tesseract is not installed")


# -- the cards -------------------------------------------------------------------------------------


def test_cards_carry_the_readers_verdict_weaker_side_first(client, api, pictures, reader):
    from illuknit.app.reading import read_candidates

    sid = _words(client, api, pictures)
    cards = _cards(client, api, sid)
    session = client.app.state.store.get(sid)
    patterns = [c.pattern for c in session.candidates]
    # the verdict the library gives the very designs, from the session's viewpoint
    again = read_candidates(
        patterns, session.prepared, machine=session.settings.machine, viewpoint=(30.0, 3.0)
    )
    by_rank = {c["rank"]: c for c in cards}
    for cand, verdict in zip(session.candidates, again, strict=True):
        card = by_rank[cand.rank]["details"]["legibility"]
        assert card["read"] is True and card["reader"] == "tesseract"
        assert (card["angle"], card["distance_m"]) == (30.0, 3.0)
        sides = card["sides"]
        assert sorted(s["view"] for s in sides) == ["A", "B"]
        # weaker first: a side that does not read before one that does, then the lower
        # correlation
        keys = [(s["reads"], s["correlation"]) for s in sides]
        assert keys == sorted(keys)
        assert card["sentence"] == "; ".join(s["sentence"] for s in sides)
        assert {s["view"]: s["words"] for s in sides} == {"A": "UP", "B": "ON"}
        assert {s["view"]: s["reads"] for s in sides} == {s.view: s.reads for s in verdict.sides}


def test_a_new_viewpoint_reads_the_cards_again_from_there(client, api, pictures, reader):
    sid = _words(client, api, pictures, "HI", "YO")
    _cards(client, api, sid)
    assert api.run_job(client, sid, "measures")["status"] == "done"
    r = client.put(f"/api/sessions/{sid}/settings", json={"view_angle": 45, "view_distance": 6})
    assert r.status_code == 200
    assert api.run_job(client, sid, "measures")["status"] == "done"
    got = client.get(f"/api/sessions/{sid}/candidates").json()
    for card in got["candidates"]:
        verdict = card["details"]["legibility"]
        assert (verdict["angle"], verdict["distance_m"]) == (45.0, 6.0), verdict
        assert card["measures"] is not None


def test_without_the_reader_the_cards_say_so_and_the_search_stands(
    client, api, pictures, monkeypatch
):
    _no_reader(monkeypatch)
    sid = _words(client, api, pictures)
    for card in _cards(client, api, sid):
        verdict = card["details"]["legibility"]
        assert verdict["read"] is False
        assert verdict["sentence"] == f"not read: {NOT_INSTALLED}"
    r = client.post(f"/api/sessions/{sid}/jobs", json={"kind": "widths"})
    assert r.status_code == 409
    error = api.error_of(r)
    assert error["field"] == "widths" and "apt-get install tesseract-ocr" in error["message"]
    assert client.get(f"/api/sessions/{sid}/widths").json()["reader"] is False


def test_a_broken_reader_leaves_the_cards_unread_with_why(
    client, api, pictures, tmp_path, monkeypatch
):
    _broken_reader(tmp_path, monkeypatch)
    sid = _words(client, api, pictures)
    for card in _cards(client, api, sid):
        verdict = card["details"]["legibility"]
        assert verdict["read"] is False
        assert "failed: Error opening data file eng.traineddata" in verdict["why"]
    job = api.run_job(client, sid, "widths")
    assert job["status"] == "failed"
    assert job["error"]["field"] == "widths" and job["error"]["code"] != "internal"
    assert "Error opening data file" in job["error"]["message"]


def test_a_single_view_is_not_read_and_has_no_width_to_find(client, api, pictures):
    sid = api.new_session(client)
    assert api.upload(client, sid, "a", pictures.word("UP")).status_code == 200
    r = client.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 24})
    assert r.status_code == 200
    for card in _cards(client, api, sid):
        assert "legibility" not in card["details"]
    r = client.post(f"/api/sessions/{sid}/jobs", json={"kind": "widths"})
    assert r.status_code == 409 and api.error_of(r)["field"] == "widths"


# -- how wide must it be ---------------------------------------------------------------------------


def _check_widths(found: dict[str, Any], asked: list[int]) -> None:
    widths = [v["width"] for v in found["tried"]]
    assert widths == asked[: len(widths)]  # narrowest first, stopping at the first that reads
    for v in found["tried"]:
        assert v["both_read"] <= (v["a_reads"] and v["b_reads"])
        assert v["width_cm"] > 0 and v["sentence"]
    firsts = [v["width"] for v in found["tried"] if v["both_read"]]
    assert found["both"] == (firsts[0] if firsts else None)
    if found["both"] is None:
        assert widths == asked and found["sentence"].startswith("no width up to")
    else:
        assert widths[-1] == found["both"]
    assert found["words"] == ["UP", "ON"]


def test_the_widths_job_reports_each_width_and_the_smallest_that_reads(
    client, api, pictures, reader
):
    sid = _words(client, api, pictures)
    asked = [12, 24, 36]
    r = client.post(f"/api/sessions/{sid}/jobs", json={"kind": "widths", "widths": asked})
    assert r.status_code == 202, r.text
    assert api.wait_job(client, sid, r.json()["id"], 300)["status"] == "done"
    got = client.get(f"/api/sessions/{sid}/widths").json()
    assert got["reader"] is True and got["current"] is True
    _check_widths(got["result"], asked)
    # the answer stands when the width changes (it is what it answers) ...
    r = client.put(f"/api/sessions/{sid}/settings", json={"width_units": 30})
    assert client.get(f"/api/sessions/{sid}/widths").json()["current"] is True
    # ... not when the viewpoint it was read from does
    r = client.put(f"/api/sessions/{sid}/settings", json={"view_distance": 9})
    assert r.status_code == 200
    assert client.get(f"/api/sessions/{sid}/widths").json()["current"] is False


def test_widths_are_bounded_where_they_are_parsed(client, api, pictures):
    sid = _words(client, api, pictures)
    for bad in ([], [3], [12, 2000], ["x"]):
        r = client.post(f"/api/sessions/{sid}/jobs", json={"kind": "widths", "widths": bad})
        assert r.status_code == 422, (bad, r.text)
        assert api.error_of(r)["field"] == "widths"


def test_the_widths_job_runs_in_its_worker_process(api, pictures, reader):
    """The app as served: the search and the widths job in their own processes."""
    from fastapi.testclient import TestClient

    from illuknit.app import create_app
    from illuknit.app.server import AppConfig

    with TestClient(create_app(AppConfig(isolate_knit=True))) as c:
        sid = _words(c, api, pictures)
        r = c.post(f"/api/sessions/{sid}/jobs", json={"kind": "widths", "widths": [12, 24]})
        job = api.wait_job(c, sid, r.json()["id"], 300)
        assert job["status"] == "done", job
        _check_widths(c.get(f"/api/sessions/{sid}/widths").json()["result"], [12, 24])
        # and the cards are read again, in the measures job's process, from a new viewpoint
        _cards(c, api, sid)
        assert c.put(f"/api/sessions/{sid}/settings", json={"view_distance": 5}).status_code == 200
        assert api.run_job(c, sid, "measures")["status"] == "done"
        for card in c.get(f"/api/sessions/{sid}/candidates").json()["candidates"]:
            assert card["details"]["legibility"]["distance_m"] == 5.0
