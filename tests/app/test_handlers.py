"""Error answers are written for a designer: the control's title and its bounds, never internals."""

from __future__ import annotations

import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")

from fastapi.testclient import TestClient

from illuknit.app import create_app
from illuknit.app.server import AppConfig


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(AppConfig(isolate_knit=False))) as c:
        yield c


@pytest.fixture()
def sid(client):
    return client.post("/api/sessions").json()["id"]


@pytest.mark.parametrize(
    ("change", "field", "message"),
    [
        ({"width_units": 5000}, "width_units", "Width can be at most 1000 units"),
        ({"width_units": 1}, "width_units", "Width must be at least 2 units"),
        ({"width_units": "wide"}, "width_units", "Width must be a whole number, not 'wide'"),
        ({"width_units": 12.5}, "width_units", "Width must be a whole number, not 12.5"),
        ({"gauge": 0}, "gauge", "Gauge must be more than 0 stitches per inch"),
        ({"width_cm": "x"}, "width_cm", "Width in cm must be a number, not 'x'"),
        ({"mode": "triple"}, "mode", "Mode must be one of: single, double, headon; not 'triple'"),
        ({"yarns": ["#000000"]}, "yarns", "choose at least 2 yarns"),
        ({"yarns": ["#000000"] * 7}, "yarns", "choose at most 6 yarns"),
        ({"smooth": "maybe"}, "smooth", "Smooth resizing must be on or off (true or false)"),
        ({"colour": 3}, "colour", "'colour' is not a setting; the settings are mode, size_mode"),
    ],
)
def test_settings_errors_read_as_sentences(client, sid, change, field, message):
    r = client.put(f"/api/sessions/{sid}/settings", json=change)
    assert r.status_code == 422
    err = r.json()["error"]
    assert err["field"] == field
    assert err["message"].startswith(message), err["message"]
    assert "Input should" not in err["message"]


def test_broken_json_is_not_a_decode_error(client, sid):
    r = client.put(
        f"/api/sessions/{sid}/settings",
        content=b'{"width_units": ',
        headers={"Content-Type": "application/json"},
    )
    assert r.status_code == 422
    err = r.json()["error"]
    assert err["message"].startswith("the request is not valid JSON"), err
    assert "decode" not in err["message"].lower() and not err["message"][0].isdigit()


def test_body_that_is_not_an_object(client, sid):
    r = client.put(f"/api/sessions/{sid}/settings", json=[1, 2])
    assert r.status_code == 422
    assert r.json()["error"]["message"] == "the request body must be a JSON object of settings"


def test_two_problems_say_how_many_more(client, sid):
    r = client.put(f"/api/sessions/{sid}/settings", json={"width_units": 0, "gauge": 0})
    assert r.json()["error"]["message"].endswith("(and 1 more problem)")


def test_query_parameters_use_their_titles(client, sid):
    r = client.get(f"/api/sessions/{sid}/render", params={"angle": 120})
    assert r.status_code == 422
    err = r.json()["error"]
    assert err["field"] == "angle" and err["message"] == "Viewing angle can be at most 90 degrees"
