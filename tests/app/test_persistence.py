"""The app keeps everything: against a real ``illuknit app`` process that is stopped (Ctrl-C) or
killed (``kill -9``) and started again on the same data folder, and against the memory bound.

A session with two pictures, settings, a chosen candidate, a tile edit and an accepted suggested
edit comes back whole (the same state, the same candidates, Undo working); a job running when
the server died comes back ``interrupted`` and runs again; the knit worker dies with the
server; an oversized upload is answered 413 with its message, to httpx and to curl.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time

import pytest

pytest.importorskip("fastapi", reason="the app extra is not installed: pip install 'illuknit[app]'")
pytest.importorskip("uvicorn", reason="the app extra is not installed: pip install 'illuknit[app]'")
httpx = pytest.importorskip("httpx")


def _design(c, pictures, api) -> tuple[str, dict]:
    """A double-view session: two pictures, settings, candidates, a picked one, an accepted
    edit (with its candidates found again) and a tile edit; its state, candidates and pairs."""
    sid = api.new_session(c)
    assert api.upload(c, sid, "a", pictures.word("UP")).status_code == 200
    assert api.upload(c, sid, "b", pictures.word("ON")).status_code == 200
    r = c.put(f"/api/sessions/{sid}/settings", json={"mode": "double", "width_units": 24})
    assert r.status_code == 200, r.text
    assert api.run_job(c, sid, "candidates", timeout=300)["status"] == "done"
    assert api.run_job(c, sid, "suggestions", timeout=300)["status"] == "done"
    edits = c.get(f"/api/sessions/{sid}/suggestions").json()["suggestions"]
    assert edits, "the word pictures must get a suggested edit"
    r = c.post(f"/api/sessions/{sid}/suggestions/{edits[0]['id']}/accept")
    assert r.status_code == 200, r.text
    assert api.wait_job(c, sid, r.json()["job"]["id"], timeout=300)["status"] == "done"
    assert api.run_job(c, sid, "measures", timeout=300)["status"] == "done"
    cands = c.get(f"/api/sessions/{sid}/candidates").json()
    pick = 2 if len(cands["candidates"]) > 1 else 1
    assert c.put(f"/api/sessions/{sid}/selection", json={"candidate": pick}).status_code == 200
    pairs = c.get(f"/api/sessions/{sid}/pairs").json()["pairs"]
    pair = pairs[0]
    other = next(o["id"] for o in pair["options"] if o["id"] != pair["tile"])
    r = c.put(f"/api/sessions/{sid}/pairs/{pair['a']}/{pair['b']}", json={"tile": other})
    assert r.status_code == 200, r.text
    return sid, _snapshot(c, sid)


def _snapshot(c, sid: str) -> dict:
    """Everything the page shows of a session (jobs aside: their timings move)."""
    state = c.get(f"/api/sessions/{sid}").json()
    state.pop("jobs")
    return {
        "state": state,
        "candidates": c.get(f"/api/sessions/{sid}/candidates").json(),
        "pairs": c.get(f"/api/sessions/{sid}/pairs").json(),
        "pattern": c.get(f"/api/sessions/{sid}/download/pattern.json").content,
        "image_a": c.get(f"/api/sessions/{sid}/images/a").content,
    }


@pytest.mark.parametrize("how", ["interrupt", "kill"])
def test_a_session_survives_a_restart_whole_and_undo_still_works(app_process, pictures, api, how):
    server = app_process()
    with httpx.Client(base_url=server.url, timeout=60) as c:
        sid, before = _design(c, pictures, api)
    server.stop(how)
    server.start()
    with httpx.Client(base_url=server.url, timeout=60) as c:
        after = _snapshot(c, sid)
        assert after == before
        assert before["state"]["history"]["undo"], "the accepted edit is on the undo list"
        r = c.post(f"/api/sessions/{sid}/history/undo")
        assert r.status_code == 200, r.text
        assert r.json()["job"] is None, "the design before the edit comes back with its candidates"
        assert r.json()["state"]["history"]["redo"] == before["state"]["history"]["undo"][:1]
        r = c.post(f"/api/sessions/{sid}/history/redo")
        assert r.status_code == 200, r.text


def test_an_evicted_session_comes_back_from_disk(tmp_path, pictures, api):
    """The memory bound takes a session out of memory, never off the disk: its page gets it
    back whole (in memory only, today's 410 ``evicted``)."""
    from fastapi.testclient import TestClient

    from illuknit.app import create_app
    from illuknit.app.server import AppConfig

    app = create_app(AppConfig(isolate_knit=False, data_dir=tmp_path / "data"))
    with TestClient(app) as c:
        sid, before = _design(c, pictures, api)
        store = app.state.store
        api.evict(store, sid)
        assert sid not in store.in_memory()
        assert _snapshot(c, sid) == before
        assert sid in store.in_memory()
        assert c.post(f"/api/sessions/{sid}/history/undo").status_code == 200


def test_many_big_sessions_lose_nothing_to_the_memory_bound(tmp_path):
    """64 sessions of two pictures that together hold three times the memory bound (the case
    of 64 sessions of two 2000-px pictures under 512 MB, at a sixteenth of the size): every one
    comes back with its pictures (in memory only, two thirds were closed and their work lost)."""
    import numpy as np
    from fastapi.testclient import TestClient

    from illuknit.app import create_app
    from illuknit.app.server import AppConfig
    from illuknit.app.sessions import UploadedImage

    app = create_app(
        AppConfig(isolate_knit=False, data_dir=tmp_path / "data", max_session_bytes=32 * 2**20)
    )
    store = app.state.store
    rng = np.random.default_rng(0)
    tile = rng.integers(0, 256, (50, 50, 3), dtype=np.uint8)
    sids = []
    for k in range(64):
        s = store.create()
        with s.lock:
            for slot in ("a", "b"):
                rgb = np.tile(tile, (10, 10, 1))
                rgb[0, 0] = (k, slot == "a", 7)  # each picture its own
                s.images[slot] = UploadedImage(f"{slot}{k}.png", 1, rgb)
            s.bump()
        store.save(s)
        store.trim(keep=s.id)
        sids.append(s.id)
    assert len(store.in_memory()) <= 22, "the memory bound took most sessions out of memory"
    with TestClient(app) as c:
        for k, sid in enumerate(sids):
            state = c.get(f"/api/sessions/{sid}").json()
            assert state["images"]["a"]["filename"] == f"a{k}.png"
            assert store.nbytes() <= store.max_bytes + 2 * 500 * 500 * 3


@pytest.mark.parametrize("how", ["interrupt", "kill"])
def test_a_job_cut_short_by_a_stop_is_interrupted_and_runs_again(app_process, pictures, api, how):
    server = app_process()
    with httpx.Client(base_url=server.url, timeout=60) as c:
        sid = api.new_session(c)
        assert api.upload(c, sid, "a", pictures.word("UP")).status_code == 200
        assert api.upload(c, sid, "b", pictures.word("ON")).status_code == 200
        r = c.put(f"/api/sessions/{sid}/settings", json={"mode": "double", "width_units": 24})
        assert r.status_code == 200
        job = c.post(f"/api/sessions/{sid}/jobs", json={"kind": "suggestions"}).json()
        # measuring suggested edits takes seconds: the server dies while it runs
        assert c.get(f"/api/sessions/{sid}/jobs/{job['id']}").json()["status"] in (
            "queued",
            "running",
        )
    server.stop(how)
    server.start()
    with httpx.Client(base_url=server.url, timeout=60) as c:
        state = c.get(f"/api/sessions/{sid}").json()
        assert state["jobs"]["suggestions"]["status"] == "interrupted"
        assert "run it again" in state["jobs"]["suggestions"]["message"]
        polled = c.get(f"/api/sessions/{sid}/jobs/{job['id']}").json()
        assert polled["status"] == "interrupted"
        again = api.run_job(c, sid, "suggestions", timeout=300)
        assert again["status"] == "done", again


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="finds the worker through /proc")
def test_the_knit_worker_dies_with_a_killed_server(app_process, pictures, api):
    import numpy as np

    server = app_process()
    with httpx.Client(base_url=server.url, timeout=60) as c:
        sid = api.new_session(c)
        rgb = np.full((400, 534, 3), 240, np.uint8)
        rgb[:, ::3] = 20  # many colour changes per row: knitting and checking take a while
        rgb[::7] = 20
        assert api.upload(c, sid, "a", pictures.png(rgb)).status_code == 200
        r = c.put(f"/api/sessions/{sid}/settings", json={"mode": "single", "width_units": 267})
        assert r.status_code == 200, r.text
        assert api.run_job(c, sid, "candidates", timeout=300)["status"] == "done"
        job = c.post(f"/api/sessions/{sid}/jobs", json={"kind": "knit"}).json()
        deadline = time.monotonic() + 60
        while not (workers := server.children()):
            assert time.monotonic() < deadline, "no knit worker was started"
            time.sleep(0.02)
        time.sleep(1.5)  # past reading its work: the worker is knitting (for about a minute)
        status = c.get(f"/api/sessions/{sid}/jobs/{job['id']}").json()["status"]
        assert status == "running", "the worker must still be at work when the server dies"
    server.stop("kill")
    deadline = time.monotonic() + 2.0
    while any(os.path.exists(f"/proc/{pid}") and not _zombie(pid) for pid in workers):
        assert time.monotonic() < deadline, f"the knit worker {workers} outlived the server"
        time.sleep(0.02)


