"""The design app's JSON API through FastAPI's TestClient: every endpoint, and the bad inputs."""

from __future__ import annotations

import io
import json
import threading
import time
import zipfile

import numpy as np
import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")

from fastapi.testclient import TestClient
from PIL import Image

from illuknit.app import create_app, design
from illuknit.app.jobs import Job, JobRunner
from illuknit.app.server import AppConfig

DARK = (20, 20, 20)
LIGHT = (245, 240, 230)


def png(rgb: np.ndarray) -> bytes:
    buf = io.BytesIO()
    Image.fromarray(np.asarray(rgb, dtype=np.uint8)).save(buf, format="PNG")
    return buf.getvalue()


def two_tone(mask: np.ndarray) -> bytes:
    return png(np.where(mask[..., None], np.array(DARK), np.array(LIGHT)))


def box_picture(h: int = 24, w: int = 36, *, top: int = 6, left: int = 8) -> bytes:
    m = np.zeros((h, w), bool)
    m[top : top + h // 2, left : left + w // 2] = True
    return two_tone(m)


def bands(h: int, w: int, cut: int) -> bytes:
    """Rows above ``cut`` dark, below light: one colour per row (knittable one course at a time)."""
    m = np.zeros((h, w), bool)
    m[:cut] = True
    return two_tone(m)


@pytest.fixture(scope="module")
def app():
    return create_app(AppConfig(max_upload_bytes=200_000, isolate_knit=False))


@pytest.fixture(scope="module")
def client(app):
    with TestClient(app) as c:
        yield c


def new_session(client: TestClient) -> str:
    r = client.post("/api/sessions")
    assert r.status_code == 201
    return r.json()["id"]


def upload(
    client: TestClient,
    sid: str,
    slot: str,
    data: bytes,
    name: str = "pic.png",
    mime: str = "image/png",
):
    return client.put(f"/api/sessions/{sid}/images/{slot}", files={"file": (name, data, mime)})


def error_of(r) -> dict:
    body = r.json()
    assert set(body) == {"error"}, body
    assert body["error"]["message"], body
    return body["error"]


def run_job(client: TestClient, sid: str, kind: str, timeout: float = 60) -> dict:
    r = client.post(f"/api/sessions/{sid}/jobs", json={"kind": kind})
    assert r.status_code == 202, r.text
    jid = r.json()["id"]
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        job = client.get(f"/api/sessions/{sid}/jobs/{jid}").json()
        if job["status"] not in ("queued", "running"):
            return job
        time.sleep(0.05)
    raise AssertionError(f"job {kind} did not end within {timeout} s")


@pytest.fixture()
def double(client):
    """A session with two equal-size pictures, 2 colours, candidates computed."""
    sid = new_session(client)
    assert upload(client, sid, "a", box_picture()).status_code == 200
    assert upload(client, sid, "b", box_picture(top=2, left=2)).status_code == 200
    r = client.put(f"/api/sessions/{sid}/settings", json={"mode": "double", "width_units": 18})
    assert r.status_code == 200
    job = run_job(client, sid, "candidates")
    assert job["status"] == "done", job
    return sid


# -- app, sessions ----------------------------------------------------------------------------


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


def test_session_lifecycle_and_unknown_session(client):
    sid = new_session(client)
    s = client.get(f"/api/sessions/{sid}").json()
    assert s["id"] == sid and s["images"] == {} and s["candidates"] == 0
    assert client.delete(f"/api/sessions/{sid}").status_code == 200
    r = client.get(f"/api/sessions/{sid}")
    assert r.status_code == 404
    assert error_of(r)["code"] == "no_session"
    r = client.get("/api/sessions/nope/inputs")
    assert r.status_code == 404 and error_of(r)["field"] == "session"


def test_unknown_route_answers_json(client):
    r = client.get("/api/nothing-here")
    assert r.status_code == 404
    error_of(r)


def test_session_store_caps_live_sessions():
    app = create_app(AppConfig(max_sessions=2))
    with TestClient(app) as c:
        first = new_session(c)
        new_session(c)
        new_session(c)
        r = c.get(f"/api/sessions/{first}")
        assert r.status_code == 410 and error_of(r)["code"] == "evicted"
        assert "more than 2 sessions" in error_of(r)["message"]
        assert len(app.state.store) == 2


# -- uploads ----------------------------------------------------------------------------------


def test_upload_get_and_delete_image(client):
    sid = new_session(client)
    data = box_picture()
    r = upload(client, sid, "a", data, name="box.png")
    assert r.status_code == 200
    im = r.json()["images"]["a"]
    assert (im["width"], im["height"], im["filename"]) == (36, 24, "box.png")
    got = client.get(f"/api/sessions/{sid}/images/a")
    assert got.status_code == 200 and got.headers["content-type"] == "image/png"
    assert np.array_equal(
        np.asarray(Image.open(io.BytesIO(got.content))), np.asarray(Image.open(io.BytesIO(data)))
    )
    assert client.delete(f"/api/sessions/{sid}/images/a").json()["images"] == {}
    r = client.get(f"/api/sessions/{sid}/images/a")
    assert r.status_code == 404 and error_of(r)["field"] == "image_a"


def test_reupload_keeps_settings_and_bumps_revision(client):
    sid = new_session(client)
    upload(client, sid, "a", box_picture())
    s1 = client.put(f"/api/sessions/{sid}/settings", json={"width_units": 20, "n_colors": 2}).json()
    s2 = upload(client, sid, "a", box_picture(top=1)).json()
    assert s2["settings"] == s1["settings"]
    assert s2["revision"] > s1["revision"]


@pytest.mark.parametrize(
    ("data", "name", "mime", "status", "code"),
    [
        (b"hello, not a picture", "notes.txt", "text/plain", 415, "not_an_image"),
        (b"%PDF-1.4\n%...", "doc.png", "image/png", 415, "not_an_image"),
        (b"\x89PNG\r\n\x1a\n" + b"\x00" * 40, "broken.png", "image/png", 415, "not_an_image"),
        (b"", "empty.png", "image/png", 422, "empty"),
    ],
)
def test_bad_uploads_are_refused_next_to_the_control(client, data, name, mime, status, code):
    sid = new_session(client)
    r = upload(client, sid, "b", data, name=name, mime=mime)
    assert r.status_code == status, r.text
    err = error_of(r)
    assert err["field"] == "image_b" and err["code"] == code
    assert client.get(f"/api/sessions/{sid}").json()["images"] == {}


def test_one_pixel_picture_is_refused(client):
    sid = new_session(client)
    r = upload(client, sid, "a", png(np.zeros((1, 1, 3), np.uint8)))
    assert r.status_code == 415
    assert "2 x 2" in error_of(r)["message"]


def test_huge_upload_is_refused_with_the_limit(client):
    sid = new_session(client)
    noise = np.random.default_rng(0).integers(0, 256, (300, 300, 3), dtype=np.uint8)
    data = png(noise)
    assert len(data) > 200_000
    r = upload(client, sid, "a", data)
    assert r.status_code == 413
    err = error_of(r)
    assert err["field"] == "image_a" and err["code"] == "too_large"
    assert "MB" in err["message"]


def test_picture_with_too_many_pixels_is_refused_from_its_header(client):
    sid = new_session(client)
    buf = io.BytesIO()
    Image.new("1", (7200, 7000)).save(buf, format="PNG")  # 50.4 megapixels, a few kB
    r = upload(client, sid, "a", buf.getvalue())
    assert r.status_code == 413
    assert "megapixels" in error_of(r)["message"]


def test_big_picture_is_reduced_on_upload(client):
    sid = new_session(client)
    buf = io.BytesIO()
    Image.new("RGB", (2400, 600), DARK).save(buf, format="JPEG")
    r = upload(client, sid, "a", buf.getvalue(), name="wide.jpg", mime="image/jpeg")
    assert r.status_code == 200
    im = r.json()["images"]["a"]
    # reduced while decoding by a whole factor, to at most 2000 pixels (the library's reader)
    assert (im["width"], im["height"]) == (1200, 300)
    assert im["bytes"] == len(buf.getvalue())
    assert im["notes"] == ["reduced from 2400 x 600 to 1200 x 300 pixels while reading"]
    kept = Image.open(io.BytesIO(client.get(f"/api/sessions/{sid}/images/a").content))
    assert kept.size == (1200, 300)


def test_upload_without_file_and_bad_slot(client):
    sid = new_session(client)
    r = client.put(f"/api/sessions/{sid}/images/a", data={"x": "1"})
    assert r.status_code == 422 and error_of(r)["field"] == "image_a"
    r = upload(client, sid, "c", box_picture())
    assert r.status_code == 404 and error_of(r)["code"] == "bad_slot"


# -- settings and inputs ----------------------------------------------------------------------


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"width_units": 0}, "width_units"),
        ({"width_units": 5000}, "width_units"),
        ({"width_units": "wide"}, "width_units"),
        ({"width_cm": -3}, "width_cm"),
        ({"gauge": 0}, "gauge"),
        ({"n_colors": 9}, "n_colors"),
        ({"candidates": 0}, "candidates"),
        ({"mode": "triple"}, "mode"),
        ({"yarns": ["#000000"]}, "yarns"),
        ({"yarns": ["#000000", "not-a-colour"]}, "yarns"),
        ({"yarns": ["#000000", "#000"]}, "yarns"),
    ],
)
def test_settings_out_of_range_name_their_field(client, change, field):
    sid = new_session(client)
    before = client.get(f"/api/sessions/{sid}").json()["settings"]
    r = client.put(f"/api/sessions/{sid}/settings", json=change)
    assert r.status_code == 422, r.text
    assert error_of(r)["field"] == field
    assert client.get(f"/api/sessions/{sid}").json()["settings"] == before


