"""Designs through the JSON API: single-view flows, candidates, selection, render, tiles, head-on,
knit (``routers/designs.py``).
"""

from __future__ import annotations

import io
import zipfile

import numpy as np
import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")

from PIL import Image


def test_single_view_three_colors_with_two_yarns_knits_a_mix(client, api, pictures):
    """What `illuknit single` accepts: 3 colours, 2 yarns, the middle colour a mix of both."""
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.three_tone())
    yarns = ["#1b1b1b", "#f4f0e8"]
    client.put(
        f"/api/sessions/{sid}/settings",
        json={"mode": "single", "n_colors": 3, "yarns": yarns, "width_units": 18},
    )
    r = client.get(f"/api/sessions/{sid}/inputs")
    assert r.status_code == 200, r.text
    legend = r.json()["legend"]["a"]
    assert len(legend) == 3
    # the legend shows what is knitted: the two yarns, and a mix named by both in their blend
    assert [e["yarn"] for e in legend] == ["black", "mix of black and linen", "linen"]
    mix = legend[1]
    assert mix["yarn_color"] == "#888682"  # the blend of the two yarns, not the picture's brown
    assert {e["yarn_color"] for e in legend} - {mix["yarn_color"]} == set(yarns)
    assert any("mix" in n for n in r.json()["notes"])
    assert api.run_job(client, sid, "candidates")["status"] == "done"
    doc = client.get(f"/api/sessions/{sid}/download/pattern.json").json()
    assert [y["rgb"] for y in doc["yarns"]] == yarns  # only the two yarns are knitted


@pytest.mark.parametrize(
    ("n_colors", "yarns", "field"),
    [
        (2, ["#000000", "#777777", "#ffffff"], "yarns"),
        (3, ["#000000", "#555555", "#aaaaaa", "#ffffff"], "yarns"),
    ],
)
def test_single_view_refuses_extra_yarns_next_to_the_yarns(
    client, n_colors, yarns, field, api, pictures
):
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.three_tone())
    client.put(
        f"/api/sessions/{sid}/settings",
        json={"mode": "single", "n_colors": n_colors, "yarns": yarns},
    )
    r = client.get(f"/api/sessions/{sid}/inputs")
    assert r.status_code == 422 and api.error_of(r)["field"] == field
    assert "knitted with 2 yarns" in api.error_of(r)["message"]


def test_single_view_four_colors_is_refused(client, api, pictures):
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.box_picture())
    client.put(
        f"/api/sessions/{sid}/settings",
        json={
            "mode": "single",
            "n_colors": 4,
            "yarns": ["#000000", "#555555", "#aaaaaa", "#ffffff"],
        },
    )
    r = client.get(f"/api/sessions/{sid}/inputs")
    assert r.status_code == 422 and api.error_of(r)["field"] == "n_colors"


def test_single_view_flow_to_checked_knitout(client, api, pictures):
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.box_picture())
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 18})
    assert api.run_job(client, sid, "candidates")["status"] == "done"
    cands = client.get(f"/api/sessions/{sid}/candidates").json()
    assert [c["rank"] for c in cands["candidates"]] == [1, 2] and cands["selected"] == 1
    assert cands["candidates"][0]["details"]["mismatch_A"] == 0.0
    pairs = client.get(f"/api/sessions/{sid}/pairs").json()
    assert pairs["editable"] is False and pairs["pairs"] == []
    r = client.put(f"/api/sessions/{sid}/pairs/0/0", json={"tile": "0"})
    assert r.status_code == 409 and api.error_of(r)["field"] == "tiles"
    # downloads before the knitout exists
    r = client.get(f"/api/sessions/{sid}/download/knitout.k")
    assert r.status_code == 409 and api.error_of(r)["field"] == "knit"
    for name, kind in (
        ("pattern.json", "application/json"),
        ("pattern.pdf", "application/pdf"),
        ("chart.svg", "image/svg+xml"),
        ("chart.png", "image/png"),
        ("instructions.txt", "text/plain"),
        ("previews.zip", "application/zip"),
    ):
        r = client.get(f"/api/sessions/{sid}/download/{name}")
        assert r.status_code == 200, (name, r.text[:200])
        assert r.headers["content-type"].startswith(kind)
        assert "attachment" in r.headers["content-disposition"]
    doc = client.get(f"/api/sessions/{sid}/download/pattern.json").json()
    # a 2 : 3 picture, units 0.7 as tall as wide
    assert doc["format"] == "illuknit-pattern" and (doc["rows"], doc["cols"]) == (17, 18)
    names = zipfile.ZipFile(
        io.BytesIO(client.get(f"/api/sessions/{sid}/download/previews.zip").content)
    ).namelist()
    assert any(n.endswith("contact.png") for n in names)
    assert "Row 1" in client.get(f"/api/sessions/{sid}/download/instructions.txt").text
    info = client.get("/api/info").json()["capabilities"]
    if not info["knit"]:
        pytest.skip("the knitout compiler is not in this install")
    assert client.get(f"/api/sessions/{sid}/knit").json() == {"ready": False}
    job = api.run_job(client, sid, "knit")
    assert job["status"] == "done", job
    k = client.get(f"/api/sessions/{sid}/knit").json()
    assert k["ready"] and k["stats"]["passes"] > 0
    text = client.get(f"/api/sessions/{sid}/download/knitout.k").text
    assert text.startswith(";!knitout-2")
    if info["check"]:
        rep = client.get(f"/api/sessions/{sid}/download/check.json").json()
        assert rep["ok"] is True, rep
        assert "OK" in client.get(f"/api/sessions/{sid}/download/check.txt").text
    # picking the other candidate makes the knitout stale
    client.put(f"/api/sessions/{sid}/selection", json={"candidate": 2})
    assert client.get(f"/api/sessions/{sid}/download/knitout.k").status_code == 409


