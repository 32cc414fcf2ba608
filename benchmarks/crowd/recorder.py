"""The recorder: what one phase measured, call by call (latency, Server-Timing, errors by
kind), and the run's state sampled every second."""

from __future__ import annotations

from collections import Counter
from contextlib import suppress
from dataclasses import dataclass, field

import httpx2
from report import CpuSnapshot, server_timing_ms

# The calls, as the report names them.
CREATE = "POST /api/sessions"
JOIN = "POST /api/sessions/join"
EVENTS = "GET /events (first byte)"
PHOTO = "PUT /photo"
STORED = "GET /photo/{own role}"
TAPS = "PUT /taps"
STATE = "GET /api/sessions/{id}"
CROP = "GET /landmarks/starter/{n}/crop"
OVERLAY = "GET /overlay/{own role}"
DELETE = "DELETE /api/sessions/{id}"
ENDPOINTS = (CREATE, JOIN, EVENTS, PHOTO, STORED, TAPS, STATE, CROP, OVERLAY, DELETE)


@dataclass
class Calls:
    """One endpoint: client latency and server time (Server-Timing) of each successful call,
    and the failed calls by kind."""

    latency_ms: list[float] = field(default_factory=list)
    server_ms: list[float] = field(default_factory=list)
    errors: Counter[str] = field(default_factory=Counter)


@dataclass(frozen=True)
class Sample:
    """The state of the run at one instant (every ``phases.SAMPLE_SECONDS``)."""

    cpu: CpuSnapshot
    sessions: int
    streams: int
    requests: int


@dataclass
class Recorder:
    """Everything one phase measured."""

    calls: dict[str, Calls] = field(default_factory=lambda: {name: Calls() for name in ENDPOINTS})
    flow_errors: Counter[str] = field(default_factory=Counter)
    events: Counter[str] = field(default_factory=Counter)
    streams_opened: int = 0
    sessions_started: int = 0
    sessions_completed: int = 0
    session_seconds: list[float] = field(default_factory=list)
    finished_at: list[float] = field(default_factory=list)  # monotonic, completed sessions
    state_fetches_per_phone: list[int] = field(default_factory=list)
    sessions_in_flight: int = 0
    streams_open: int = 0
    requests_in_flight: int = 0
    samples: list[Sample] = field(default_factory=list)
    loop_lag_ms: list[float] = field(default_factory=list)

    def ok(self, endpoint: str, latency_ms: float, response: httpx2.Response) -> None:
        calls = self.calls[endpoint]
        calls.latency_ms.append(latency_ms)
        with suppress(KeyError, IndexError, ValueError):
            calls.server_ms.append(server_timing_ms(response))

    def failed(self, endpoint: str, kind: str) -> None:
        self.calls[endpoint].errors[kind] += 1

    def flow(self, kind: str) -> None:
        """Something a phone expected and did not see (an event, a stream that dropped)."""
        self.flow_errors[kind] += 1

    @property
    def http_errors(self) -> int:
        return sum(sum(calls.errors.values()) for calls in self.calls.values())

    @property
    def errors(self) -> int:
        return self.http_errors + sum(self.flow_errors.values())


def error_kind(response: httpx2.Response) -> str:
    """``HTTP 503 busy``: the status and the API's error code, when it sent one."""
    code = ""
    with suppress(ValueError, KeyError, TypeError):
        code = " " + str(response.json()["error"]["code"])
    return f"HTTP {response.status_code}{code}"