def test_inputs_quantise_and_legend(client):
    sid = new_session(client)
    upload(client, sid, "a", box_picture())
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 18})
    inp = client.get(f"/api/sessions/{sid}/inputs").json()
    assert (inp["rows"], inp["cols"]) == (12, 18)
    legend = inp["legend"]["a"]
    assert [e["yarn_color"] for e in legend] == ["#1b1b1b", "#f4f0e8"]
    assert abs(sum(e["share"] for e in legend) - 1) < 1e-3
    q = client.get(inp["images"]["a"])
    assert q.status_code == 200
    arr = np.asarray(Image.open(io.BytesIO(q.content)))
    assert arr.shape == (12, 18, 3)
    assert {tuple(c) for c in arr.reshape(-1, 3)} == {(0x1B, 0x1B, 0x1B), (0xF4, 0xF0, 0xE8)}
    r = client.get(f"/api/sessions/{sid}/inputs/b.png")
    assert r.status_code == 404


def test_physical_size_uses_the_gauge(client):
    sid = new_session(client)
    upload(client, sid, "a", box_picture())
    client.put(
        f"/api/sessions/{sid}/settings",
        json={"mode": "single", "size_mode": "physical", "width_cm": 10.16, "gauge": 5},
    )
    assert client.get(f"/api/sessions/{sid}/inputs").json()["cols"] == 10  # 4 in x 5 st/in / 2


