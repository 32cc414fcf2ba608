"""What every response says to the browser about security, and the logging that could leak.

:class:`SecurityHeaders` is pure-ASGI middleware around the whole app (errors included):

- ``Content-Security-Policy``: the app loads its own script and stylesheet and nothing else;
  photos are shown from the API, from ``blob:`` URLs (the phone decodes a picked photo before
  sending it) and the icon from a ``data:`` URL; it talks to its own origin only (``fetch``,
  ``EventSource``) and installs its own service worker and manifest. No inline script or
  ``<style>`` (Preact sets styles through the CSSOM, which CSP allows). A route may send a
  policy of its own (``/docs``: the app's, with Swagger UI's one inline script allowed by
  its hash).
- ``Referrer-Policy: no-referrer``: pictures and event streams carry ``?token=``; no
  address of this app is ever sent to another site.
- ``X-Frame-Options``/``frame-ancestors``, ``nosniff``, ``Cross-Origin-Opener-Policy`` and
  ``-Resource-Policy``, a ``Permissions-Policy`` that allows the camera and no location or
  microphone.
- ``Cache-Control: no-store`` on API answers that do not say otherwise: states hold join
  codes, answers hold tokens.
- ``Strict-Transport-Security`` when the request came over HTTPS (directly, or through a
  trusted proxy's ``X-Forwarded-Proto``, which uvicorn's ``--proxy-headers`` applies).

No CORS headers, ever: the API is for the app on its own origin, and a browser on any other
origin gets no permission to read an answer.
"""

from __future__ import annotations

import base64
import hashlib
import logging
import re

from starlette.types import Message, Receive, Scope, Send

from backend.middleware import HttpMiddleware

APP_POLICY = "; ".join(
    (
        "default-src 'self'",
        "img-src 'self' blob: data:",
        "connect-src 'self'",
        "script-src 'self'",
        "style-src 'self'",
        # The app shell's service worker and the web app manifest (default-src allows
        # them too; said outright so that a narrower default-src cannot drop them).
        "worker-src 'self'",
        "manifest-src 'self'",
        "object-src 'none'",
        "base-uri 'none'",
        "frame-ancestors 'none'",
        "form-action 'self'",
    )
)

HEADERS: dict[str, str] = {
    "Content-Security-Policy": APP_POLICY,
    "X-Content-Type-Options": "nosniff",
    "Referrer-Policy": "no-referrer",
    "X-Frame-Options": "DENY",
    "Permissions-Policy": "camera=(self), geolocation=(), microphone=()",
    "Cross-Origin-Opener-Policy": "same-origin",
    "Cross-Origin-Resource-Policy": "same-origin",
}
HSTS = "max-age=31536000"

# Pillow logs the EXIF tags it reads from an upload (camera, time, where GPS data sits) at
# DEBUG, following the root logger: held at WARNING, so that debug logging of the service
# cannot record what it strips from photos. (SQLAlchemy's statements and rows are logged
# only when asked for: its logger starts at WARNING; parameters are hidden even then.)
_CHATTY_LOGGERS = ("PIL",)


def quiet_chatty_loggers() -> None:
    for name in _CHATTY_LOGGERS:
        logging.getLogger(name).setLevel(logging.WARNING)


def inline_script_policy(html: str) -> str:
    """The app's policy, also allowing the inline scripts of ``html`` by their hashes (so
    that no other inline script runs): for Swagger UI's page at ``/docs``, which starts
    from one. Swagger UI 5 needs nothing else (its styles are set through the CSSOM)."""
    hashes = " ".join(
        "'sha256-" + base64.b64encode(hashlib.sha256(script.encode()).digest()).decode() + "'"
        for script in re.findall(r"<script>(.*?)</script>", html, re.S)
    )
    return APP_POLICY.replace("script-src 'self'", f"script-src 'self' {hashes}")


class SecurityHeaders(HttpMiddleware):
    """ASGI middleware: the headers above on every HTTP response (a header the app set
    itself is kept)."""

    async def http(self, scope: Scope, receive: Receive, send: Send) -> None:
        extra = dict(HEADERS)
        if str(scope["path"]).startswith("/api/"):
            extra["Cache-Control"] = "no-store"
        if scope.get("scheme") == "https":
            extra["Strict-Transport-Security"] = HSTS
        added = [(name.lower().encode(), value.encode()) for name, value in extra.items()]

        async def with_headers(message: Message) -> None:
            if message["type"] == "http.response.start":
                headers = list(message.get("headers", []))
                present = {name.lower() for name, _ in headers}
                headers += [(name, value) for name, value in added if name not in present]
                message = {**message, "headers": headers}
            await send(message)

        await self.app(scope, receive, with_headers)
