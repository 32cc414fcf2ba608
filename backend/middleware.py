"""Request-level middleware: refuse bodies over the size limit, report server time, gzip the
event stream (and the base of every HTTP middleware of the app, ``security.SecurityHeaders``
too)."""

from __future__ import annotations

import time
import zlib
from abc import ABC, abstractmethod
from typing import Any

from starlette.datastructures import MutableHeaders
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from backend import timing
from backend.api.errors import error_response
from backend.errors import ErrorCode

# An event stream's compressor: gzip (16 +) with an 8 kB window (2 ** 13), and hash tables
# to match (memory level 6): about 64 kB for as long as the stream is open.
GZIP_WINDOW = 16 + 13
GZIP_MEMORY_LEVEL = 6


class HttpMiddleware(ABC):
    """Pure-ASGI middleware for HTTP requests: every other scope (lifespan, websocket)
    passes through untouched; a subclass says what it does to a request in :meth:`http`."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        await self.http(scope, receive, send)

    @abstractmethod
    async def http(self, scope: Scope, receive: Receive, send: Send) -> None:
        """Handle one HTTP request, calling ``self.app`` to have it answered."""


class BodySizeLimit(HttpMiddleware):
    """ASGI middleware: 413 for a declared Content-Length over ``max_bytes``. A body that
    turns out longer while streaming gets the same 413, sent from here; the app is handed
    an end of body and whatever it answers is dropped.

    Not FastAPI's own ``max_body_size``: measured with it, a photo upload over the limit
    is answered by Starlette's middleware as a plain-text "Content Too Large", outside the
    app's error handlers, where every refusal must be the one JSON shape
    (tests/backend/test_bad_input.py)."""

    def __init__(self, app: ASGIApp, max_bytes: int) -> None:
        super().__init__(app)
        self.max_bytes = max_bytes

    async def http(self, scope: Scope, receive: Receive, send: Send) -> None:
        refusal = error_response(
            ErrorCode.BODY_TOO_LARGE,
            f"The request is larger than {self.max_bytes // 1_000_000} MB.",
        )
        declared = dict(scope["headers"]).get(b"content-length")
        if declared is not None and (not declared.isdigit() or int(declared) > self.max_bytes):
            await refusal(scope, receive, send)
            return
        seen = 0
        refused = False

        async def limited() -> Message:
            nonlocal seen, refused
            message = await receive()
            if message["type"] == "http.request" and not refused:
                seen += len(message.get("body", b""))
                if seen > self.max_bytes:
                    refused = True
                    await refusal(scope, receive, send)
                    return {"type": "http.request", "body": b"", "more_body": False}
            return message

        async def unless_refused(message: Message) -> None:
            if not refused:
                await send(message)

        await self.app(scope, limited, unless_refused)


class ServerTiming(HttpMiddleware):
    """ASGI middleware: ``Server-Timing: app;dur=<ms>, db;dur=<ms>`` on every response.
    ``app``: from the request's arrival to the response's start (body upload included);
    ``db``: the part of it spent in database statements (:mod:`backend.timing`); the rest
    is the app's own work and its waits (for a worker thread, the GIL, a connection).
    Benchmarks read it to separate the server's time from the network's."""

    async def http(self, scope: Scope, receive: Receive, send: Send) -> None:
        started = time.perf_counter()
        with timing.tallying() as tally:

            async def timed(message: Message) -> None:
                if message["type"] == "http.response.start":
                    elapsed = (time.perf_counter() - started) * 1000
                    database = tally.get(timing.DATABASE, 0.0) * 1000
                    value = f"app;dur={elapsed:.2f}, {timing.DATABASE};dur={database:.2f}"
                    headers = [*message.get("headers", []), (b"server-timing", value.encode())]
                    message = {**message, "headers": headers}
                await send(message)

            await self.app(scope, receive, timed)


class EventStreamGzip(HttpMiddleware):
    """ASGI middleware: an event stream (``text/event-stream``) gzipped for a phone that
    accepts gzip, each of the app's writes flushed as it comes (``Z_SYNC_FLUSH``), so an
    event is readable on arrival as before, and its first bytes (``retry``) leave at once.

    Starlette's ``GZipMiddleware`` leaves event streams alone: it would hold an event back
    until its buffer fills. One compressor for the whole stream finds each event's keys and
    most of its numbers in the events before: on a venue's link an answer event of 3.6 kB
    goes as 0.5 kB (make bench-network). Its window is 8 kB (an answer event fits with
    room), not zlib's 32 kB: a compressor's memory, ~64 kB instead of ~256 kB, lives as
    long as its stream."""

    def __init__(self, app: ASGIApp, level: int = 6) -> None:
        super().__init__(app)
        self.level = level

    async def http(self, scope: Scope, receive: Receive, send: Send) -> None:
        if b"gzip" not in dict(scope["headers"]).get(b"accept-encoding", b""):
            await self.app(scope, receive, send)
            return
        compressor: Any = None  # zlib's compressor type is not public

        async def compressed(message: Message) -> None:
            nonlocal compressor
            if message["type"] == "http.response.start":
                headers = MutableHeaders(raw=list(message.get("headers", [])))
                stream = headers.get("content-type", "").startswith("text/event-stream")
                if stream and "content-encoding" not in headers:
                    compressor = zlib.compressobj(
                        self.level, zlib.DEFLATED, GZIP_WINDOW, GZIP_MEMORY_LEVEL
                    )
                    headers["content-encoding"] = "gzip"
                    headers.add_vary_header("Accept-Encoding")
                    del headers["content-length"]
                    message = {**message, "headers": headers.raw}
            elif message["type"] == "http.response.body" and compressor is not None:
                more = message.get("more_body", False)
                body = compressor.compress(message.get("body", b""))
                body += compressor.flush(zlib.Z_SYNC_FLUSH if more else zlib.Z_FINISH)
                message = {**message, "body": body}
            await send(message)

        await self.app(scope, receive, compressed)
