"""The app's "made for" control (issue #37): generated from the declared option, passed to the
search as ``RankOptions(made_for=...)``, and the cards carry the hand figures when made for hands."""

from __future__ import annotations

import pytest

from illuknit.app.schemas import DesignSettings, SettingsPatch, choice_control
from illuknit.core.declared import declared_options
from illuknit.design.options import MadeFor, RankOptions


def test_the_control_is_the_declared_option():
    declared = declared_options(RankOptions)["made_for"]
    control = choice_control(DesignSettings, "made_for")
    assert control["choices"] == list(declared.choices) == [m.value for m in MadeFor]
    assert control["default"] == declared.cli_default == DesignSettings().made_for == "machine"
    assert control["title"] == declared.title
    assert SettingsPatch(made_for="hands").made_for == "hands"
    with pytest.raises(ValueError):
        DesignSettings(made_for="robots")


@pytest.mark.parametrize("made_for", ["machine", "hands"])
def test_made_for_reaches_the_ranking(search_keywords, made_for):
    assert search_keywords(made_for=made_for)["ranking"].made_for is MadeFor(made_for)


def test_made_for_hands_in_the_app(tmp_path, api, pictures):
    pytest.importorskip("fastapi", reason="the app extra is not installed")
    from fastapi.testclient import TestClient

    from illuknit.app import create_app
    from illuknit.app.server import AppConfig

    with TestClient(create_app(AppConfig(isolate_knit=False, data_dir=tmp_path))) as c:
        assert c.get("/api/info").json()["controls"]["made_for"]["choices"] == ["machine", "hands"]
        sid = api.new_session(c)
        assert api.upload(c, sid, "a", pictures.box_picture()).status_code == 200
        assert api.upload(c, sid, "b", pictures.box_picture(top=2, left=2)).status_code == 200
        settings = {"mode": "double", "width_units": 12, "candidates": 2, "made_for": "hands"}
        r = c.put(f"/api/sessions/{sid}/settings", json=settings)
        assert r.status_code == 200, r.text
        assert "made for machine -> hands" in r.json()["history"]["undo"][0]
        assert api.run_job(c, sid, "candidates")["status"] == "done"
        got = c.get(f"/api/sessions/{sid}/candidates").json()
        assert got["made_for"] == "hands"
        for cand in got["candidates"]:
            hand = cand["details"]["hand"]
            assert 0 <= hand["knittable_rows"] <= hand["rows"] and hand["longest_float"] >= 0
            # a shared-stripe design (every row one yarn) says so on its card
            assert hand["shared_stripes"] == ("shared stripes" in hand["text"])
        # measured, the order still puts the rows a hand knitter can work first
        assert api.run_job(c, sid, "measures")["status"] == "done"
        got = c.get(f"/api/sessions/{sid}/candidates?order=perception").json()
        shares = [x["measures"]["hand"]["knittable_share"] for x in got["candidates"]]
        assert shares == sorted(shares, reverse=True)


def test_the_search_bar_counts_the_hand_models_seconds(tmp_path, api, pictures, monkeypatch):
    """Made for hands, the search's bound and words include the constraint model's solve, which
    runs in the search's process (Cancel kills it with the search)."""
    pytest.importorskip("fastapi", reason="the app extra is not installed")
    from fastapi.testclient import TestClient

    from illuknit.app import create_app
    from illuknit.app.jobs import Job
    from illuknit.app.server import AppConfig
    from illuknit.design.tiles.perception import POOL_SECONDS

    said: list[str] = []

    def in_process(self, fn, *args, tick=None, **_):  # the words at 3 s, then the search here
        tick(3.0)
        said.append(self.message)
        return fn(*args)

    monkeypatch.setattr(Job, "run_isolated", in_process)
    monkeypatch.setenv("ILLUKNIT_HAND_MODEL_SECONDS", "2")
    with TestClient(create_app(AppConfig(isolate_search=True, data_dir=tmp_path))) as c:
        sid = api.new_session(c)
        api.upload(c, sid, "a", pictures.box_picture())
        api.upload(c, sid, "b", pictures.box_picture(top=2, left=2))
        for made_for in ("hands", "machine"):
            settings = {"mode": "double", "width_units": 12, "candidates": 1, "made_for": made_for}
            assert c.put(f"/api/sessions/{sid}/settings", json=settings).status_code == 200
            assert api.run_job(c, sid, "candidates")["status"] == "done"
    hands, machine = said
    assert "solving the constraint model made for hands (up to 2 s)" in hands
    assert f"done in at most {POOL_SECONDS + 10 + 2:.0f} s" in hands
    assert "constraint model" not in machine
    assert f"done in at most {POOL_SECONDS + 10:.0f} s" in machine