def test_inputs_missing_picture_names_the_slot(client):
    sid = new_session(client)
    upload(client, sid, "a", box_picture())
    r = client.get(f"/api/sessions/{sid}/inputs")  # default mode is double view
    assert r.status_code == 422
    assert error_of(r)["field"] == "image_b"


def test_mismatched_sizes_offer_resize(client):
    sid = new_session(client)
    upload(client, sid, "a", box_picture(24, 36))
    upload(client, sid, "b", box_picture(30, 30))
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "double", "width_units": 18})
    r = client.get(f"/api/sessions/{sid}/inputs")
    assert r.status_code == 409
    err = error_of(r)
    assert err["field"] == "image_b" and err["code"] == "size_mismatch"
    assert "Resize" in err["message"]
    client.put(f"/api/sessions/{sid}/settings", json={"resize": True})
    inp = client.get(f"/api/sessions/{sid}/inputs").json()
    assert (inp["rows"], inp["cols"]) == (12, 18)
    assert inp["notes"] and "stretched" in inp["notes"][0]


def test_more_colors_than_yarns_points_at_n_colors(client):
    sid = new_session(client)
    upload(client, sid, "a", box_picture())
    upload(client, sid, "b", box_picture(top=2))
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "double", "n_colors": 3})
    r = client.get(f"/api/sessions/{sid}/inputs")
    assert r.status_code == 422 and error_of(r)["field"] == "n_colors"


