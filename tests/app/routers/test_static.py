"""The design app's page, static files, info and OpenAPI schema (``routers/static.py``)."""

from __future__ import annotations

import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")


def test_page_and_static_files_are_served(client):
    r = client.get("/")
    assert r.status_code == 200 and "illuknit" in r.text
    import re

    from illuknit.app.routers.static import STATIC_DIR

    # every script and style sheet the page names is served, and the page names them all
    named = re.findall(r'(?:src|href)="/static/([^"]+)"', r.text)
    assert "app.js" in named and "main.js" in named and "app.css" in named
    assert sorted(named) == sorted(
        p.name for p in STATIC_DIR.iterdir() if p.suffix in (".js", ".css")
    )
    for name in named:
        assert client.get(f"/static/{name}").status_code == 200, name
    # everything the page loads comes from this server: no CDN, works offline
    for src in ("index.html", *named):
        body = (STATIC_DIR / src).read_text(encoding="utf-8")
        assert "http://" not in body and "https://" not in body, src


def test_info_lists_capabilities_limits_and_presets(client):
    info = client.get("/api/info").json()
    assert info["capabilities"]["single"] is True
    assert info["capabilities"]["dat"] is True
    assert info["limits"]["max_upload_bytes"] == 200_000
    assert all(len(v) >= 2 for v in info["presets"].values())


def test_openapi_documents_every_endpoint(client):
    spec = client.get("/openapi.json").json()
    paths = spec["paths"]
    for p in (
        "/api/info",
        "/api/sessions",
        "/api/sessions/{sid}",
        "/api/sessions/{sid}/images/{slot}",
        "/api/sessions/{sid}/settings",
        "/api/sessions/{sid}/inputs",
        "/api/sessions/{sid}/inputs/{slot}.png",
        "/api/sessions/{sid}/jobs",
        "/api/sessions/{sid}/jobs/{job_id}",
        "/api/sessions/{sid}/candidates",
        "/api/sessions/{sid}/selection",
        "/api/sessions/{sid}/pairs",
        "/api/sessions/{sid}/pairs/{a}/{b}",
        "/api/sessions/{sid}/tiles/{tile_id}.png",
        "/api/sessions/{sid}/render",
        "/api/sessions/{sid}/download/{name}",
        "/api/sessions/{sid}/knit",
        "/api/sessions/{sid}/suggestions",
        "/api/sessions/{sid}/suggestions/{edit_id}/{slot}/{which}.png",
        "/api/sessions/{sid}/suggestions/{edit_id}/accept",
        "/api/sessions/{sid}/suggestions/{edit_id}/refuse",
        "/api/sessions/{sid}/diagnostic.png",
    ):
        assert p in paths, p
    docs = client.get("/docs")
    assert docs.status_code == 200 and "/api/sessions/{sid}/render" in docs.text
    assert "cdn" not in docs.text.lower()


def test_unknown_route_answers_json(client, api):
    r = client.get("/api/nothing-here")
    assert r.status_code == 404
    api.error_of(r)
