"""The app's 500 path: a bug inside a handler is one JSON error, not a traceback, and costs nothing.

An unexpected exception (not an :class:`~illuknit.core.errors.IlluknitError`, not a request
error) raised inside a handler -- while it reads the session, in the middle of changing it, or
while saving it -- is answered with status 500 in the app's one error shape (``{"error":
{"message", "field", "code": "internal"}}``, docs/app.md), with no traceback or source path in
the body; the session is as it was before the request and reads as before, on the same client
(the answer says ``Connection: close``, as the server closes the connection after it); and the
server's log (uvicorn's ``uvicorn.error`` logger, what ``illuknit app`` prints) has the
traceback, so the bug can be found. The app is served by uvicorn, as ``illuknit app`` serves it.
"""

from __future__ import annotations

import logging
from collections.abc import Iterator
from typing import Any

import httpx
import pytest

from illuknit.app import lookups
from illuknit.app.routers import sessions as sessions_router
from illuknit.app.sessions import Session

SECRET = "the-bug-says-this"


class _Records(logging.Handler):
    def __init__(self) -> None:
        super().__init__(logging.DEBUG)
        self.records: list[logging.LogRecord] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.records.append(record)

    def text(self) -> str:
        formatter = logging.Formatter("%(name)s %(levelname)s %(message)s")
        return "\n".join(formatter.format(r) for r in self.records)


@pytest.fixture(scope="module")
def server(app: Any, serve_app: Any) -> Iterator[httpx.Client]:
    with serve_app(app) as port, httpx.Client(base_url=f"http://127.0.0.1:{port}") as client:
        yield client


@pytest.fixture()
def log() -> Iterator[_Records]:
    """What the server logs while the test runs (uvicorn's error logger)."""
    handler = _Records()
    logger = logging.getLogger("uvicorn.error")
    logger.addHandler(handler)
    try:
        yield handler
    finally:
        logger.removeHandler(handler)


def _boom(*args: Any, **kwargs: Any) -> Any:
    raise RuntimeError(SECRET)


def _after(original: Any) -> Any:
    """``original``, then the bug: the session is already half changed when it strikes."""

    def changed_then_boom(*args: Any, **kwargs: Any) -> Any:
        original(*args, **kwargs)
        raise RuntimeError(SECRET)

    return changed_then_boom


#: Where the bug strikes: (object, attribute, replacement given the original).
PLACES = {
    "reading the state": (sessions_router, "state_json", lambda original: _boom),
    "after the settings changed": (Session, "bump", _after),
    "saving the session": (Session, "save", lambda original: _boom),
}


def _assert_internal_error(r: httpx.Response) -> None:
    assert r.status_code == 500, r.text
    assert r.headers["content-type"].startswith("application/json")
    # the server closes the connection after a 500 (to log it): the answer says so
    assert r.headers.get("connection") == "close"
    body = r.json()
    assert set(body) == {"error"} and set(body["error"]) == {"message", "field", "code"}, body
    assert body["error"]["code"] == "internal" and body["error"]["field"] is None
    assert body["error"]["message"].startswith("internal error: RuntimeError")
    for leak in ("Traceback", 'File "', ".py", "line "):
        assert leak not in r.text, f"the body shows {leak!r}: {r.text}"


@pytest.mark.parametrize("place", sorted(PLACES))
def test_a_bug_in_a_handler_is_a_json_500_and_leaves_the_session_as_it_was(
    server, log, monkeypatch, place
):
    sid = server.post("/api/sessions").json()["id"]
    r = server.put(f"/api/sessions/{sid}/settings", json={"width_units": 30})
    assert r.status_code == 200, r.text
    before = server.get(f"/api/sessions/{sid}").json()
    where, name, replace = PLACES[place]
    monkeypatch.setattr(where, name, replace(getattr(where, name)))
    try:
        failed = server.put(f"/api/sessions/{sid}/settings", json={"width_units": 42})
    finally:
        monkeypatch.undo()
    _assert_internal_error(failed)
    after = server.get(f"/api/sessions/{sid}")
    assert after.status_code == 200, after.text
    assert after.json() == before
    assert after.json()["settings"]["width_units"] == 30
    logged = log.text()
    assert "Traceback" in logged and f"RuntimeError: {SECRET}" in logged, logged
    assert any(r.exc_info and r.levelno >= logging.ERROR for r in log.records)
    # the session still takes changes
    again = server.put(f"/api/sessions/{sid}/settings", json={"width_units": 42})
    assert again.status_code == 200 and again.json()["settings"]["width_units"] == 42


def test_a_bug_while_reading_a_session_is_a_json_500_and_the_next_read_works(
    server, log, monkeypatch
):
    sid = server.post("/api/sessions").json()["id"]
    before = server.get(f"/api/sessions/{sid}").json()
    monkeypatch.setattr(lookups, "state_json", _boom)
    monkeypatch.setattr(sessions_router, "state_json", _boom)
    try:
        failed = server.get(f"/api/sessions/{sid}")
    finally:
        monkeypatch.undo()
    _assert_internal_error(failed)
    assert server.get(f"/api/sessions/{sid}").json() == before
    assert f"RuntimeError: {SECRET}" in log.text()
