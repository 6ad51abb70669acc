"""The app binds safely: loopback unless told a concrete address, a loud warning on any other,
a bad address or a busy port refused before anything is created, and every answer carrying
the headers that keep it out of other sites' frames and sniffers (``illuknit/cli/app.py``,
``illuknit/app/middleware.py``)."""

from __future__ import annotations

import socket
import subprocess
import sys

import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("uvicorn", reason="the app extra is not installed: pip install 'illuknit[app]'")

from illuknit.cli import main
from illuknit.cli.app import listen

APP = (sys.executable, "-m", "illuknit", "app")


def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert err.startswith("illuknit: error: ") and "\n" not in err, err
    return err


@pytest.mark.parametrize("host", ["256.1.1.1", "not a host", "1.2.3.4.5"])
def test_a_bad_host_is_refused_before_the_data_folder_is_made(host, tmp_path, capsys):
    folder = tmp_path / "data"
    with pytest.raises(SystemExit) as e:
        main(["app", "--host", host, "--port", "0", "--data-dir", str(folder)])
    assert e.value.code == 2
    assert repr(host) in _one_error_line(capsys)
    assert not folder.exists()


def test_a_busy_port_is_refused_before_the_data_folder_is_made(tmp_path, capsys):
    folder = tmp_path / "data"
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen(1)
        port = s.getsockname()[1]
        with pytest.raises(SystemExit) as e:
            main(["app", "--port", str(port), "--data-dir", str(folder)])
    assert e.value.code == 2
    assert f"cannot listen on 127.0.0.1:{port}" in _one_error_line(capsys)
    assert not folder.exists()


@pytest.mark.parametrize("host", ["", "  ", "127.0.0.1", "localhost"])
def test_an_empty_host_is_loopback_never_every_interface(host):
    sock, shown, loopback = listen(host, 0)
    try:
        assert loopback
        if host != "localhost":  # a name may resolve to ::1 first on some machines
            assert sock.getsockname()[0] == "127.0.0.1" and shown == "127.0.0.1"
    finally:
        sock.close()


def test_ipv6_loopback_is_shown_in_brackets():
    if not socket.has_ipv6:
        pytest.skip("no IPv6 on this machine")
    try:
        sock, shown, loopback = listen("::1", 0)
    except Exception as e:  # an IPv6 stack without a loopback address
        pytest.skip(f"cannot listen on ::1 here: {e}")
    sock.close()
    assert (shown, loopback) == ("[::1]", True)


@pytest.mark.parametrize("host", ["0.0.0.0", "::"])
def test_every_interface_is_warned_about_loudly(host, tmp_path):
    if host == "::" and not socket.has_ipv6:
        pytest.skip("no IPv6 on this machine")
    proc = subprocess.Popen(
        [*APP, "--host", host, "--port", "0", "--data-dir", str(tmp_path / "data")],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        warning = proc.stderr.readline()
        served = proc.stdout.readline()
    finally:
        proc.terminate()
        proc.wait(30)
        proc.stdout.close()
        proc.stderr.close()
    assert warning.startswith("illuknit app: WARNING: listening on "), warning
    assert "anyone who can reach it" in warning and "--host 127.0.0.1" in warning
    assert "http://127.0.0.1:" in served  # an address a browser can open, never http://:port/


def test_loopback_serves_without_a_warning(tmp_path):
    proc = subprocess.Popen(
        [*APP, "--host", "", "--port", "0", "--data-dir", str(tmp_path / "data")],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        served = proc.stdout.readline()
    finally:
        proc.terminate()
        proc.wait(30)
        err = proc.stderr.read()
        proc.stdout.close()
        proc.stderr.close()
    assert served.startswith("illuknit app: serving http://127.0.0.1:"), served
    assert "WARNING" not in err


# -- headers on every answer -----------------------------------------------------------------


def _check_headers(r) -> None:
    h = r.headers
    assert h["x-content-type-options"] == "nosniff", r.url
    assert h["x-frame-options"] == "DENY", r.url
    assert h["referrer-policy"] == "no-referrer", r.url
    policy = h["content-security-policy"]
    assert "frame-ancestors 'none'" in policy, r.url
    assert "script-src 'self'" in policy or "default-src 'none'" in policy, r.url
    assert "unsafe-eval" not in policy


def test_every_answer_carries_the_security_headers(client, api, pictures, double):
    sid = api.new_session(client)
    assert api.upload(client, sid, "a", pictures.box_picture()).status_code == 200
    answers = [
        client.get("/"),
        client.get("/static/app.js"),
        client.get("/static/app.css"),
        client.get("/docs"),
        client.get("/api/info"),
        client.get(f"/api/sessions/{sid}"),
        client.get(f"/api/sessions/{sid}/images/a"),  # a picture
        client.get(f"/api/sessions/{double}/download/pattern.json"),  # a download
        client.get("/api/sessions/nope"),  # an error
        client.get("/no/such/page"),
        client.get("/", headers={"host": "evil.example"}),  # refused by the host guard
        client.put(  # refused by the upload limit, before the app reads it
            f"/api/sessions/{sid}/images/a",
            content=b"x" * 400_000,
            headers={"content-type": "multipart/form-data; boundary=x"},
        ),
    ]
    assert [r.status_code for r in answers[-4:]] == [404, 404, 400, 413]
    assert answers[7].status_code == 200 and "attachment" in answers[7].headers.get(
        "content-disposition", ""
    )
    for r in answers:
        _check_headers(r)


def test_the_page_uses_no_inline_script_or_style():
    """The policy allows the page's own files only: an inline script, style sheet or style
    attribute in the page would be blocked by it (the browser test runs the page under it)."""
    import re

    from illuknit.app.routers.static import STATIC_DIR

    page = (STATIC_DIR / "index.html").read_text()
    assert not re.search(r"<script(?![^>]*\bsrc=)", page)
    assert "<style" not in page and " style=" not in page
    assert not re.search(r"\son[a-z]+=", page)  # no inline event handlers
    for js in STATIC_DIR.glob("*.js"):
        text = js.read_text()
        assert "style=" not in text, js.name  # HTML strings with a style attribute
        assert "eval(" not in text and "new Function" not in text, js.name