def test_double_view_candidates_pick_and_render(client, double, api):
    info = client.get("/api/info").json()["capabilities"]
    if not info["double"]:
        pytest.skip("the tile bank is not in this install")
    c = client.get(f"/api/sessions/{double}/candidates").json()
    ranks = [x["rank"] for x in c["candidates"]]
    assert ranks == list(range(1, len(ranks) + 1)) and ranks
    assert all(x["editable"] for x in c["candidates"])
    # the search's rank is `illuknit double`'s default order: how the views read
    assert api.run_job(client, double, "measures")["status"] == "done"
    by_reading = client.get(f"/api/sessions/{double}/candidates", params={"order": "perception"})
    assert [x["rank"] for x in by_reading.json()["candidates"]] == ranks
    last = ranks[-1]
    assert (
        client.put(f"/api/sessions/{double}/selection", json={"candidate": last}).json()["selected"]
        == last
    )
    r = client.put(f"/api/sessions/{double}/selection", json={"candidate": 99})
    assert r.status_code == 422 and api.error_of(r)["field"] == "candidate"
    shapes = set()
    for view in ("A", "B", "headon"):
        for angle in (10, 45, 90):
            r = client.get(f"/api/sessions/{double}/render", params={"view": view, "angle": angle})
            assert r.status_code == 200 and r.headers["content-type"] == "image/png"
            shapes.add(np.asarray(Image.open(io.BytesIO(r.content))).shape[1:])
    assert len(shapes) == 1  # every view has the same width and 3 channels
    r = client.get(f"/api/sessions/{double}/render", params={"view": "A", "candidate": 1})
    assert r.status_code == 200


@pytest.mark.parametrize(
    ("params", "field"),
    [
        ({"angle": 0}, "angle"),
        ({"angle": 91}, "angle"),
        ({"angle": "steep"}, "angle"),
        ({"view": "C"}, "view"),
        ({"candidate": 0}, "candidate"),
        ({"distance": 0}, "distance"),
        ({"distance": -3}, "distance"),
    ],
)
def test_render_bad_parameters(client, double, params, field, api):
    r = client.get(f"/api/sessions/{double}/render", params=params)
    assert r.status_code == 422
    assert api.error_of(r)["field"] == field


def test_render_changes_with_angle_when_the_renderer_is_installed(client, double):
    if not client.get("/api/info").json()["capabilities"]["render"]:
        pytest.skip("the angled renderer is not in this install")
    imgs = [
        np.asarray(
            Image.open(
                io.BytesIO(
                    client.get(
                        f"/api/sessions/{double}/render", params={"view": "A", "angle": a}
                    ).content
                )
            )
        )
        for a in (8, 80)
    ]
    # seen at 8 degrees the piece is foreshortened to sin 8 / sin 80 of its height at 80
    assert imgs[0].shape[1] == imgs[1].shape[1]
    ratio = imgs[0].shape[0] / imgs[1].shape[0]
    assert ratio == pytest.approx(np.sin(np.radians(8)) / np.sin(np.radians(80)), abs=0.03)
    assert imgs[0].shape != imgs[1].shape


