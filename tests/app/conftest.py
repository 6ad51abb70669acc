"""Shared fixtures of the app tests."""

from __future__ import annotations

import contextlib
import socket
import threading
import time
from collections.abc import Callable, Iterator
from types import SimpleNamespace
from typing import Any

import pytest


@contextlib.contextmanager
def _serve(app: Any) -> Iterator[int]:
    import uvicorn

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = int(s.getsockname()[1])
    srv = uvicorn.Server(uvicorn.Config(app, host="127.0.0.1", port=port, log_level="warning"))
    thread = threading.Thread(target=srv.run, daemon=True)
    thread.start()
    deadline = time.monotonic() + 20
    while not srv.started:
        assert time.monotonic() < deadline, "server did not start"
        assert thread.is_alive(), "server thread died"
        time.sleep(0.02)
    try:
        yield port
    finally:
        srv.should_exit = True
        thread.join(10)


@pytest.fixture(autouse=True)
def _quick_app_searches(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> None:
    """Quick searches. No reader (tesseract) for the app tests that do not ask for it with the
    ``reader`` fixture: it adds seconds to every search of two word pictures (the letters most
    of these tests upload), and what it says is tested where it is asked for.
    ``$ILLUKNIT_READER`` names a program that is not there. And searches made for hands give the
    constraint model 2 s, not 20 (``$ILLUKNIT_HAND_MODEL_SECONDS``)."""
    if "reader" not in request.fixturenames:
        monkeypatch.setenv("ILLUKNIT_READER", "tesseract-not-here")
    # searches made for hands solve the constraint model for 20 s by default: 2 s here
    monkeypatch.setenv("ILLUKNIT_HAND_MODEL_SECONDS", "2")


@pytest.fixture(scope="session")
def serve_app() -> Callable[[Any], contextlib.AbstractContextManager[int]]:
    """``with serve_app(app) as port:`` -- the app on uvicorn in a background thread, on a free
    loopback port, stopped on leaving the block."""
    return _serve


# -- the JSON API (tests/app/routers/) -----------------------------------------------------------

DARK = (20, 20, 20)
LIGHT = (245, 240, 230)


def _png(rgb: Any) -> bytes:
    import io

    import numpy as np
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(np.asarray(rgb, dtype=np.uint8)).save(buf, format="PNG")
    return buf.getvalue()


def _two_tone(mask: Any) -> bytes:
    import numpy as np

    return _png(np.where(mask[..., None], np.array(DARK), np.array(LIGHT)))


def _box_picture(h: int = 24, w: int = 36, *, top: int = 6, left: int = 8) -> bytes:
    import numpy as np

    m = np.zeros((h, w), bool)
    m[top : top + h // 2, left : left + w // 2] = True
    return _two_tone(m)


def _bands(h: int, w: int, cut: int) -> bytes:
    """Rows above ``cut`` dark, below light: one colour per row (knittable one course at a time)."""
    import numpy as np

    m = np.zeros((h, w), bool)
    m[:cut] = True
    return _two_tone(m)


def _three_tone(h: int = 24, w: int = 36) -> bytes:
    """Dark, middle and light bands: a 3-colour picture."""
    import numpy as np

    rgb = np.zeros((h, w, 3), np.uint8)
    rgb[: h // 3] = DARK
    rgb[h // 3 : 2 * h // 3] = (150, 110, 60)
    rgb[2 * h // 3 :] = LIGHT
    return _png(rgb)


def _word(text: str, grey: slice | None = None) -> bytes:
    """A 72 x 48 two-colour picture of a word: at 24 units wide its outlines are ragged, so the
    library suggests edits of it. ``grey``: rows whose background is a third, mid-grey colour."""
    import numpy as np

    from illuknit.pictures.drawings import draw_text

    mask = draw_text(text, shape=(48, 72))
    rgb = np.where(mask[..., None], 24, 246).astype(np.uint8).repeat(3, axis=2)
    if grey is not None:
        rgb[grey][~mask[grey]] = 140
    return _png(rgb)


def _new_session(client: Any) -> str:
    r = client.post("/api/sessions")
    assert r.status_code == 201
    return str(r.json()["id"])


def _upload(
    client: Any, sid: str, slot: str, data: bytes, name: str = "pic.png", mime: str = "image/png"
) -> Any:
    return client.put(f"/api/sessions/{sid}/images/{slot}", files={"file": (name, data, mime)})


def _error_of(r: Any) -> dict[str, Any]:
    body = r.json()
    assert set(body) == {"error"}, body
    assert body["error"]["message"], body
    return dict(body["error"])


def _wait_job(client: Any, sid: str, jid: str, timeout: float = 120) -> dict[str, Any]:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        job = client.get(f"/api/sessions/{sid}/jobs/{jid}").json()
        if job["status"] not in ("queued", "running"):
            return dict(job)
        time.sleep(0.05)
    raise AssertionError(f"job {jid} did not end within {timeout} s")


def _run_job(client: Any, sid: str, kind: str, timeout: float = 120) -> dict[str, Any]:
    r = client.post(f"/api/sessions/{sid}/jobs", json={"kind": kind})
    assert r.status_code == 202, r.text
    return _wait_job(client, sid, r.json()["id"], timeout)


def _evict(store: Any, sid: str) -> None:
    """Close session ``sid`` as the memory bound would: with no room at all, a new session
    pushes it out (the new one stays open)."""
    # the bound never closes a session a request is working on (the page's requests after an
    # upload may still be in flight): wait until none is
    deadline = time.monotonic() + 30
    while store._sessions[sid].pins:
        assert time.monotonic() < deadline, f"a request kept session {sid} busy for 30 s"
        time.sleep(0.02)
    limit, store.max_bytes = store.max_bytes, 0
    try:
        other = store.create()
        assert sid in store.trim(keep=other.id)
    finally:
        store.max_bytes = limit


@pytest.fixture(scope="session")
def pictures() -> SimpleNamespace:
    """Small test pictures as PNG bytes: ``png(rgb)``, ``two_tone(mask)``, ``box_picture()``,
    ``bands(h, w, cut)``, ``three_tone()``, ``word(text, grey)`` (a word whose outlines are ragged
    at 24 units), and the ``DARK`` / ``LIGHT`` colours."""
    return SimpleNamespace(
        DARK=DARK,
        LIGHT=LIGHT,
        png=_png,
        two_tone=_two_tone,
        box_picture=_box_picture,
        bands=_bands,
        three_tone=_three_tone,
        word=_word,
    )


@pytest.fixture(scope="session")
def api() -> SimpleNamespace:
    """Calls of the JSON API: ``new_session(client)``, ``upload(client, sid, slot, data)``,
    ``run_job(client, sid, kind)`` (starts a job and waits for its end), ``wait_job(client, sid,
    jid)``, ``error_of(response)`` and ``evict(store, sid)`` (closes a session as the memory bound
    would)."""
    return SimpleNamespace(
        new_session=_new_session,
        upload=_upload,
        error_of=_error_of,
        run_job=_run_job,
        wait_job=_wait_job,
        evict=_evict,
    )


@pytest.fixture(scope="module")
def app() -> Any:
    """The app with a small upload limit, knitting in-process."""
    from illuknit.app import create_app
    from illuknit.app.server import AppConfig

    return create_app(AppConfig(max_upload_bytes=200_000, isolate_knit=False))


@pytest.fixture(scope="module")
def client(app: Any) -> Iterator[Any]:
    from fastapi.testclient import TestClient

    with TestClient(app) as c:
        yield c


@pytest.fixture()
def double(client: Any) -> str:
    """A session with two equal-size pictures, 2 colours, candidates computed."""
    sid = _new_session(client)
    assert _upload(client, sid, "a", _box_picture()).status_code == 200
    assert _upload(client, sid, "b", _box_picture(top=2, left=2)).status_code == 200
    r = client.put(f"/api/sessions/{sid}/settings", json={"mode": "double", "width_units": 18})
    assert r.status_code == 200
    job = _run_job(client, sid, "candidates")
    assert job["status"] == "done", job
    return sid


# -- a real server process (tests/app/test_persistence.py, the browser's restart test) -----------


class AppProcess:
    """``illuknit app`` run as its own process on a data folder, stopped and started again on
    the same port (so a browser tab keeps its origin and its ``sessionStorage``)."""

    def __init__(self, data_dir: Any, *extra: str) -> None:
        self.data_dir = data_dir
        self.extra = extra
        self.port = 0
        self.proc: Any = None

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    def start(self) -> AppProcess:
        import os
        import re
        import subprocess
        import sys

        import httpx

        self.proc = subprocess.Popen(
            [
                *(sys.executable, "-m", "illuknit", "app", "--port", str(self.port)),
                *("--data-dir", str(self.data_dir), *self.extra),
            ],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env=dict(os.environ),
        )
        line = self.proc.stdout.readline()
        found = re.search(r"127\.0\.0\.1:(\d+)/", line)
        assert found, f"the app did not start: {line!r} {self.proc.stderr.read()[-2000:]!r}"
        self.port = int(found.group(1))
        deadline = time.monotonic() + 30
        while True:
            try:
                httpx.get(f"{self.url}/api/info", timeout=5).raise_for_status()
                return self
            except httpx.HTTPError:
                assert time.monotonic() < deadline, "the app did not answer"
                time.sleep(0.1)

    def stop(self, how: str = "interrupt") -> None:
        """``interrupt`` (Ctrl-C, waits for a clean stop) or ``kill`` (kill -9)."""
        import signal

        if self.proc is None:
            return
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT if how == "interrupt" else signal.SIGKILL)
        self.proc.wait(30)
        self.proc.stdout.close()
        self.proc.stderr.close()
        self.proc = None

    def children(self) -> list[int]:
        """Pids of the processes the server started (its knit worker)."""
        import os

        pid = self.proc.pid
        out = []
        for entry in os.listdir("/proc"):
            if entry.isdigit():
                try:
                    with open(f"/proc/{entry}/stat") as f:
                        stat = f.read()
                except OSError:
                    continue
                if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                    out.append(int(entry))
        return out


@pytest.fixture()
def app_process(tmp_path: Any) -> Iterator[Callable[..., AppProcess]]:
    """``app_process(*options)``: a started ``illuknit app`` process on a fresh data folder
    (``.start()``, ``.stop("interrupt" or "kill")``, ``.url``); stopped after the test."""
    made: list[AppProcess] = []

    def make(*extra: str) -> AppProcess:
        p = AppProcess(tmp_path / "data", *extra)
        made.append(p)
        return p.start()

    yield make
    for p in made:
        p.stop("kill")


@pytest.fixture
def search_keywords(monkeypatch: pytest.MonkeyPatch) -> Callable[..., dict[str, Any]]:
    """Start the app's candidate search on a tiny quantised pair with ``**settings`` and return
    the keywords it called the tile stage (``design_tiles``) with; the search stops there."""
    import numpy as np

    import illuknit.pipeline.stages as stages
    from illuknit.app.candidates import make_candidates
    from illuknit.app.inputs import Prepared
    from illuknit.core.pattern import parse_yarns
    from illuknit.pictures.images import QuantisedImage

    class _Searched(Exception):
        pass

    def run(**settings: Any) -> dict[str, Any]:
        seen: dict[str, Any] = {}

        def fake_design_tiles(*args: Any, **kw: Any) -> None:
            seen.update(kw)
            raise _Searched

        monkeypatch.setattr(stages, "design_tiles", fake_design_tiles)
        yarns = parse_yarns("#1b1b1b,#f4f0e8")
        pal = np.array([y.rgb for y in yarns], dtype=np.uint8)
        q = QuantisedImage(np.eye(4, dtype=int), yarns, pal)
        with pytest.raises(_Searched):
            make_candidates(
                Prepared("double", yarns, {"a": q, "b": q}),
                count=1,
                progress=lambda f, m: None,
                **settings,
            )
        return seen

    return run
