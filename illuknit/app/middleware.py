"""ASGI middleware of the app: limits checked before a request reaches a route."""

from __future__ import annotations

import json
from collections.abc import Awaitable, Callable, MutableMapping
from typing import Any

from illuknit.app.handlers import error_body
from illuknit.app.inputs import too_large_message

__all__ = ["PAGE_POLICY", "SameOriginGuard", "SecurityHeaders", "UploadLimit"]

Scope = MutableMapping[str, Any]
Message = MutableMapping[str, Any]
Receive = Callable[[], Awaitable[Message]]
Send = Callable[[Message], Awaitable[None]]


class UploadLimit:
    """ASGI middleware: refuse image uploads over the size limit before the app reads them.

    ``limit`` is the server's one upload limit (``AppConfig.max_upload_bytes``), on the file. A
    request carries the file inside multipart framing, so a request is refused here when it is
    over the limit plus room for the framing: by its declared ``Content-Length``, or a chunked
    body as soon as it passes it. A file over the limit in a request within it is refused by the
    upload route, with the same 413 and the same message (:func:`~illuknit.app.inputs.
    too_large_message`), never a dropped connection.

    The 413 must reach the client *before* the connection closes. A server that answers and
    closes while the client is still sending resets the connection, and the client may lose the
    answer (httpx: "peer closed connection without sending complete message body"; curl: "Send
    failure: Connection reset by peer"). So the 413 is sent at once, from the headers (a client
    that waits for an answer before sending, as with ``Expect: 100-continue``, gets it), and the
    connection is *not* closed: the server reads the rest of the body and throws it away (uvicorn
    discards the body of a request that has been answered; nothing is kept, memory stays flat),
    then the connection serves the next request. Only a client that said ``Expect:
    100-continue``, and so sends no body after a refusal, is answered with ``Connection: close``.
    """

    def __init__(self, app: Any, *, limit: int) -> None:
        self.app = app
        # multipart framing adds a few hundred bytes; allow some slack over the file limit
        self.limit = limit + 64 * 1024
        self.file_limit = limit

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        path = scope.get("path", "")
        if (
            scope["type"] != "http"
            or scope.get("method") not in ("PUT", "POST")
            or "/images/" not in path
        ):
            await self.app(scope, receive, send)
            return
        slot = path.rstrip("/").rsplit("/", 1)[-1]
        field = f"image_{slot}" if slot in ("a", "b") else "image_a"
        headers = dict(scope.get("headers") or [])
        declared = headers.get(b"content-length")
        waits = headers.get(b"expect", b"").lower() == b"100-continue"
        if declared is not None and declared.isdigit() and int(declared) > self.limit:
            await self._refuse(send, field, close=waits)
            return
        chunks: list[bytes] = []
        total = 0
        more = True
        while more:
            message = await receive()
            if message["type"] == "http.disconnect":
                return
            body = message.get("body", b"")
            total += len(body)
            more = message.get("more_body", False)
            if total > self.limit:
                await self._refuse(send, field, close=False)
                return
            chunks.append(body)
        replay = [{"type": "http.request", "body": b"".join(chunks), "more_body": False}]

        async def replay_receive() -> Message:
            if replay:
                return replay.pop()
            return await receive()

        await self.app(scope, replay_receive, send)

    async def _refuse(self, send: Send, field: str, *, close: bool) -> None:
        body = json.dumps(
            error_body(too_large_message(self.file_limit), field, "too_large")
        ).encode()
        headers = [
            (b"content-type", b"application/json"),
            (b"content-length", str(len(body)).encode()),
        ]
        if close:
            headers.append((b"connection", b"close"))
        await send({"type": "http.response.start", "status": 413, "headers": headers})
        await send({"type": "http.response.body", "body": body})


#: Request methods that change state; only these need to come from the app's own page.
STATE_CHANGING = frozenset({"POST", "PUT", "PATCH", "DELETE"})
#: Names of the loopback interface a browser may use for a server bound to it.
LOOPBACK_NAMES = ("127.0.0.1", "localhost", "[::1]")


def _host_name(host: str) -> str:
    """A host as it appears in a Host header (IPv6 addresses in brackets)."""
    return f"[{host}]" if ":" in host and not host.startswith("[") else host


