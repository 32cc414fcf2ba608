"""The tables. Everything of a session hangs off its row and goes with it (ON DELETE CASCADE)."""

from __future__ import annotations

from datetime import datetime

from sqlalchemy import (
    DateTime,
    Float,
    ForeignKey,
    Index,
    Integer,
    LargeBinary,
    String,
    Table,
    Text,
    UniqueConstraint,
)
from sqlalchemy.orm import DeclarativeBase, Mapped, mapped_column


class Base(DeclarativeBase):
    pass


class SessionRow(Base):
    """One search: two friends, their photos and taps, the current answer."""

    __tablename__ = "sessions"

    id: Mapped[str] = mapped_column(String(32), primary_key=True)
    created_at: Mapped[datetime] = mapped_column(DateTime())
    expires_at: Mapped[datetime] = mapped_column(DateTime(), index=True)
    # Single use: cleared when the friend joins. Eight digits: the search's number, then
    # its secret.
    join_code: Mapped[str | None] = mapped_column(String(8), unique=True)
    join_code_expires_at: Mapped[datetime | None] = mapped_column(DateTime())
    # Wrong codes that named this code's search number; at the limit the code is renewed
    # (a new number and secret) and this starts again from 0.
    join_code_failures: Mapped[int] = mapped_column(Integer, default=0, server_default="0")
    # How many times the code was renewed so (the starter's phone says why it changed).
    join_code_renewals: Mapped[int] = mapped_column(Integer, default=0, server_default="0")
    # Bumped by every change a phone should see; the answer records the version it is for.
    version: Mapped[int] = mapped_column(Integer, default=1)
    # JSON: {"answer": what each phone is told, "solution": the solver's own answer,
    # "first": whose photo was photo 1}, or {"error": {"code", "message"}}.
    answer: Mapped[str | None] = mapped_column(Text)
    answer_version: Mapped[int | None] = mapped_column(Integer)


class ParticipantRow(Base):
    """The starter or the joiner: who holds which token, whether online, what they tapped."""

    __tablename__ = "participants"
    __table_args__ = (UniqueConstraint("session_id", "role"),)

    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    session_id: Mapped[str] = mapped_column(
        ForeignKey("sessions.id", ondelete="CASCADE"), index=True
    )
    role: Mapped[str] = mapped_column(String(8))  # starter, joiner
    token_hash: Mapped[str] = mapped_column(String(64), unique=True)
    joined_at: Mapped[datetime] = mapped_column(DateTime())
    last_seen_at: Mapped[datetime | None] = mapped_column(DateTime())
    taps: Mapped[str | None] = mapped_column(Text)  # JSON: backend.taps.schemas.Taps


class PhotoRow(Base):
    """A friend's photo as stored: upright JPEG, downscaled, no metadata; of its EXIF only
    the lens's focal length is kept (what the solver uses), never the rest."""

    __tablename__ = "photos"

    session_id: Mapped[str] = mapped_column(
        ForeignKey("sessions.id", ondelete="CASCADE"), primary_key=True
    )
    role: Mapped[str] = mapped_column(String(8), primary_key=True)
    data: Mapped[bytes] = mapped_column(LargeBinary)
    width: Mapped[int] = mapped_column(Integer)
    height: Mapped[int] = mapped_column(Integer)
    scale: Mapped[float] = mapped_column(Float)
    uploaded_at: Mapped[datetime] = mapped_column(DateTime())
    # The lens, 35 mm equivalent, with its relative uncertainty, and who read it from EXIF
    # (the server from the upload, or the phone before shrinking it); NULL: not told.
    lens_focal_35mm: Mapped[float | None] = mapped_column(Float)
    lens_uncertainty: Mapped[float | None] = mapped_column(Float)
    lens_told_by: Mapped[str | None] = mapped_column(String(5))
    # Which way was down at the shutter, as the phone read it: JSON [x, y, z, sigma_deg] in
    # the stored photo's camera frame (backend.photos.gravity); NULL: not read.
    gravity: Mapped[str | None] = mapped_column(Text)
    # Which way the lens looked at the shutter, as the phone's compass read it: degrees
    # clockwise from north in [0, 360), and its sigma, degrees (backend.photos.heading);
    # NULL: not read.
    heading: Mapped[float | None] = mapped_column(Float)
    heading_sigma_deg: Mapped[float | None] = mapped_column(Float)
    # The session's version that stored this photo: with the session and the role, the name
    # of these bytes (replicas keep photos they read lately by it: backend.photos.kept).
    version: Mapped[int | None] = mapped_column(Integer)


class EventRow(Base):
    """'This changed' for the phones' event streams; ids are the streams' event ids."""

    __tablename__ = "events"
    # Ids are never reused, on SQLite too: a watcher that has looked past an id never
    # needs to look there again (migration 0004).
    __table_args__ = ({"sqlite_autoincrement": True},)

    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    session_id: Mapped[str] = mapped_column(
        ForeignKey("sessions.id", ondelete="CASCADE"), index=True
    )
    type: Mapped[str] = mapped_column(String(16))
    data: Mapped[str] = mapped_column(Text)  # JSON
    created_at: Mapped[datetime] = mapped_column(DateTime())


class JoinFailureRow(Base):
    """A join that failed (wrong, used or expired code), by client address: what the
    guessing limits count. Kept for the counting window only (the sweeper prunes it)."""

    __tablename__ = "join_failures"
    __table_args__ = (Index("ix_join_failures_client_failed_at", "client", "failed_at"),)

    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    # An IPv4 address or an IPv6 /64 network (one subscriber's whole range).
    client: Mapped[str] = mapped_column(String(64))
    failed_at: Mapped[datetime] = mapped_column(DateTime(), index=True)


def core(row: type[Base]) -> Table:
    """``row``'s table as SQLAlchemy Core sees it: for the hottest statements, built once and
    run with no ORM work per call."""
    table = row.__table__
    assert isinstance(table, Table)
    return table
