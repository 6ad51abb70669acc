"""The first hour in the app (issue 33, item 9): saved designs can be reopened from any tab, a
colour count above the yarns adds yarns as the command line chooses them, and a new design is
sized by the library's sizing policy (``illuknit.pictures.sizing``), not a fixed 60 units.
(Uploads that never race are the browser's: ``test_browser.py``.)"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")

from illuknit.core.colors import lab_from_rgb
from illuknit.core.pattern import parse_yarns
from illuknit.pictures.sizing import DEFAULT_MAX_WIDTH, grid_width


def _settings(client, sid: str, **change) -> dict:
    r = client.put(f"/api/sessions/{sid}/settings", json=change)
    assert r.status_code == 200, r.text
    return r.json()


@pytest.mark.parametrize(("width_px", "units"), [(36, 36), (72, 72), (300, DEFAULT_MAX_WIDTH)])
def test_a_new_design_is_sized_by_the_policy(client, api, pictures, width_px, units):
    sid = api.new_session(client)
    assert client.get(f"/api/sessions/{sid}").json()["settings"]["size_mode"] == "picture"
    data = pictures.box_picture(h=width_px * 2 // 3, w=width_px)
    state = api.upload(client, sid, "a", data).json()
    assert state["width_units"] == units == grid_width(width_px)
    _settings(client, sid, mode="single")
    assert client.get(f"/api/sessions/{sid}/inputs").json()["cols"] == units


def test_typing_a_width_sizes_by_it_from_then_on(client, api, pictures):
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.box_picture())
    _settings(client, sid, mode="single")
    state = _settings(client, sid, width_units=24)
    assert state["settings"]["size_mode"] == "units" and state["width_units"] == 24
    assert client.get(f"/api/sessions/{sid}/inputs").json()["cols"] == 24
    # the width the designer saw (the picture's 36 units), not the unused stored 60
    assert (
        state["history"]["undo"][0] == "change of size by picture -> units, width (units) 36 -> 24"
    )
    state = _settings(client, sid, size_mode="picture")
    assert state["width_units"] == 36  # the picture's width again


def test_more_colours_than_yarns_adds_yarns_from_the_pictures(client, api, pictures):
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.three_tone())
    api.upload(client, sid, "b", pictures.three_tone())
    state = _settings(client, sid, mode="double", width_units=18, n_colors=3)
    yarns = state["settings"]["yarns"]
    assert len(yarns) == 3 and yarns[:2] == ["#1b1b1b", "#f4f0e8"]  # the designer's kept
    added = lab_from_rgb(np.array(parse_yarns([yarns[2]])[0].rgb, float))
    middle = lab_from_rgb(np.array([150, 110, 60], float))
    assert np.linalg.norm(added - middle) < 10  # the pictures' third colour, not a guess
    r = client.get(f"/api/sessions/{sid}/inputs")
    assert r.status_code == 200, r.text  # no "add a yarn" dead end
    assert len(r.json()["yarns"]) == 3
    state = _settings(client, sid, n_colors=4)  # the pictures have no fourth: a spare yarn
    assert len(state["settings"]["yarns"]) == 4
    assert len(set(state["settings"]["yarns"])) == 4


def test_more_colours_without_pictures_adds_spare_yarns(client, api):
    sid = api.new_session(client)
    state = _settings(client, sid, mode="double", n_colors=4)
    assert len(state["settings"]["yarns"]) == 4
    assert state["history"]["undo"][0].endswith("yarns (2 -> 4)")


def test_a_single_view_keeps_two_yarns_for_three_colours(client, api):
    sid = api.new_session(client)
    state = _settings(client, sid, mode="single", n_colors=3)
    assert len(state["settings"]["yarns"]) == 2  # the third colour is a mix of two yarns


def test_saved_designs_are_listed_to_reopen(tmp_path, api, pictures):
    from fastapi.testclient import TestClient

    from illuknit.app import create_app
    from illuknit.app.server import AppConfig

    def listed(c) -> list[dict]:
        r = c.get("/api/sessions")
        assert r.status_code == 200
        return list(r.json()["sessions"])

    app = create_app(AppConfig(data_dir=tmp_path / "data", isolate_knit=False))
    with TestClient(app) as c:
        assert listed(c) == []
        first = api.new_session(c)
        api.upload(c, first, "a", pictures.box_picture(), name="heart.png")
        api.new_session(c)  # an empty tab: nothing to reopen
        second = api.new_session(c)
        api.upload(c, second, "a", pictures.box_picture(), name="star.png")
        api.upload(c, second, "b", pictures.box_picture(top=2), name="moon.png")
        got = listed(c)
        assert [d["id"] for d in got] == [second, first]  # most recently used first
        assert got[0]["pictures"] == {"a": "star.png", "b": "moon.png"}
        assert got[0]["mode"] == "double" and got[0]["last_seen"] > 0
    # after a restart too (the list is read from the data folder)
    app = create_app(AppConfig(data_dir=tmp_path / "data", isolate_knit=False))
    with TestClient(app) as c:
        assert [d["id"] for d in listed(c)] == [second, first]
        assert c.get(f"/api/sessions/{first}").json()["images"]["a"]["filename"] == "heart.png"


def test_saved_designs_without_a_data_folder_come_from_memory(client, api, pictures):
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.box_picture(), name="kept.png")
    listed = client.get("/api/sessions").json()["sessions"]
    assert listed[0]["id"] == sid and listed[0]["pictures"] == {"a": "kept.png"}


def test_settings_given_a_width_are_sized_by_it():
    from illuknit.app.schemas import DesignSettings

    assert DesignSettings().size_mode == "picture"
    assert DesignSettings(width_units=48).size_mode == "units"
    assert DesignSettings(width_cm=10.0).size_mode == "physical"
    assert DesignSettings(width_units=48, size_mode="picture").size_mode == "picture"
