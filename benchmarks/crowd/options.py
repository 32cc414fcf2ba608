"""What one run was asked to do: the command's options (``benchmarks/load.py``)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Setup:
    """The options of one run, checked (``benchmarks/load.py --help`` says what each does)."""

    argv: list[str]  # as given: the report quotes the command
    concurrency: int
    duration: float
    budget: int | None
    ramp: float
    idle_seconds: float
    quiet_sessions: int
    speed: float
    workers: int
    database_kind: str
    event_poll_seconds: float | None  # BUDDY_EVENT_POLL_SECONDS for the server; None: default
    seed: int
