"""Downloads through the JSON API: what needs candidates or a program first
(``routers/downloads.py``).
"""

from __future__ import annotations

import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")


def test_dat_before_knitout_and_unknown_downloads(client, double, api):
    r = client.get(f"/api/sessions/{double}/download/pattern.dat")
    assert r.status_code == 409 and api.error_of(r)["field"] == "knit"
    assert "make the knitout first" in api.error_of(r)["message"]
    r = client.get(f"/api/sessions/{double}/download/secrets.txt")
    assert r.status_code == 404 and api.error_of(r)["field"] == "downloads"


def test_downloads_and_render_need_candidates(client, api):
    sid = api.new_session(client)
    for path in ("/download/pattern.json", "/render?view=A", "/pairs"):
        r = client.get(f"/api/sessions/{sid}{path}")
        assert r.status_code == 409, path
        assert api.error_of(r)["code"] == "no_candidates"