def _zombie(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] == "Z"
    except OSError:
        return True


@pytest.fixture(scope="module")
def oversized(tmp_path_factory):
    """A 40 MB file (over the 32 MB default limit), as random bytes."""
    path = tmp_path_factory.mktemp("big") / "big.png"
    path.write_bytes(os.urandom(40 * 2**20))
    return path


def test_an_oversized_upload_is_answered_413_to_httpx(app_process, oversized):
    server = app_process()
    with httpx.Client(base_url=server.url, timeout=120) as c:
        sid = c.post("/api/sessions").json()["id"]
        for send in ("whole", "streamed", "chunked"):
            if send == "whole":
                r = c.put(
                    f"/api/sessions/{sid}/images/a",
                    files={"file": ("big.png", oversized.read_bytes(), "image/png")},
                )
            elif send == "streamed":
                with open(oversized, "rb") as f:
                    r = c.put(
                        f"/api/sessions/{sid}/images/a", files={"file": ("big.png", f, "image/png")}
                    )
            else:

                def chunks():
                    with open(oversized, "rb") as f:
                        while block := f.read(2**20):
                            yield block

                r = c.put(
                    f"/api/sessions/{sid}/images/a",
                    content=chunks(),
                    headers={"content-type": "multipart/form-data; boundary=x"},
                )
            assert r.status_code == 413, (send, r.text)
            assert r.json()["error"]["code"] == "too_large", send
            assert "32 MB" in r.json()["error"]["message"], send
        # the server is fine afterwards
        assert c.get(f"/api/sessions/{sid}").status_code == 200


