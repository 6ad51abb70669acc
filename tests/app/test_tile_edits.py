"""The tile table: overlap pairs grouped by the fill A shows, the rare ones folded (API)."""

from __future__ import annotations

import io

import numpy as np
import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")

from fastapi.testclient import TestClient
from PIL import Image

from illuknit.app import create_app
from illuknit.app.server import AppConfig


def speckled(*, split: str) -> bytes:
    """An 18 x 12 picture, half dark (top half, or left half) and half light, with a 2 x 2 speck
    of mid grey; on the 17 x 18 grid that keeps its proportions (units 0.7 as tall as wide) the
    speck is 6 of 306 units, an overlap under 2 % of the units wherever it lies."""
    rgb = np.full((12, 18, 3), 240, np.uint8)
    if split == "left":
        rgb[:, :9] = 20
    else:
        rgb[:6] = 20
    rgb[8:10, 12:14] = 128
    buf = io.BytesIO()
    Image.fromarray(rgb).save(buf, format="PNG")
    return buf.getvalue()


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(AppConfig(isolate_knit=False))) as c:
        yield c


@pytest.fixture(scope="module")
def designed(client, api):
    sid = client.post("/api/sessions").json()["id"]
    for slot, split in (("a", "top"), ("b", "left")):
        files = {"file": (f"{slot}.png", speckled(split=split), "image/png")}
        assert client.put(f"/api/sessions/{sid}/images/{slot}", files=files).status_code == 200
    settings = {
        "mode": "double",
        "width_units": 18,
        "n_colors": 3,
        "smooth": False,
        "yarns": ["#1b1b1b", "#8a8a8a", "#f4f0e8"],
    }
    assert client.put(f"/api/sessions/{sid}/settings", json=settings).status_code == 200
    job = api.run_job(client, sid, "candidates")
    assert job["status"] == "done", job
    return sid


def test_pairs_are_grouped_by_fill_and_the_rare_ones_folded(client, designed):
    p = client.get(f"/api/sessions/{designed}/pairs").json()
    keys = [f"{x['a']}/{x['b']}" for x in p["pairs"]]
    grouped = [k for g in p["groups"] for k in g["pairs"]]
    # every pair once, in the order of the groups, then the rare line
    assert keys == grouped + p["rare"]["pairs"]
    assert len(set(keys)) == len(keys)
    share = {f"{x['a']}/{x['b']}": x["share"] for x in p["pairs"]}
    assert p["rare"]["pairs"] == ["1/1"]  # the speck over the speck: 6 of 306 units
    assert p["rare"]["below"] == 0.02 and p["rare"]["share"] == pytest.approx(6 / 306, abs=1e-4)
    for g in p["groups"]:
        assert g["fill"] and g["share"] == pytest.approx(sum(share[k] for k in g["pairs"]), 1e-3)
        assert all(share[k] >= 0.02 for k in g["pairs"])
    assert [g["share"] for g in p["groups"]] == sorted(
        (g["share"] for g in p["groups"]), reverse=True
    )
    # one group per fill shown from A: pairs of one colour of A share it
    by_a = {}
    for g in p["groups"]:
        for k in g["pairs"]:
            by_a.setdefault(k.split("/")[0], set()).add(g["fill"])
    assert all(len(fills) == 1 for fills in by_a.values())


def test_an_edit_keeps_the_row_in_its_group(client, designed):
    before = client.get(f"/api/sessions/{designed}/pairs").json()
    row = next(
        x for x in before["pairs"] if f"{x['a']}/{x['b']}" == before["groups"][0]["pairs"][0]
    )
    other = next(o["id"] for o in row["options"] if not o["exact"])
    r = client.put(f"/api/sessions/{designed}/pairs/{row['a']}/{row['b']}", json={"tile": other})
    assert r.status_code == 200, r.text
    after = r.json()
    assert after["groups"] == before["groups"] and after["rare"] == before["rare"]
    edited = next(x for x in after["pairs"] if (x["a"], x["b"]) == (row["a"], row["b"]))
    assert edited["overridden"] and edited["tile"] == other
    # measured at once: the edited design's readability differs from the candidate's own
    assert before["edited"] is None
    m = after["edited"]
    assert m["views"] == ["A", "B"] and all(-1 <= x <= 1 for x in m["readability"])
    if before["measures"] is not None:
        assert m["readability"] != before["measures"]["readability"]
    r = client.put(f"/api/sessions/{designed}/pairs/{row['a']}/{row['b']}", json={"tile": None})
    assert r.status_code == 200
    assert r.json()["edited"] is None


def test_a_headon_design_groups_by_the_headon_fill(client, api):
    sid = client.post("/api/sessions").json()["id"]
    files = {"file": ("a.png", speckled(split="top"), "image/png")}
    assert client.put(f"/api/sessions/{sid}/images/a", files=files).status_code == 200
    settings = {"mode": "headon", "width_units": 18, "smooth": False}
    assert client.put(f"/api/sessions/{sid}/settings", json=settings).status_code == 200
    job = api.run_job(client, sid, "candidates")
    assert job["status"] == "done", job
    p = client.get(f"/api/sessions/{sid}/pairs").json()
    assert p["views"][0] == "headon"
    keys = [f"{x['a']}/{x['b']}" for x in p["pairs"]]
    assert keys == [k for g in p["groups"] for k in g["pairs"]] + p["rare"]["pairs"]
    assert keys and all(g["fill"] for g in p["groups"])
