"""Time, in one place: naive UTC datetimes (what SQLite and PostgreSQL columns hold)."""

from __future__ import annotations

from collections.abc import Callable
from datetime import UTC, datetime

Clock = Callable[[], datetime]


def utc_now() -> datetime:
    return datetime.now(UTC).replace(tzinfo=None)


def aware(moment: datetime) -> datetime:
    """For JSON: the same instant marked as UTC."""
    return moment.replace(tzinfo=UTC)
