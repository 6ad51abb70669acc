"""The app names the machine truthfully and says when a piece fits only the generic bed."""

from __future__ import annotations

import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")


def test_selector_labels_say_what_each_machine_is(client):
    labels = {m["name"]: m["label"] for m in client.get("/api/info").json()["machines"]}
    assert labels["generic540"] == "generic 540-needle V-bed (SWG091N2 rules)"
    assert labels["swg091n2"] == "SWG091N2" and labels["kniterate"] == "Kniterate"


def test_a_piece_wider_than_the_real_swg091n2_gets_a_note(client, pictures, api):
    sid = api.new_session(client)
    assert api.upload(client, sid, "a", pictures.box_picture()).status_code == 200
    r = client.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 130})
    assert r.status_code == 200, r.text
    notes = client.get(f"/api/sessions/{sid}/inputs").json()["notes"]
    assert [n for n in notes if "not a real SWG091N2" in n and "130 units" in n], notes
    client.put(f"/api/sessions/{sid}/settings", json={"width_units": 60})
    notes = client.get(f"/api/sessions/{sid}/inputs").json()["notes"]
    assert not [n for n in notes if "SWG091N2" in n], notes
