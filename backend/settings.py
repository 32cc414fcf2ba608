"""Every setting of the service, from the environment (prefix ``BUDDY_``), in one class.

The defaults run the app on one machine with nothing else to start: SQLite under ``./var``.
"""

from __future__ import annotations

from functools import lru_cache

from pydantic import Field
from pydantic_settings import BaseSettings, SettingsConfigDict

from backend import limits


class Settings(BaseSettings):
    """Documented in the README's settings table; each field's description is the reference."""

    model_config = SettingsConfigDict(env_prefix="BUDDY_", env_file=".env", extra="ignore")

    host: str = Field(
        "0.0.0.0", description="Address make run listens on (all: phones on the network reach it)."
    )
    port: int = Field(8000, gt=0, lt=65536, description="Port make run listens on.")
    workers: int = Field(
        1,
        ge=1,
        le=64,
        description="Server processes make run starts: one per core serves the most phones "
        "(each process runs Python on one core).",
    )
    frontend_dir: str = Field(
        "frontend/dist", description="The built phone app, served at / (make run builds it)."
    )
    database_url: str = Field(
        "sqlite:///var/buddy.db",
        description="SQLAlchemy URL: SQLite (WAL mode) for the processes of one machine, "
        "PostgreSQL (`postgresql+psycopg://user:password@host:5432/buddy`) for replicas on "
        "several.",
    )
    public_url: str | None = Field(
        None,
        description="Base URL of the app as phones reach it, for join links "
        "(default: the URL of the request that created the session).",
    )
    session_ttl_seconds: int = Field(
        7200, gt=0, description="A session is deleted this long after it starts."
    )
    join_code_ttl_seconds: int = Field(600, gt=0, description="How long a join code stays valid.")
    sweep_interval_seconds: float = Field(
        60.0, gt=0, description="How often expired sessions are deleted."
    )
    join_attempt_window_seconds: int = Field(
        600,
        gt=0,
        description="The window in which failed joins (a wrong, used or expired code) are "
        "counted, sliding.",
    )
    join_failures_per_client: int = Field(
        60,
        gt=0,
        description="Failed joins one client address (an IPv4 address, an IPv6 /64) may make "
        "per window; then it gets 429 `too_many_attempts` until the oldest leaves the window. "
        "Successful joins are not counted.",
    )
    join_failures_per_code: int = Field(
        5,
        gt=0,
        description="Wrong codes naming a search's number (the first four digits) after "
        "which its join code is renewed: a new number and secret, shown on the starter's phone.",
    )
    join_failures_overall: int = Field(
        600,
        gt=0,
        description="Failed joins of all clients together per window above which guessing "
        "is taken to be under way: then an address that has failed in the window waits until "
        "its failures leave it; an address that has not may still try.",
    )
    erase_interval_seconds: float = Field(
        600.0,
        ge=0,
        description="PostgreSQL: how often at most the bytes of deleted sessions are erased "
        "from the database's files (VACUUM FULL, by one replica's sweeper for all; it locks "
        "each table while it copies it, longer the more photos are kept: "
        "benchmarks/erase.py measures it). SQLite "
        "erases them at once.",
    )
    max_body_bytes: int = Field(30_000_000, gt=0, description="Largest request body accepted.")
    max_photo_pixels: int = Field(
        50_000_000,
        gt=0,
        description="Largest photo (width x height, read from its header before decoding).",
    )
    stored_photo_side: int = Field(
        limits.STORED_PHOTO_SIDE,
        gt=0,
        description="Photos are stored downscaled to at most this many px on the long side.",
    )
    max_landmarks: int = Field(
        limits.MAX_LANDMARKS, gt=0, description="Most landmarks one participant may tap."
    )
    tap_sigma: float = Field(
        3.0,
        gt=0,
        description="Standard deviation of a finger's tap on a stored photo, px: the noise "
        "the answer's uncertainty is computed from.",
    )
    online_seconds: float = Field(
        45.0,
        gt=0,
        description="A participant counts as online this long after its event stream was "
        "last alive.",
    )
    keepalive_seconds: float = Field(
        15.0, gt=0, description="Interval of keepalive pings on the event stream."
    )
    event_poll_seconds: float = Field(
        10.0,
        gt=0,
        description="How often an event stream re-reads the event table, in case a wake-up "
        "was lost (changes wake the streams at once, in every process: on PostgreSQL by "
        "notifications, on SQLite by each process's watcher, 4 times a second).",
    )


@lru_cache
def get_settings() -> Settings:
    """The settings of this process, read once from the environment."""
    return Settings()