def three_tone(h: int = 24, w: int = 36) -> bytes:
    """Dark, middle and light bands: a 3-colour picture."""
    rgb = np.zeros((h, w, 3), np.uint8)
    rgb[: h // 3] = DARK
    rgb[h // 3 : 2 * h // 3] = (150, 110, 60)
    rgb[2 * h // 3 :] = LIGHT
    return png(rgb)


def test_single_view_three_colors_with_two_yarns_knits_a_mix(client):
    """What `illuknit single` accepts: 3 colours, 2 yarns, the middle colour a mix of both."""
    sid = new_session(client)
    upload(client, sid, "a", three_tone())
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
    assert run_job(client, sid, "candidates")["status"] == "done"
    doc = client.get(f"/api/sessions/{sid}/download/pattern.json").json()
    assert [y["rgb"] for y in doc["yarns"]] == yarns  # only the two yarns are knitted


@pytest.mark.parametrize(
    ("n_colors", "yarns", "field"),
    [
        (2, ["#000000", "#777777", "#ffffff"], "yarns"),
        (3, ["#000000", "#555555", "#aaaaaa", "#ffffff"], "yarns"),
    ],
)
def test_single_view_refuses_extra_yarns_next_to_the_yarns(client, n_colors, yarns, field):
    sid = new_session(client)
    upload(client, sid, "a", three_tone())
    client.put(
        f"/api/sessions/{sid}/settings",
        json={"mode": "single", "n_colors": n_colors, "yarns": yarns},
    )
    r = client.get(f"/api/sessions/{sid}/inputs")
    assert r.status_code == 422 and error_of(r)["field"] == field
    assert "knitted with 2 yarns" in error_of(r)["message"]


def test_single_view_four_colors_is_refused(client):
    sid = new_session(client)
    upload(client, sid, "a", box_picture())
    client.put(
        f"/api/sessions/{sid}/settings",
        json={
            "mode": "single",
            "n_colors": 4,
            "yarns": ["#000000", "#555555", "#aaaaaa", "#ffffff"],
        },
    )
    r = client.get(f"/api/sessions/{sid}/inputs")
    assert r.status_code == 422 and error_of(r)["field"] == "n_colors"


# -- single view: candidates, render, downloads, knitout ---------------------------------------


def test_single_view_flow_to_checked_knitout(client):
    sid = new_session(client)
    upload(client, sid, "a", box_picture())
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 18})
    assert run_job(client, sid, "candidates")["status"] == "done"
    cands = client.get(f"/api/sessions/{sid}/candidates").json()
    assert [c["rank"] for c in cands["candidates"]] == [1, 2] and cands["selected"] == 1
    assert cands["candidates"][0]["details"]["mismatch_A"] == 0.0
    pairs = client.get(f"/api/sessions/{sid}/pairs").json()
    assert pairs["editable"] is False and pairs["pairs"] == []
    r = client.put(f"/api/sessions/{sid}/pairs/0/0", json={"tile": "0"})
    assert r.status_code == 409 and error_of(r)["field"] == "tiles"
    # downloads before the knitout exists
    r = client.get(f"/api/sessions/{sid}/download/knitout.k")
    assert r.status_code == 409 and error_of(r)["field"] == "knit"
    for name, kind in (
        ("pattern.json", "application/json"),
        ("chart.png", "image/png"),
        ("instructions.txt", "text/plain"),
        ("previews.zip", "application/zip"),
    ):
        r = client.get(f"/api/sessions/{sid}/download/{name}")
        assert r.status_code == 200, (name, r.text[:200])
        assert r.headers["content-type"].startswith(kind)
        assert "attachment" in r.headers["content-disposition"]
    doc = client.get(f"/api/sessions/{sid}/download/pattern.json").json()
    assert doc["format"] == "illuknit-pattern" and (doc["rows"], doc["cols"]) == (12, 18)
    names = zipfile.ZipFile(
        io.BytesIO(client.get(f"/api/sessions/{sid}/download/previews.zip").content)
    ).namelist()
    assert any(n.endswith("contact.png") for n in names)
    assert "Row 1" in client.get(f"/api/sessions/{sid}/download/instructions.txt").text
    info = client.get("/api/info").json()["capabilities"]
    if not info["knit"]:
        pytest.skip("the knitout compiler is not in this install")
    assert client.get(f"/api/sessions/{sid}/knit").json() == {"ready": False}
    job = run_job(client, sid, "knit")
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


def test_dat_before_knitout_and_unknown_downloads(client, double):
    r = client.get(f"/api/sessions/{double}/download/pattern.dat")
    assert r.status_code == 409 and error_of(r)["field"] == "knit"
    assert "make the knitout first" in error_of(r)["message"]
    r = client.get(f"/api/sessions/{double}/download/secrets.txt")
    assert r.status_code == 404 and error_of(r)["field"] == "downloads"


def test_downloads_and_render_need_candidates(client):
    sid = new_session(client)
    for path in ("/download/pattern.json", "/render?view=A", "/pairs"):
        r = client.get(f"/api/sessions/{sid}{path}")
        assert r.status_code == 409, path
        assert error_of(r)["code"] == "no_candidates"


# -- double view: candidates, pick, render, tiles ---------------------------------------------


def test_double_view_candidates_pick_and_render(client, double):
    info = client.get("/api/info").json()["capabilities"]
    if not info["double"]:
        pytest.skip("the tile bank is not in this install")
    c = client.get(f"/api/sessions/{double}/candidates").json()
    ranks = [x["rank"] for x in c["candidates"]]
    assert ranks == list(range(1, len(ranks) + 1)) and ranks
    scores = [x["score"] for x in c["candidates"]]
    assert scores == sorted(scores)
    assert all(x["editable"] for x in c["candidates"])
    last = ranks[-1]
    assert (
        client.put(f"/api/sessions/{double}/selection", json={"candidate": last}).json()["selected"]
        == last
    )
    r = client.put(f"/api/sessions/{double}/selection", json={"candidate": 99})
    assert r.status_code == 422 and error_of(r)["field"] == "candidate"
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
    ],
)
def test_render_bad_parameters(client, double, params, field):
    r = client.get(f"/api/sessions/{double}/render", params=params)
    assert r.status_code == 422
    assert error_of(r)["field"] == field


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
    assert imgs[0].shape == imgs[1].shape
    assert not np.array_equal(imgs[0], imgs[1])


