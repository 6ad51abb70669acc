"""Pictures through the JSON API: uploads and their refusals, quantised inputs
(``routers/pictures.py``).
"""

from __future__ import annotations

import io

import numpy as np
import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("multipart", reason="python-multipart is not installed")

from PIL import Image


def test_upload_get_and_delete_image(client, api, pictures):
    sid = api.new_session(client)
    data = pictures.box_picture()
    r = api.upload(client, sid, "a", data, name="box.png")
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
    assert r.status_code == 404 and api.error_of(r)["field"] == "image_a"


def test_reupload_keeps_settings_and_bumps_revision(client, api, pictures):
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.box_picture())
    s1 = client.put(f"/api/sessions/{sid}/settings", json={"width_units": 20, "n_colors": 2}).json()
    s2 = api.upload(client, sid, "a", pictures.box_picture(top=1)).json()
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
def test_bad_uploads_are_refused_next_to_the_control(client, data, name, mime, status, code, api):
    sid = api.new_session(client)
    r = api.upload(client, sid, "b", data, name=name, mime=mime)
    assert r.status_code == status, r.text
    err = api.error_of(r)
    assert err["field"] == "image_b" and err["code"] == code
    assert client.get(f"/api/sessions/{sid}").json()["images"] == {}


def test_one_pixel_picture_is_refused(client, api, pictures):
    sid = api.new_session(client)
    r = api.upload(client, sid, "a", pictures.png(np.zeros((1, 1, 3), np.uint8)))
    assert r.status_code == 415
    assert "2 x 2" in api.error_of(r)["message"]


def padded_png(rgb: np.ndarray, size: int) -> bytes:
    """A PNG of ``rgb`` exactly ``size`` bytes long: a private chunk (``ilKp``, which readers
    skip) before IEND makes up the difference."""
    import struct
    import zlib

    base = io.BytesIO()
    Image.fromarray(rgb).save(base, format="PNG")
    head, iend = base.getvalue()[:-12], base.getvalue()[-12:]
    fill = size - len(head) - len(iend) - 12
    assert fill >= 0, f"a PNG of this picture is over {size} bytes already"
    data = bytes(fill)
    chunk = struct.pack(">I", fill) + b"ilKp" + data + struct.pack(">I", zlib.crc32(b"ilKp" + data))
    out = head + chunk + iend
    assert len(out) == size
    return out


def test_one_upload_limit_from_the_configuration(client, api, pictures):
    """The configured limit (200 000 bytes in these tests) is the one limit: a file of exactly
    that size is accepted, one byte more is refused once, with the one message, which the page
    gets from /api/info to say the same before sending a file."""
    from illuknit.app.inputs import too_large_message

    limit = client.app.state.config.max_upload_bytes
    message = too_large_message(limit)
    assert client.get("/api/info").json()["limits"]["too_large"] == message
    rgb = np.zeros((24, 36, 3), np.uint8)
    rgb[6:18, 8:26] = pictures.LIGHT
    sid = api.new_session(client)
    r = api.upload(client, sid, "a", padded_png(rgb, limit))
    assert r.status_code == 200, r.text
    assert r.json()["images"]["a"]["bytes"] == limit
    got = np.asarray(Image.open(io.BytesIO(client.get(f"/api/sessions/{sid}/images/a").content)))
    assert np.array_equal(got, rgb)
    # one byte over: inside the request's framing allowance, so the upload route refuses it
    r = api.upload(client, sid, "b", padded_png(rgb, limit + 1))
    assert r.status_code == 413
    assert api.error_of(r) == {"message": message, "field": "image_b", "code": "too_large"}
    # far over: the request itself is refused before it is read, in the same words
    r = api.upload(client, sid, "b", padded_png(rgb, 3 * limit))
    assert r.status_code == 413
    assert api.error_of(r) == {"message": message, "field": "image_b", "code": "too_large"}
    assert "195.3 kB" in message and "b" not in client.get(f"/api/sessions/{sid}").json()["images"]


def test_a_configured_limit_over_the_default_is_the_limit(api, pictures):
    """No second, built-in limit: a server configured for larger files takes a file over the
    default limit (32 MB)."""
    from fastapi.testclient import TestClient

    from illuknit.app import create_app
    from illuknit.app.inputs import MAX_UPLOAD_BYTES
    from illuknit.app.server import AppConfig

    size = MAX_UPLOAD_BYTES + 1000
    app = create_app(AppConfig(max_upload_bytes=size, isolate_knit=False))
    with TestClient(app) as c:
        sid = api.new_session(c)
        r = api.upload(c, sid, "a", padded_png(np.full((8, 8, 3), 200, np.uint8), size))
        assert r.status_code == 200, r.text
        assert r.json()["images"]["a"]["bytes"] == size


def test_picture_with_too_many_pixels_is_refused_from_its_header(client, api):
    sid = api.new_session(client)
    buf = io.BytesIO()
    Image.new("1", (7200, 7000)).save(buf, format="PNG")  # 50.4 megapixels, a few kB
    r = api.upload(client, sid, "a", buf.getvalue())
    assert r.status_code == 413
    assert "megapixels" in api.error_of(r)["message"]


