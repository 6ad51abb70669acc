"""The viewpoint the app measures from is the designer's: a setting, undoable, kept on disk."""

from __future__ import annotations

import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")

from fastapi.testclient import TestClient

from illuknit.app import create_app
from illuknit.app.server import AppConfig
from illuknit.design.options import RankOptions
from illuknit.pipeline.stages import measure_design


def _library_measures(session, pattern, *, angle, distance, knit_time):
    """What the library's stage says of ``pattern`` from that viewpoint."""
    q = session.prepared.quantised
    ranking = RankOptions(
        machine=session.settings.machine, knit_time=knit_time, angle=angle, distance=distance
    )
    return measure_design(pattern, "double", q["a"], q["b"], ranking=ranking).to_json()


def _design(c, api, pictures) -> str:
    sid = api.new_session(c)
    assert api.upload(c, sid, "a", pictures.box_picture()).status_code == 200
    assert api.upload(c, sid, "b", pictures.box_picture(top=2, left=2)).status_code == 200
    r = c.put(
        f"/api/sessions/{sid}/settings", json={"mode": "double", "width_units": 12, "candidates": 2}
    )
    assert r.status_code == 200, r.text
    assert api.run_job(c, sid, "candidates")["status"] == "done"
    return sid


def test_the_measures_follow_the_viewpoint_setting_undo_and_a_restart(tmp_path, api, pictures):
    app = create_app(AppConfig(isolate_knit=False, data_dir=tmp_path / "data"))
    with TestClient(app) as c:
        sid = _design(c, api, pictures)
        assert c.get(f"/api/sessions/{sid}").json()["settings"]["view_angle"] == 30.0
        assert api.run_job(c, sid, "measures")["status"] == "done"
        before = c.get(f"/api/sessions/{sid}/candidates").json()
        assert before["measured_at"] == {"angle": 30.0, "distance": 3.0}

        r = c.put(f"/api/sessions/{sid}/settings", json={"view_angle": 55, "view_distance": 8})
        assert r.status_code == 200, r.text
        state = r.json()
        assert state["history"]["undo"][0] == (
            "change of measured at angle 30.0 -> 55.0, measured from (m) 3.0 -> 8.0"
        )
        # the same candidates (no new search), no longer measured: their numbers were from 30°
        moved = c.get(f"/api/sessions/{sid}/candidates").json()
        assert moved["revision"] == before["revision"] and not moved["measured"]
        assert [x["rank"] for x in moved["candidates"]] == [x["rank"] for x in before["candidates"]]
        assert moved["measured_at"] == {"angle": 55.0, "distance": 8.0}

        assert api.run_job(c, sid, "measures")["status"] == "done"
        after = c.get(f"/api/sessions/{sid}/candidates").json()
        session = app.state.store.get(sid)
        old = {x["rank"]: x["measures"] for x in before["candidates"]}
        for shown, cand in zip(after["candidates"], session.candidates, strict=True):
            want = _library_measures(session, cand.pattern, angle=55, distance=8, knit_time=False)
            # how it reads is the library's from there; the knitting is the same from anywhere
            knit = ("knit_minutes", "machine_passes", "knit_note")
            assert {k: v for k, v in shown["measures"].items() if k not in knit} == {
                k: v for k, v in want.items() if k not in knit
            }
            assert [shown["measures"][k] for k in knit] == [old[shown["rank"]][k] for k in knit]
        new = {x["rank"]: x["measures"] for x in after["candidates"]}
        assert old != new, "55° from 8 m must read differently from 30° from 3 m"

        # a tile edit is measured from the same viewpoint
        pairs = c.get(f"/api/sessions/{sid}/pairs").json()
        pair = pairs["pairs"][0]
        other = next(o["id"] for o in pair["options"] if o["id"] != pair["tile"])
        r = c.put(f"/api/sessions/{sid}/pairs/{pair['a']}/{pair['b']}", json={"tile": other})
        assert r.status_code == 200, r.text
        edited = r.json()
        assert edited["measured_at"] == {"angle": 55.0, "distance": 8.0}
        from illuknit.app import design

        pattern = design.pattern_for(session.candidates[session.selected - 1], session.overrides)
        want = _library_measures(session, pattern, angle=55, distance=8, knit_time=False)
        assert edited["edited"] == want
        c.post(f"/api/sessions/{sid}/history/undo")  # the tile edit

        # Undo takes the viewpoint back, with the measures taken from it
        assert c.post(f"/api/sessions/{sid}/history/undo").status_code == 200
        back = c.get(f"/api/sessions/{sid}/candidates").json()
        assert back["measured_at"] == {"angle": 30.0, "distance": 3.0}
        assert {x["rank"]: x["measures"] for x in back["candidates"]} == old
        assert c.post(f"/api/sessions/{sid}/history/redo").status_code == 200
        again = c.get(f"/api/sessions/{sid}/candidates").json()
        assert {x["rank"]: x["measures"] for x in again["candidates"]} == new
    # a restarted app on the same data folder has the viewpoint and its measures
    with TestClient(create_app(AppConfig(isolate_knit=False, data_dir=tmp_path / "data"))) as c:
        state = c.get(f"/api/sessions/{sid}").json()
        assert (state["settings"]["view_angle"], state["settings"]["view_distance"]) == (55, 8)
        kept = c.get(f"/api/sessions/{sid}/candidates").json()
        assert {x["rank"]: x["measures"] for x in kept["candidates"]} == new


@pytest.mark.parametrize(
    "change", [{"view_angle": 0}, {"view_angle": 91}, {"view_distance": 0}, {"view_distance": 2000}]
)
def test_a_viewpoint_out_of_the_librarys_range_is_refused(client, api, change):
    sid = api.new_session(client)
    r = client.put(f"/api/sessions/{sid}/settings", json=change)
    assert r.status_code == 422
    assert api.error_of(r)["field"] == next(iter(change))


def test_settings_saved_before_the_viewpoint_existed_load_with_its_defaults():
    from illuknit.app.schemas import DesignSettings

    state = DesignSettings(width_units=24).__getstate__()
    del state["__dict__"]["view_angle"], state["__dict__"]["view_distance"]
    old = DesignSettings.__new__(DesignSettings)
    old.__setstate__(state)
    assert old == DesignSettings(width_units=24) and old.viewpoint == (30.0, 3.0)
