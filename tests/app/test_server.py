"""The design app served for real: `illuknit app` in a subprocess, and uvicorn on a loopback port.

Everything is bounded in time: servers run on free loopback ports, every wait has a timeout, and
the subprocess is terminated by its own handle.
"""

from __future__ import annotations

import contextlib
import http.client
import json
import queue
import socket
import subprocess
import sys
import threading
import time
import urllib.request

import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
uvicorn = pytest.importorskip(
    "uvicorn", reason="the app extra is not installed: pip install 'illuknit[app]'"
)

from illuknit.app import create_app  # noqa: E402
from illuknit.app.server import AppConfig  # noqa: E402
from illuknit.cli import main  # noqa: E402


@pytest.fixture(scope="module")
def server(serve_app):
    """uvicorn in a background thread on a free loopback port, with a 100 kB upload limit."""
    with serve_app(create_app(AppConfig(max_upload_bytes=100_000, isolate_knit=False))) as port:
        yield port


def post_session(port: int) -> str:
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    conn.request("POST", "/api/sessions")
    sid = json.loads(conn.getresponse().read())["id"]
    conn.close()
    return sid


def multipart(body: bytes, boundary: str = "illuknitboundary") -> tuple[bytes, str]:
    head = (
        f'--{boundary}\r\nContent-Disposition: form-data; name="file"; filename="big.png"\r\n'
        "Content-Type: image/png\r\n\r\n"
    ).encode()
    return (
        head + body + f"\r\n--{boundary}--\r\n".encode(),
        f"multipart/form-data; boundary={boundary}",
    )


def test_declared_oversize_upload_is_refused_before_reading(server):
    sid = post_session(server)
    conn = http.client.HTTPConnection("127.0.0.1", server, timeout=10)
    conn.putrequest("PUT", f"/api/sessions/{sid}/images/b")
    conn.putheader("Content-Type", "multipart/form-data; boundary=x")
    conn.putheader("Content-Length", str(50_000_000))
    conn.endheaders()  # no body sent at all: the answer must come from the header alone
    r = conn.getresponse()
    assert r.status == 413
    err = json.loads(r.read())["error"]
    assert err["field"] == "image_b" and err["code"] == "too_large"
    conn.close()


def test_chunked_oversize_upload_is_refused(server):
    sid = post_session(server)
    body, ctype = multipart(b"\x89PNG" + b"\0" * 300_000)
    conn = http.client.HTTPConnection("127.0.0.1", server, timeout=10)
    chunks = (body[i : i + 16_384] for i in range(0, len(body), 16_384))
    # the server may answer and close before the client has sent everything
    with contextlib.suppress(BrokenPipeError, ConnectionResetError):
        conn.request(
            "PUT",
            f"/api/sessions/{sid}/images/a",
            body=chunks,
            headers={"Content-Type": ctype},
            encode_chunked=True,
        )
    r = conn.getresponse()
    assert r.status == 413
    assert json.loads(r.read())["error"]["field"] == "image_a"
    conn.close()


def test_small_upload_goes_through_the_limit(server):
    import io

    import numpy as np
    from PIL import Image

    sid = post_session(server)
    buf = io.BytesIO()
    Image.fromarray(np.full((8, 8, 3), 200, np.uint8)).save(buf, format="PNG")
    body, ctype = multipart(buf.getvalue())
    conn = http.client.HTTPConnection("127.0.0.1", server, timeout=10)
    conn.request("PUT", f"/api/sessions/{sid}/images/a", body=body, headers={"Content-Type": ctype})
    r = conn.getresponse()
    assert r.status == 200, r.read()
    assert json.loads(r.read())["images"]["a"]["width"] == 8
    conn.close()


def test_cli_app_serves_the_page():
    """`illuknit app --port 0` prints its URL, serves page and API, and stops when terminated."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "illuknit", "app", "--port", "0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    lines: queue.Queue[str] = queue.Queue()
    threading.Thread(target=lambda: lines.put(proc.stdout.readline()), daemon=True).start()  # type: ignore[union-attr]
    try:
        try:
            first = lines.get(timeout=60)
        except queue.Empty:
            pytest.fail("`illuknit app` printed nothing within 60 s")
        assert first.startswith("illuknit app: serving http://127.0.0.1:"), first
        url = first.split()[3]
        deadline = time.monotonic() + 20
        while True:
            try:
                with urllib.request.urlopen(url + "api/info", timeout=5) as r:
                    info = json.loads(r.read())
                break
            except OSError:
                assert time.monotonic() < deadline and proc.poll() is None, proc.stderr.read()  # type: ignore[union-attr]
                time.sleep(0.1)
        assert info["capabilities"]["single"] is True
        with urllib.request.urlopen(url, timeout=5) as r:
            assert b"illuknit" in r.read()
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait(timeout=5)


def test_cli_app_busy_port_is_one_clear_error(capsys):
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen(1)
        port = s.getsockname()[1]
        with pytest.raises(SystemExit) as e:
            main(["app", "--port", str(port)])
    assert e.value.code == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("illuknit: error: cannot listen on 127.0.0.1:") and "\n" not in err


def test_cli_app_help_and_bad_port(capsys):
    try:
        main(["app", "--help"])
    except SystemExit as e:
        assert e.code == 0
    assert "--port" in capsys.readouterr().out
    with pytest.raises(SystemExit) as e:
        main(["app", "--port", "99999"])
    assert e.value.code == 2