class SameOriginGuard:
    """ASGI middleware: the local app answers only its own page and its own address.

    * **Host** (DNS rebinding): a web page can point a domain of its own at 127.0.0.1 and then
      talk to the app as if it were its own site; the browser then sends that domain as ``Host``.
      Every request must name the address the server is bound to (the socket's own address and
      port; for a loopback address also ``localhost``), or one of ``allowed_hosts``.
    * **Origin** (cross-site requests): any page the designer visits can send a ``POST`` to
      127.0.0.1. A state-changing request (POST, PUT, PATCH, DELETE) whose ``Sec-Fetch-Site``
      is not ``same-origin`` (or ``none``: typed by the user), or whose ``Origin`` is not this
      server's, is refused with a 403. Scripts that send neither header (curl, httpx) are not
      browsers acting for another site and pass.
    """

    def __init__(self, app: Any, *, allowed_hosts: tuple[str, ...] = ()) -> None:
        self.app = app
        self.allowed_hosts = tuple(h.lower() for h in allowed_hosts)

    def _hosts(self, scope: Scope) -> tuple[str, set[str]]:
        """The server's own address and every Host value that names it."""
        server = scope.get("server")
        if not server:  # no socket (an in-process call): nothing to rebind
            return "", set()
        host, port = str(server[0]), server[1]
        names = {_host_name(host)}
        if host in ("127.0.0.1", "::1", "localhost") or host.startswith("127."):
            names.update(LOOPBACK_NAMES)
        names.update(self.allowed_hosts)
        out = {f"{n}:{port}" for n in names if port is not None}
        if port in (80, None) and scope.get("scheme", "http") == "http":
            out.update(names)
        if port == 443 and scope.get("scheme") == "https":
            out.update(names)
        return f"{_host_name(host)}:{port}", out

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope["headers"]}
        host = headers.get("host", "").strip().lower()
        own_address, hosts = self._hosts(scope)
        if hosts and host not in hosts:
            await _refuse(
                send,
                400,
                f"this app answers only at {own_address}, not at {host or 'an unnamed host'}"
                " (a request through another name is refused, so that no web site can reach the "
                "app through a domain of its own)",
                "bad_host",
            )
            return
        if scope.get("method") in STATE_CHANGING:
            site = headers.get("sec-fetch-site")
            origin = headers.get("origin")
            own = f"{scope.get('scheme', 'http')}://{host}"
            if (site is not None and site not in ("same-origin", "none")) or (
                origin is not None and origin.lower() != own
            ):
                await _refuse(
                    send,
                    403,
                    f"changes are accepted only from the app's own page ({own}); this request "
                    f"came from {origin or 'another site'} and was refused",
                    "cross_origin",
                )
                return
        await self.app(scope, receive, send)


async def _refuse(send: Send, status: int, message: str, code: str) -> None:
    body = json.dumps(error_body(message, None, code)).encode()
    await send(
        {
            "type": "http.response.start",
            "status": status,
            "headers": [
                (b"content-type", b"application/json"),
                (b"content-length", str(len(body)).encode()),
            ],
        }
    )
    await send({"type": "http.response.body", "body": body})


#: The Content-Security-Policy of every answer: the page's own scripts, styles and pictures
#: only (no inline script or style, nothing from another site), and never inside another
#: site's frame (a frame could trick the designer into clicking the app's buttons).
PAGE_POLICY = (
    "default-src 'self'; script-src 'self'; style-src 'self'; img-src 'self' data: blob:; "
    "connect-src 'self'; object-src 'none'; base-uri 'none'; form-action 'self'; "
    "frame-ancestors 'none'"
)

#: Headers every answer carries (downloads and refusals included).
SECURITY_HEADERS = (
    (b"x-content-type-options", b"nosniff"),
    (b"x-frame-options", b"DENY"),
    (b"referrer-policy", b"no-referrer"),
    (b"cross-origin-opener-policy", b"same-origin"),
)


class SecurityHeaders:
    """ASGI middleware: every answer says how a browser may use it.

    ``Content-Security-Policy`` (:data:`PAGE_POLICY`, unless the answer sets its own, as the
    ``/docs`` page does for its inline style sheet), ``X-Content-Type-Options: nosniff`` (a
    download is never run as something else), ``X-Frame-Options: DENY`` (for browsers older
    than ``frame-ancestors``), ``Referrer-Policy: no-referrer`` (a session id in the address
    never leaves the app in a Referer header).
    """

    def __init__(self, app: Any) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return

        async def send_with_headers(message: Message) -> None:
            if message["type"] == "http.response.start":
                headers = list(message.get("headers") or [])
                names = {k.lower() for k, _ in headers}
                headers += [(k, v) for k, v in SECURITY_HEADERS if k not in names]
                if b"content-security-policy" not in names:
                    headers.append((b"content-security-policy", PAGE_POLICY.encode()))
                message["headers"] = headers
            await send(message)

        await self.app(scope, receive, send_with_headers)
