"""The ASGI app: ``backend.main:app`` (``make run`` serves it with uvicorn)."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Any

import fastapi_offline
from fastapi import FastAPI
from fastapi.openapi.docs import get_swagger_ui_html
from fastapi.responses import HTMLResponse
from fastapi.staticfiles import StaticFiles
from starlette.middleware.gzip import GZipMiddleware
from starlette.types import ASGIApp

from backend import __version__, wiring
from backend.api import errors
from backend.api import responses as api_responses
from backend.api.routes import events, health, pairing, photos, sessions, solver, taps
from backend.background import (
    erase_forever,
    keep_online_forever,
    sweep_forever,
    watch_events_forever,
)
from backend.clock import Clock, utc_now
from backend.frontend import serve_app
from backend.middleware import BodySizeLimit, EventStreamGzip, ServerTiming
from backend.security import SecurityHeaders, inline_script_policy, quiet_chatty_loggers
from backend.settings import Settings, get_settings
from backend.storage.database import make_engine

ROOT = Path(__file__).resolve().parents[1]
# How often a process on SQLite looks for other processes' changes: their latency at most.
WATCH_SECONDS = 0.25
# How soon after a deletion its bytes are erased from the database's files (off the request).
ERASE_SECONDS = 2.0
DESCRIPTION = """Find a friend across a venue from two phone photos.

Stateless: `POST /api/solve` and `POST /api/overlay` for scripts.
Sessions: one friend starts a search, the other joins with its code; each uploads a photo and
taps landmarks; the answer is recomputed on every change and drawn on each photo. Every
error is `{"error": {"code": "...", "message": "..."}}`.
"""


def create_app(settings: Settings | None = None, clock: Clock = utc_now) -> FastAPI:
    """The app with its database (migrated at start), event notifier and expiry sweeper."""
    settings = settings or get_settings()
    quiet_chatty_loggers()

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        engine = make_engine(settings.database_url)
        services = wiring.build(engine, settings, clock)
        app.state.services = services
        tasks = [
            asyncio.create_task(
                sweep_forever(services.pairing, services.eraser, settings.sweep_interval_seconds)
            ),
            asyncio.create_task(keep_online_forever(services.streams, settings.online_seconds / 3)),
            asyncio.create_task(erase_forever(services.eraser, ERASE_SECONDS)),
        ]
        # Other processes' changes wake this one's streams too: on PostgreSQL they notify,
        # on SQLite (several worker processes on one file) the watcher looks.
        if listener := services.listener:
            tasks.append(asyncio.create_task(listener.run()))
            await listener.started(timeout=10)  # else /healthz says 503 until it is
        else:
            tasks.append(asyncio.create_task(watch_events_forever(services.streams, WATCH_SECONDS)))
        try:
            yield
        finally:
            for task in tasks:
                task.cancel()
            await asyncio.gather(*tasks, return_exceptions=True)
            engine.dispose()

    app = FastAPI(
        title="Buddy Search",
        version=__version__,
        description=DESCRIPTION,
        lifespan=lifespan,
        docs_url=None,  # served below from local files: nothing is loaded from the internet
        redoc_url=None,
    )
    app.state.settings = settings
    errors.install(app, settings.max_body_bytes)
    # Gzipped when asked: answers by Starlette's middleware (not photos, nor the event
    # stream, whose events it would hold back), the event stream event by event by ours.
    # Behind nginx, nginx compresses answers and asks the replicas for plain ones
    # (deploy/nginx.conf): with gzip in the replicas, their CPU per search under load rose
    # from 347 to 428 ms (make bench-load); event streams it passes on as the replicas
    # gzipped them.
    app.add_middleware(GZipMiddleware, compresslevel=6)
    app.add_middleware(EventStreamGzip)
    app.add_middleware(BodySizeLimit, max_bytes=settings.max_body_bytes)
    app.add_middleware(ServerTiming)
    _secure_every_response(app)
    for module in (solver, pairing, sessions, photos, taps, events, health):
        app.include_router(module.router)
    _serve_docs(app)
    _document_refusals(app)
    frontend = Path(settings.frontend_dir)
    # Last: its catch-all route goes after the API. Relative to the project, not the cwd.
    serve_app(app, frontend if frontend.is_absolute() else ROOT / frontend)
    return app


def _secure_every_response(app: FastAPI) -> None:
    """Security headers on every response, outermost: also on the 500s that Starlette's
    error middleware answers outside ``add_middleware``'s reach."""
    build = app.build_middleware_stack

    def build_middleware_stack() -> ASGIApp:
        return SecurityHeaders(build())

    app.build_middleware_stack = build_middleware_stack  # type: ignore[method-assign]


def _document_refusals(app: FastAPI) -> None:
    """FastAPI documents request errors as {"detail": [...]}; this API answers them in its
    one shape, so the schema says that instead. Also what the event stream's events carry
    (FastAPI documents no data of a stream of ``ServerSentEvent``)."""
    build = app.openapi

    def openapi() -> dict[str, Any]:
        if app.openapi_schema is None:
            schema = build()
            for operations in schema.get("paths", {}).values():
                for operation in operations.values():
                    answers = operation.get("responses", {})
                    if answers.get("422", {}).get("description") == "Validation Error":
                        answers["422"] = api_responses.INVALID_REQUEST
            schema.get("components", {}).get("schemas", {}).pop("HTTPValidationError", None)
            schema.get("components", {}).get("schemas", {}).pop("ValidationError", None)
            events.document_events(schema)
            app.openapi_schema = schema
        return app.openapi_schema

    app.openapi = openapi  # type: ignore[method-assign]


def _serve_docs(app: FastAPI) -> None:
    """Swagger UI at /docs, from the fastapi-offline package's copy (Swagger UI 5, which
    reads OpenAPI 3.1) instead of a CDN."""
    assets = Path(fastapi_offline.__file__).parent / "static"
    app.mount("/docs-assets", StaticFiles(directory=assets), name="docs-assets")

    page = get_swagger_ui_html(
        openapi_url="/openapi.json",
        title="Buddy Search API",
        swagger_js_url="/docs-assets/swagger-ui-bundle.js",
        swagger_css_url="/docs-assets/swagger-ui.css",
        swagger_favicon_url="/docs-assets/favicon.png",
        # Not the default validator badge, an image from validator.swagger.io.
        swagger_ui_parameters={"validatorUrl": None},
    ).body
    # Swagger UI starts from one inline script: its page alone allows it, by its hash.
    policy = inline_script_policy(bytes(page).decode())

    @app.get("/docs", include_in_schema=False)
    def docs() -> HTMLResponse:
        return HTMLResponse(page, headers={"Content-Security-Policy": policy})


app = create_app()
