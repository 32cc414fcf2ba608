"""Where a request's time in the app goes, for its ``Server-Timing`` header.

:class:`backend.middleware.ServerTiming` opens a tally for each request; the storage adds
the time its database statements take (:func:`add`). The tally lives in a context variable:
the worker thread that runs a route runs in a copy of the request's context (anyio's
``to_thread``), which holds the same tally, so what the route's statements add is there
when the response starts. Outside a request (the background sweeper) nothing is tallied.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar

# The one part the storage tallies: statements sent to the database and their answers read.
DATABASE = "db"

_tally: ContextVar[dict[str, float] | None] = ContextVar("server_timing", default=None)


@contextmanager
def tallying() -> Iterator[dict[str, float]]:
    """A fresh tally (seconds by part) for the code in the block and what it calls."""
    tally: dict[str, float] = {}
    token = _tally.set(tally)
    try:
        yield tally
    finally:
        _tally.reset(token)


def add(part: str, seconds: float) -> None:
    """Add ``seconds`` to ``part`` of the current request's tally, if there is one."""
    tally = _tally.get()
    if tally is not None:
        tally[part] = tally.get(part, 0.0) + seconds