def test_tile_override_per_pair(client, double, api):
    pairs = client.get(f"/api/sessions/{double}/pairs").json()
    assert pairs["editable"] is True and pairs["pairs"]
    p = pairs["pairs"][0]
    assert p["tile"] == p["default"] and not p["overridden"]
    assert p["options"][0]["exact"] is True
    before = client.get(f"/api/sessions/{double}/download/pattern.json").json()
    other = next(o["id"] for o in p["options"] if o["id"] != p["tile"])
    r = client.put(f"/api/sessions/{double}/pairs/{p['a']}/{p['b']}", json={"tile": other})
    assert r.status_code == 200
    edited = next(x for x in r.json()["pairs"] if (x["a"], x["b"]) == (p["a"], p["b"]))
    assert edited["tile"] == other and edited["overridden"]
    after = client.get(f"/api/sessions/{double}/download/pattern.json").json()
    assert after != before  # the pattern (and so its preview) follows the edit
    assert client.get(f"/api/sessions/{double}/tiles/{other}.png").status_code == 200
    # a tile written as rows works too; nonsense does not
    r = client.put(f"/api/sessions/{double}/pairs/{p['a']}/{p['b']}", json={"tile": "0/1^"})
    assert r.status_code == 200
    custom = next(x for x in r.json()["pairs"] if (x["a"], x["b"]) == (p["a"], p["b"]))
    assert custom["tile"] == "0/1^"
    assert client.get(f"/api/sessions/{double}/{custom['tile_picture']}").status_code == 200
    for tile, status in (("99999", 404), ("x/y", 422)):
        r = client.put(f"/api/sessions/{double}/pairs/{p['a']}/{p['b']}", json={"tile": tile})
        assert r.status_code == status, r.text
        assert api.error_of(r)["field"] == "tiles"
    r = client.put(f"/api/sessions/{double}/pairs/7/7", json={"tile": other})
    assert r.status_code == 404 and api.error_of(r)["code"] == "no_pair"
    # null restores the candidate's own tile
    r = client.put(f"/api/sessions/{double}/pairs/{p['a']}/{p['b']}", json={"tile": None})
    assert not next(x for x in r.json()["pairs"] if (x["a"], x["b"]) == (p["a"], p["b"]))[
        "overridden"
    ]
    assert client.get(f"/api/sessions/{double}/download/pattern.json").json() == before
    r = client.get(f"/api/sessions/{double}/tiles/99999.png")
    assert r.status_code == 404


def test_headon_mode_with_one_picture(client, api, pictures):
    if not client.get("/api/info").json()["capabilities"]["headon"]:
        pytest.skip("the head-on tiles are not in this install")
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.box_picture())
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "headon", "width_units": 18})
    job = api.run_job(client, sid, "candidates")
    assert job["status"] == "done", job
    c = client.get(f"/api/sessions/{sid}/candidates").json()["candidates"]
    assert c and c[0]["details"]["views"] == ["headon", "side"]


def test_knit_of_a_double_view_pattern(client, api, pictures):
    if not client.get("/api/info").json()["capabilities"]["knit"]:
        pytest.skip("the knitout compiler is not in this install")
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.bands(24, 36, 8))
    api.upload(client, sid, "b", pictures.bands(24, 36, 16))
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "double", "width_units": 12})
    assert api.run_job(client, sid, "candidates")["status"] == "done"
    job = api.run_job(client, sid, "knit")
    assert job["status"] == "done", job
    assert client.get(f"/api/sessions/{sid}/download/knitout.k").text.startswith(";!knitout-2")


def test_the_far_view_is_what_the_eye_resolves(client, double):
    """From far away the render is blurred by the eye's resolution (1 arc-minute), as much as the
    library says; from near it is the render itself, to the pixel."""
    from illuknit.design.tiles.perception import eye_blur_units, seen_from

    def get(**params):
        r = client.get(f"/api/sessions/{double}/render", params={"view": "A", **params})
        assert r.status_code == 200, r.text
        return np.asarray(Image.open(io.BytesIO(r.content)).convert("RGB"))

    near = get()
    assert (
        np.array_equal(get(distance=0.5), near)
        or np.abs(get(distance=0.5).astype(int) - near).max() <= 2
    )  # at half a metre a unit is far coarser than the eye's resolution
    far = get(distance=200)
    cols = client.get(f"/api/sessions/{double}/inputs").json()["cols"]
    sigma = eye_blur_units(200, gauge=7.0) * near.shape[1] / cols
    assert np.array_equal(far, seen_from(near, sigma))
    assert far.astype(float).std() < near.astype(float).std()  # detail is lost from afar


def test_eye_blur_grows_with_distance_and_fineness():
    from illuknit.core.errors import OptionError
    from illuknit.design.tiles.perception import eye_blur_units

    assert eye_blur_units(2) == pytest.approx(0.034, abs=1e-3)
    assert eye_blur_units(20) == pytest.approx(10 * eye_blur_units(2))
    assert eye_blur_units(2, gauge=14) == pytest.approx(2 * eye_blur_units(2))
    with pytest.raises(OptionError):
        eye_blur_units(0)
