"""The phone app: the built frontend (``frontend/dist``) served at ``/``.

Static files under ``/assets``; every other GET that is not the API answers ``index.html``,
so the app's own routes (``/join/<code>``, the session screen) load it after a reload.

The page, the service worker (``sw.js``) and the web app manifest are sent with
``Cache-Control: no-cache``: the browser asks each time whether they changed, so a new build
is seen at the next visit (the worker then moves the page to it: frontend/src/shell/).
Everything under ``/assets`` is named by its content's hash and never changes.
"""

from __future__ import annotations

from pathlib import Path

from fastapi import FastAPI
from fastapi.responses import FileResponse, HTMLResponse
from fastapi.staticfiles import StaticFiles

from backend.errors import ErrorCode, RefusedError

# Paths the app must never swallow: an unknown API path is a 404 in the one error shape.
# (The service worker's navigation fallback denies the same ones: frontend/vite.config.ts.)
_NOT_THE_APP = ("api/", "docs", "openapi.json", "healthz")
# Files at the top of dist/ whose name stays while their content changes, with their media
# type (Python's table has no .webmanifest; a worker script must be JavaScript).
_NEVER_STALE = {
    "sw.js": "text/javascript",
    "manifest.webmanifest": "application/manifest+json",
}
_NO_CACHE = {"Cache-Control": "no-cache"}

_NOT_BUILT = """<!doctype html><meta charset="utf-8"><title>Buddy Search</title>
<p>The phone app is not built yet: run <code>make run</code> (it builds it), or
<code>cd frontend && npm ci && npm run build</code>. The API is at <a href="/docs">/docs</a>.</p>
"""


def serve_app(app: FastAPI, folder: Path) -> None:
    """Serve the built app in ``folder`` (its ``index.html`` and ``assets/``)."""
    index = folder / "index.html"
    assets = folder / "assets"
    if assets.is_dir():
        app.mount("/assets", StaticFiles(directory=assets), name="assets")

    @app.get("/{path:path}", include_in_schema=False, response_model=None)
    def page(path: str) -> FileResponse | HTMLResponse:
        if path.startswith(_NOT_THE_APP):
            raise RefusedError(ErrorCode.NOT_FOUND, "There is nothing at this address.")
        static = (folder / path).resolve()
        if path and static.is_file() and static.is_relative_to(folder.resolve()):
            if path in _NEVER_STALE:
                return FileResponse(static, media_type=_NEVER_STALE[path], headers=_NO_CACHE)
            return FileResponse(static)  # the icons: files at the top of dist/
        if index.is_file():
            return FileResponse(index, headers=_NO_CACHE)
        return HTMLResponse(_NOT_BUILT)
