"""ASGI middleware of the app: limits checked before a request reaches a route."""

from __future__ import annotations

import json
from collections.abc import Awaitable, Callable, MutableMapping
from typing import Any

from illuknit.app.handlers import error_body
from illuknit.pattern import MAX_UNITS

__all__ = ["UploadLimit"]

Scope = MutableMapping[str, Any]
Message = MutableMapping[str, Any]
Receive = Callable[[], Awaitable[Message]]
Send = Callable[[Message], Awaitable[None]]


class UploadLimit:
    """ASGI middleware: refuse image uploads over the size limit before the app reads them.

    A declared ``Content-Length`` over the limit is refused at once; a chunked body is counted as
    it arrives and refused as soon as it passes the limit. Either way the answer is a 413 with the
    usual error body naming the upload control, never a dropped connection.
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
        if declared is not None and declared.isdigit() and int(declared) > self.limit:
            await self._refuse(send, field, int(declared))
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
            if total > self.limit:
                await self._refuse(send, field, total)
                return
            chunks.append(body)
            more = message.get("more_body", False)
        replay = [{"type": "http.request", "body": b"".join(chunks), "more_body": False}]

        async def replay_receive() -> Message:
            if replay:
                return replay.pop()
            return await receive()

        await self.app(scope, replay_receive, send)

    async def _refuse(self, send: Send, field: str, size: int) -> None:
        mb = self.file_limit / 1e6
        body = json.dumps(
            error_body(
                f"the upload is {'over ' if size <= self.limit else ''}{max(size, self.limit) / 1e6:.1f} MB;"
                f" pictures are limited to {mb:.0f} MB. Save a smaller copy (a knitted piece is at most "
                f"{MAX_UNITS} units across, so a few hundred pixels are plenty).",
                field,
                "too_large",
            )
        ).encode()
        await send(
            {
                "type": "http.response.start",
                "status": 413,
                "headers": [
                    (b"content-type", b"application/json"),
                    (b"connection", b"close"),
                    (b"content-length", str(len(body)).encode()),
                ],
            }
        )
        await send({"type": "http.response.body", "body": body})
