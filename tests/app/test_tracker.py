"""The row tracker (``/tracker``) and the square-units setting, through the JSON API."""

from __future__ import annotations

import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")


def check_the_tracker(c, sid: str, api) -> str:
    """The tracker of session ``sid``'s picked pattern: chart, written rows, moves; its key."""
    r = c.get(f"/api/sessions/{sid}/tracker")
    assert r.status_code == 200, r.text
    t = r.json()
    n = len(c.get(f"/api/sessions/{sid}/download/pattern.json").json()["yarn"])
    assert t["row"] == 1 and t["rows"] == 2 * n
    assert len(t["chart"]) == len(t["purl"]) == len(t["written"]) == t["rows"]
    assert {len(row) for row in t["chart"]} == {t["stitches"]}
    assert [w["number"] for w in t["written"]] == list(range(1, t["rows"] + 1))
    assert t["written"][0]["side"] == "RS" and t["written"][1]["side"] == "WS"
    assert t["written"][4]["text"].endswith(f"({t['stitches']} sts).")
    put = c.put(f"/api/sessions/{sid}/tracker", json={"row": 5, "key": t["key"]})
    assert put.status_code == 200, put.text
    assert c.get(f"/api/sessions/{sid}/tracker").json()["row"] == 5
    # a move made for another pattern (the pick changed since) is refused, not applied
    stale = c.put(f"/api/sessions/{sid}/tracker", json={"row": 2, "key": "0" * 16})
    assert stale.status_code == 409 and api.error_of(stale)["code"] == "stale"
    beyond = c.put(f"/api/sessions/{sid}/tracker", json={"row": t["rows"] + 1, "key": t["key"]})
    assert beyond.status_code >= 400 and api.error_of(beyond)["field"] == "tracker"
    zero = c.put(f"/api/sessions/{sid}/tracker", json={"row": 0, "key": t["key"]})
    assert zero.status_code == 422
    assert c.get(f"/api/sessions/{sid}/tracker").json()["row"] == 5
    put = c.put(f"/api/sessions/{sid}/tracker", json={"row": 7, "key": t["key"]})
    assert put.status_code == 200, put.text
    return str(t["key"])


def test_the_tracker_follows_the_pick_and_its_row_survives_a_restart(tmp_path, pictures, api):
    from fastapi.testclient import TestClient

    from illuknit.app import create_app
    from illuknit.app.server import AppConfig

    def app():
        return create_app(AppConfig(isolate_knit=False, data_dir=tmp_path / "data"))

    with TestClient(app()) as c:
        sid = api.new_session(c)
        none_yet = c.get(f"/api/sessions/{sid}/tracker")
        assert none_yet.status_code == 409 and api.error_of(none_yet)["code"] == "no_candidates"
        assert api.upload(c, sid, "a", pictures.box_picture()).status_code == 200
        r = c.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 12})
        assert r.status_code == 200, r.text
        assert api.run_job(c, sid, "candidates")["status"] == "done"
        key = check_the_tracker(c, sid, api)
    with TestClient(app()) as c:  # the same data folder, after the app stopped
        t = c.get(f"/api/sessions/{sid}/tracker").json()
        assert (t["key"], t["row"]) == (key, 7)


def test_square_units_size_the_grid_without_the_gauge_ratio(client, pictures, api):
    sid = api.new_session(client)
    assert api.upload(client, sid, "a", pictures.box_picture(h=36, w=36)).status_code == 200
    r = client.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 20})
    assert r.status_code == 200
    fabric = client.get(f"/api/sessions/{sid}/inputs").json()
    r = client.put(f"/api/sessions/{sid}/settings", json={"square_units": True})
    assert r.status_code == 200 and r.json()["settings"]["square_units"] is True
    square = client.get(f"/api/sessions/{sid}/inputs").json()
    # a square picture: 20 x 20 square units, or 1 / 0.7 as many rows to stay square in fabric
    assert (square["rows"], square["cols"]) == (20, 20)
    assert fabric["rows"] == pytest.approx(20 / 0.7, abs=1)
    w, h = (square["finished_size"][k] for k in ("width_cm", "height_cm"))
    assert h == pytest.approx(0.7 * w, rel=0.03)  # the piece comes out shorter than the picture
    assert "square units" in r.json()["history"]["undo"][0]