def test_big_picture_is_reduced_on_upload(client, api, pictures):
    sid = api.new_session(client)
    buf = io.BytesIO()
    Image.new("RGB", (2400, 600), pictures.DARK).save(buf, format="JPEG")
    r = api.upload(client, sid, "a", buf.getvalue(), name="wide.jpg", mime="image/jpeg")
    assert r.status_code == 200
    im = r.json()["images"]["a"]
    # reduced while decoding by a whole factor, to at most 2000 pixels (the library's reader)
    assert (im["width"], im["height"]) == (1200, 300)
    assert im["bytes"] == len(buf.getvalue())
    assert im["notes"] == ["reduced from 2400 x 600 to 1200 x 300 pixels while reading"]
    kept = Image.open(io.BytesIO(client.get(f"/api/sessions/{sid}/images/a").content))
    assert kept.size == (1200, 300)


def test_upload_without_file_and_bad_slot(client, api, pictures):
    sid = api.new_session(client)
    r = client.put(f"/api/sessions/{sid}/images/a", data={"x": "1"})
    assert r.status_code == 422 and api.error_of(r)["field"] == "image_a"
    r = api.upload(client, sid, "c", pictures.box_picture())
    assert r.status_code == 404 and api.error_of(r)["code"] == "bad_slot"


def test_inputs_quantise_and_legend(client, api, pictures):
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.box_picture())
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 18})
    inp = client.get(f"/api/sessions/{sid}/inputs").json()
    assert (inp["rows"], inp["cols"]) == (17, 18)  # 2 : 3 picture, units 0.7 as tall as wide
    size = inp["finished_size"]  # the picture's 2 : 3, knitted: within 3 %
    assert size["height_cm"] / size["width_cm"] == pytest.approx(2 / 3, rel=0.03)
    assert "cm" in size["text"] and "in)" in size["text"]
    legend = inp["legend"]["a"]
    assert [e["yarn_color"] for e in legend] == ["#1b1b1b", "#f4f0e8"]
    assert abs(sum(e["share"] for e in legend) - 1) < 1e-3
    q = client.get(inp["images"]["a"])
    assert q.status_code == 200
    arr = np.asarray(Image.open(io.BytesIO(q.content)))
    # the 17 x 18 grid in the fabric's proportions, 8 pixels a unit across: the picture's 2 : 3
    assert arr.shape == (round(17 * 8 * 0.7), 18 * 8, 3)
    assert arr.shape[0] / arr.shape[1] == pytest.approx(2 / 3, rel=0.03)
    assert {tuple(c) for c in arr.reshape(-1, 3)} == {(0x1B, 0x1B, 0x1B), (0xF4, 0xF0, 0xE8)}
    r = client.get(f"/api/sessions/{sid}/inputs/b.png")
    assert r.status_code == 404


def test_physical_size_uses_the_gauge(client, api, pictures):
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.box_picture())
    client.put(
        f"/api/sessions/{sid}/settings",
        json={"mode": "single", "size_mode": "physical", "width_cm": 10.16, "gauge": 5},
    )
    assert client.get(f"/api/sessions/{sid}/inputs").json()["cols"] == 10  # 4 in x 5 st/in / 2


def test_inputs_missing_picture_names_the_slot(client, api, pictures):
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.box_picture())
    r = client.get(f"/api/sessions/{sid}/inputs")  # default mode is double view
    assert r.status_code == 422
    assert api.error_of(r)["field"] == "image_b"


def test_mismatched_sizes_offer_resize(client, api, pictures):
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.box_picture(24, 36))
    api.upload(client, sid, "b", pictures.box_picture(30, 30))
    client.put(f"/api/sessions/{sid}/settings", json={"mode": "double", "width_units": 18})
    r = client.get(f"/api/sessions/{sid}/inputs")
    assert r.status_code == 409
    err = api.error_of(r)
    assert err["field"] == "image_b" and err["code"] == "size_mismatch"
    assert "Resize" in err["message"]
    client.put(f"/api/sessions/{sid}/settings", json={"resize": True})
    inp = client.get(f"/api/sessions/{sid}/inputs").json()
    assert (inp["rows"], inp["cols"]) == (17, 18)  # 2 : 3 picture, units 0.7 as tall as wide
    assert inp["notes"] and "stretched" in inp["notes"][0]


def test_more_colors_than_yarns_points_at_n_colors(client, api, pictures):
    sid = api.new_session(client)
    api.upload(client, sid, "a", pictures.box_picture())
    api.upload(client, sid, "b", pictures.box_picture(top=2))
    # yarns given with the colour count are the designer's: none is added (a colour count
    # alone adds yarns from the pictures: tests/app/test_first_hour.py)
    two = ["#1b1b1b", "#f4f0e8"]
    r = client.put(
        f"/api/sessions/{sid}/settings", json={"mode": "double", "n_colors": 3, "yarns": two}
    )
    assert r.json()["settings"]["yarns"] == two
    r = client.get(f"/api/sessions/{sid}/inputs")
    assert r.status_code == 422 and api.error_of(r)["field"] == "n_colors"