def test_tile_override_per_pair(client, double):
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
        assert error_of(r)["field"] == "tiles"
    r = client.put(f"/api/sessions/{double}/pairs/7/7", json={"tile": other})
    assert r.status_code == 404 and error_of(r)["code"] == "no_pair"
    # null restores the candidate's own tile
    r = client.put(f"/api/sessions/{double}/pairs/{p['a']}/{p['b']}", json={"tile": None})
    assert not next(x for x in r.json()["pairs"] if (x["a"], x["b"]) == (p["a"], p["b"]))[
        "overridden"
    ]
    assert client.get(f"/api/sessions/{double}/download/pattern.json").json() == before
    r = client.get(f"/api/sessions/{double}/tiles/99999.png")
    assert r.status_code == 404


def test_headon_mode_with_one_picture(client):
    if not client.get("/api/info").json()["capabilities"]["headon"]:
        pytest.skip("the head-on tiles are not in this install")
    sid = new_session(client)
    upload(client, sid, "a", box_picture())
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "headon", "width_units": 18})
    job = run_job(client, sid, "candidates")
    assert job["status"] == "done", job
    c = client.get(f"/api/sessions/{sid}/candidates").json()["candidates"]
    assert c and c[0]["details"]["views"] == ["headon", "side"]


def test_knit_of_a_double_view_pattern(client):
    if not client.get("/api/info").json()["capabilities"]["knit"]:
        pytest.skip("the knitout compiler is not in this install")
    sid = new_session(client)
    upload(client, sid, "a", bands(24, 36, 8))
    upload(client, sid, "b", bands(24, 36, 16))
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "double", "width_units": 12})
    assert run_job(client, sid, "candidates")["status"] == "done"
    job = run_job(client, sid, "knit")
    assert job["status"] == "done", job
    assert client.get(f"/api/sessions/{sid}/download/knitout.k").text.startswith(";!knitout-2")


# -- jobs ------------------------------------------------------------------------------------


def test_job_errors_are_reported_with_their_field(client):
    sid = new_session(client)
    r = client.post(f"/api/sessions/{sid}/jobs", json={"kind": "candidates"})
    assert r.status_code == 422 and error_of(r)["field"] == "image_a"
    r = client.post(f"/api/sessions/{sid}/jobs", json={"kind": "sweater"})
    assert r.status_code == 422 and error_of(r)["field"] == "kind"
    r = client.get(f"/api/sessions/{sid}/jobs/abc")
    assert r.status_code == 404


def test_jobs_are_private_to_their_session(client, double):
    other = new_session(client)
    job = client.post(f"/api/sessions/{double}/jobs", json={"kind": "candidates"}).json()
    r = client.get(f"/api/sessions/{other}/jobs/{job['id']}")
    assert r.status_code == 404
    assert client.delete(f"/api/sessions/{other}/jobs/{job['id']}").status_code == 404


def test_cancel_a_running_job():
    runner = JobRunner(workers=1)
    seen = []

    def slow(job: Job) -> int:
        for i in range(10_000):
            job.report(i / 10_000, f"step {i}")
            seen.append(i)
            time.sleep(0.001)
        return 1

    job = runner.submit("candidates", slow)
    while not seen:
        time.sleep(0.01)
    assert job.to_json()["status"] == "running"
    assert job.cancel()
    assert job.wait(10)
    assert job.status == "cancelled" and job.result is None
    assert len(seen) < 10_000
    assert not job.cancel()  # already over
    runner.shutdown()


