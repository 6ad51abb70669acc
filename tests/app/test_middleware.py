"""The local app answers only its own page at its own address (issue: a safe local app).

Served for real by uvicorn on a free loopback port, so that the Host check sees the socket's
address as a browser would reach it.
"""

from __future__ import annotations

import http.client
import json

import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
uvicorn = pytest.importorskip(
    "uvicorn", reason="the app extra is not installed: pip install 'illuknit[app]'"
)

from illuknit.app import create_app  # noqa: E402
from illuknit.app.server import AppConfig  # noqa: E402


@pytest.fixture(scope="module")
def served(serve_app):
    app = create_app(AppConfig(isolate_knit=False, allowed_hosts=("studio.local",)))
    with serve_app(app) as port:
        yield app, port


def call(port: int, method: str, path: str, headers: dict[str, str] | None = None, body=None):
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    conn.request(method, path, body=body, headers=headers or {})
    r = conn.getresponse()
    data = r.read()
    conn.close()
    return r.status, (json.loads(data) if data.startswith(b"{") else data)


# -- Host: DNS rebinding ----------------------------------------------------------------------


@pytest.mark.parametrize("name", ["127.0.0.1", "localhost", "studio.local"])
def test_own_address_is_answered(served, name):
    _, port = served
    status, info = call(port, "GET", "/api/info", {"Host": f"{name}:{port}"})
    assert status == 200 and "capabilities" in info


@pytest.mark.parametrize(
    "host",
    [
        "attacker.example:{port}",
        "attacker.example",
        "127.0.0.1:1",
        "localhost",
        "127.0.0.1.nip.io:{port}",
    ],
)
def test_foreign_host_is_refused_on_every_route(served, host):
    app, port = served
    before = len(app.state.store)
    for method, path in (("GET", "/api/info"), ("GET", "/"), ("POST", "/api/sessions")):
        status, body = call(port, method, path, {"Host": host.format(port=port)})
        assert status == 400, (method, path)
        err = body["error"]
        assert err["code"] == "bad_host"
        assert f"127.0.0.1:{port}" in err["message"] and "\n" not in err["message"]
    assert len(app.state.store) == before


# -- Origin / Sec-Fetch-Site: cross-site requests ---------------------------------------------


def own(port: int) -> dict[str, str]:
    return {"Host": f"127.0.0.1:{port}"}


def test_same_origin_page_may_change_state(served):
    _, port = served
    headers = {**own(port), "Origin": f"http://127.0.0.1:{port}", "Sec-Fetch-Site": "same-origin"}
    status, state = call(port, "POST", "/api/sessions", headers)
    assert status == 201
    sid = state["id"]
    status, state = call(
        port,
        "PUT",
        f"/api/sessions/{sid}/settings",
        {**headers, "Content-Type": "application/json"},
        json.dumps({"width_units": 30}),
    )
    assert status == 200 and state["settings"]["width_units"] == 30
    assert call(port, "DELETE", f"/api/sessions/{sid}", headers)[0] == 200


def test_scripts_without_browser_headers_pass(served):
    _, port = served
    assert call(port, "POST", "/api/sessions", own(port))[0] == 201


@pytest.mark.parametrize(
    "extra",
    [
        {"Origin": "https://attacker.example"},
        {"Origin": "null"},
        {"Origin": "http://127.0.0.1:1"},
        {"Sec-Fetch-Site": "cross-site"},
        {"Sec-Fetch-Site": "same-site"},
        {"Sec-Fetch-Site": "cross-site", "Origin": "https://attacker.example"},
    ],
)
def test_cross_site_changes_are_refused(served, extra):
    app, port = served
    status, state = call(port, "POST", "/api/sessions", own(port))
    sid = state["id"]
    before = len(app.state.store)
    headers = {**own(port), **extra}
    for method, path, body in (
        ("POST", "/api/sessions", None),
        ("PUT", f"/api/sessions/{sid}/settings", json.dumps({"width_units": 40})),
        ("POST", f"/api/sessions/{sid}/jobs", json.dumps({"kind": "candidates"})),
        ("DELETE", f"/api/sessions/{sid}", None),
    ):
        h = {**headers, "Content-Type": "application/json"} if body else headers
        status, answer = call(port, method, path, h, body)
        assert status == 403, (method, path, answer)
        err = answer["error"]
        assert err["code"] == "cross_origin"
        assert err["message"].startswith("changes are accepted only from the app's own page")
    assert len(app.state.store) == before
    # nothing changed: the session is still there with its settings
    status, state = call(port, "GET", f"/api/sessions/{sid}", own(port))
    assert status == 200 and state["settings"]["width_units"] == 60


def test_cross_site_reads_are_not_refused_but_carry_no_cors_grant(served):
    """A GET changes nothing; without CORS headers the foreign page cannot read the answer."""
    _, port = served
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    conn.request("GET", "/api/info", headers={**own(port), "Origin": "https://attacker.example"})
    r = conn.getresponse()
    r.read()
    assert r.status == 200 and r.getheader("access-control-allow-origin") is None
    conn.close()
