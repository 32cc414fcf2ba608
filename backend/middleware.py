"""Request-level middleware: refuse bodies over the size limit, report server time (and the
base of every HTTP middleware of the app, ``security.SecurityHeaders`` too)."""

from __future__ import annotations

import time
from abc import ABC, abstractmethod

from starlette.types import ASGIApp, Message, Receive, Scope, Send

from backend import timing
from backend.api.errors import error_response
from backend.errors import ErrorCode


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
