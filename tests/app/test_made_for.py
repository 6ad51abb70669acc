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
        # sized and described for the piece knitted by hand: a square picture knits square
        square = pictures.box_picture(24, 24)
        api.upload(c, sid, "a", square)
        api.upload(c, sid, "b", square)
        size = c.get(f"/api/sessions/{sid}/inputs").json()["finished_size"]
        assert size["by_hand"] and size["estimate"]
        assert abs(size["height_cm"] - size["width_cm"]) <= size["height_cm"] / 12  # a unit row
        assert api.run_job(c, sid, "candidates")["status"] == "done"
        pdf = c.get(f"/api/sessions/{sid}/download/pattern.pdf")
        assert pdf.status_code == 200
        words = _pdf_words(pdf.content, tmp_path)
        if words is not None:
            assert "The design is drawn for hand-knitted illusion fabric" in words
            assert f"Finished size by hand: about {size['width_cm']:g} x" in words


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


def test_made_for_hands_sizes_the_grid_by_the_hand_gauge():
    """The app sizes a design made for hands as the command line does (the hand pattern's
    gauge), and a widths answer found for one does not hold for the other."""
    from illuknit.app.inputs import sizing_aspect
    from illuknit.app.reading import widths_key
    from illuknit.core.gauge import hand_gauge
    from illuknit.core.machine import get_machine

    machine = DesignSettings()
    hands = DesignSettings(made_for="hands")
    gauge = get_machine(machine.machine).fabric_gauge
    assert sizing_aspect(machine) == gauge.unit_aspect
    assert sizing_aspect(hands) == hand_gauge(gauge).unit_aspect < gauge.unit_aspect
    assert sizing_aspect(DesignSettings(made_for="hands", square_units=True)) == 1.0
    assert widths_key({}, machine) != widths_key({}, hands)


def _pdf_words(data: bytes, tmp_path) -> str | None:
    """The PDF's text, whitespace collapsed (None without pdftotext)."""
    import shutil
    import subprocess

    tool = shutil.which("pdftotext")
    if tool is None:
        return None
    path = tmp_path / "got.pdf"
    path.write_bytes(data)
    out = subprocess.run([tool, str(path), "-"], capture_output=True, text=True, check=True)
    return " ".join(out.stdout.split())