def test_cancel_kills_isolated_work():
    runner = JobRunner(workers=1)
    started = threading.Event()

    def work(job: Job) -> str:
        started.set()
        return job.run_isolated(time.sleep, 120.0)  # a builtin: picklable for the spawned child

    job = runner.submit("knit", work)
    started.wait(10)
    time.sleep(0.2)
    job.cancel()
    assert job.wait(30), "cancelling must stop the worker process, not wait 120 s for it"
    assert job.status == "cancelled"
    ok = runner.submit("knit", lambda j: j.run_isolated(divmod, 7, 2))
    assert ok.wait(60) and ok.status == "done" and ok.result == (3, 1)
    runner.shutdown()


def test_cancel_through_the_api(client):
    sid = new_session(client)
    upload(client, sid, "a", box_picture())
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 18})
    assert run_job(client, sid, "candidates")["status"] == "done"
    app = client.app
    gate = threading.Event()

    def blocked(job: Job) -> None:
        while not gate.wait(0.01):
            job.report(0.5, "waiting")

    job = app.state.runner.submit("knit", blocked)
    app.state.store.get(sid).jobs["knit"] = job
    assert client.get(f"/api/sessions/{sid}/jobs/{job.id}").json()["status"] in (
        "queued",
        "running",
    )
    r = client.delete(f"/api/sessions/{sid}/jobs/{job.id}")
    assert r.status_code == 200 and r.json()["status"] == "cancelled"
    gate.set()


def test_a_new_upload_discards_a_stale_job_result(client):
    sid = new_session(client)
    upload(client, sid, "a", box_picture())
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 18})
    r = client.post(f"/api/sessions/{sid}/jobs", json={"kind": "candidates"})
    upload(client, sid, "a", box_picture(top=1))  # while (or after) the job runs
    jid = r.json()["id"]
    deadline = time.monotonic() + 30
    while client.get(f"/api/sessions/{sid}/jobs/{jid}").json()["status"] in ("queued", "running"):
        assert time.monotonic() < deadline
        time.sleep(0.05)
    assert client.get(f"/api/sessions/{sid}/candidates").json()["candidates"] == []


# -- two tabs at once --------------------------------------------------------------------------


def test_concurrent_sessions_do_not_mix_state(client):
    """Two tabs upload different pictures with different settings at the same time."""
    pics = {
        "left": (
            box_picture(24, 36),
            {"mode": "single", "width_units": 18, "yarns": ["#102030", "#f0e0d0"]},
        ),
        "right": (
            box_picture(40, 40, top=4),
            {"mode": "single", "width_units": 10, "yarns": ["#400000", "#e0ffe0"]},
        ),
    }
    sids = {k: new_session(client) for k in pics}
    results: dict[str, dict] = {}
    errors: list[BaseException] = []
    barrier = threading.Barrier(2)

    def tab(key: str) -> None:
        try:
            sid = sids[key]
            data, settings = pics[key]
            barrier.wait(10)
            for _ in range(3):
                assert upload(client, sid, "a", data).status_code == 200
                assert client.put(f"/api/sessions/{sid}/settings", json=settings).status_code == 200
            job = run_job(client, sid, "candidates")
            assert job["status"] == "done", job
            results[key] = {
                "inputs": client.get(f"/api/sessions/{sid}/inputs").json(),
                "pattern": client.get(f"/api/sessions/{sid}/download/pattern.json").json(),
                "image": client.get(f"/api/sessions/{sid}/images/a").content,
            }
        except BaseException as e:  # surfaced below
            errors.append(e)

    threads = [threading.Thread(target=tab, args=(k,)) for k in pics]
    for t in threads:
        t.start()
    for t in threads:
        t.join(60)
    assert not errors, errors
    for key, (data, settings) in pics.items():
        got = results[key]
        kept = np.asarray(Image.open(io.BytesIO(got["image"])))
        assert np.array_equal(kept, np.asarray(Image.open(io.BytesIO(data))))
        assert got["inputs"]["cols"] == settings["width_units"]
        assert [y["rgb"] for y in got["pattern"]["yarns"]] == settings["yarns"]
        assert got["pattern"]["cols"] == settings["width_units"]


def test_design_errors_are_app_errors():
    with pytest.raises(design.AppRequestError) as e:
        design.render_view(None, "A", angle=0)  # type: ignore[arg-type]
    assert e.value.field == "angle"
    assert json.dumps(design.capabilities())