@pytest.mark.skipif(shutil.which("curl") is None, reason="curl is not installed")
@pytest.mark.parametrize(
    "options",
    [[], ["-H", "Expect:"], ["-H", "Expect:", "-H", "Transfer-Encoding: chunked"]],
    ids=["expect-100", "no-expect", "chunked"],
)
def test_an_oversized_upload_is_answered_413_to_curl(app_process, oversized, options):
    server = app_process()
    sid = httpx.post(f"{server.url}/api/sessions").json()["id"]
    url = f"{server.url}/api/sessions/{sid}/images/a"
    if "Transfer-Encoding: chunked" in options:
        body = ["-H", "Content-Type: image/png", "--data-binary", f"@{oversized}"]
    else:
        body = ["-F", f"file=@{oversized};type=image/png"]
    out = subprocess.run(
        ["curl", "-sS", "-X", "PUT", *options, *body, url, "-w", "\n%{http_code}"],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert out.returncode == 0, out.stderr
    text, _, code = out.stdout.rpartition("\n")
    assert code == "413", out.stdout[-500:]
    assert '"too_large"' in text and "32 MB" in text


def test_a_refused_upload_leaves_the_connection_open_while_the_body_is_sent(app_process):
    """The mechanism behind both tests above, deterministic: the 413 comes from the headers, and
    the server then reads the body the client goes on sending and serves the next request on the
    same connection. (Closing at the 413 resets a connection whose client is still sending, and
    a client may then lose the answer: "peer closed connection without sending complete message
    body".)"""
    import json
    import socket

    server = app_process()
    sid = httpx.post(f"{server.url}/api/sessions").json()["id"]
    size = 40 * 2**20
    with socket.create_connection(("127.0.0.1", server.port), timeout=60) as sock:
        sock.sendall(
            (
                f"PUT /api/sessions/{sid}/images/a HTTP/1.1\r\nHost: 127.0.0.1:{server.port}\r\n"
                "Content-Type: multipart/form-data; boundary=x\r\n"
                f"Content-Length: {size}\r\n\r\n"
            ).encode()
        )
        reader = sock.makefile("rb")
        status = reader.readline()
        headers = {}
        while (line := reader.readline()) not in (b"\r\n", b""):
            key, _, value = line.decode().partition(":")
            headers[key.strip().lower()] = value.strip()
        body = json.loads(reader.read(int(headers["content-length"])))
        assert status.split()[1] == b"413" and body["error"]["code"] == "too_large"
        assert headers.get("connection") != "close"
        block = bytes(2**20)
        for _ in range(size // len(block)):
            sock.sendall(block)  # the server reads it (and drops it): no reset
        sock.sendall(
            f"GET /api/sessions/{sid} HTTP/1.1\r\nHost: 127.0.0.1:{server.port}\r\n\r\n".encode()
        )
        assert reader.readline().split()[1] == b"200"


def test_the_cli_refuses_a_data_folder_in_use(app_process, tmp_path):
    server = app_process()
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "illuknit",
            "app",
            "--port",
            "0",
            "--data-dir",
            str(server.data_dir),
        ],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert out.returncode == 2
    assert out.stderr.count("\n") == 1 and "another illuknit app" in out.stderr
