"""A session as the phones see it, read in one statement: the hottest read (every state
fetch and every change reads it). Everything but the photos' bytes."""

from __future__ import annotations

import json
from dataclasses import dataclass
from datetime import datetime
from typing import Any

from sqlalchemy import bindparam, select

from .database import Database
from .tables import ParticipantRow, PhotoRow, SessionRow


@dataclass(frozen=True)
class PhotoInfo:
    width: int
    height: int
    scale: float
    lens_focal_35mm: float | None = None
    lens_uncertainty: float | None = None
    lens_told_by: str | None = None
    version: int | None = None  # the session's version that stored it: names its bytes
    gravity: str | None = None  # JSON [x, y, z, sigma_deg] (backend.photos.gravity), or None
    heading: float | None = None  # degrees from north in [0, 360) (backend.photos.heading)
    heading_sigma_deg: float | None = None


@dataclass(frozen=True)
class Member:
    """A participant as the others see them."""

    role: str
    joined_at: datetime
    last_seen_at: datetime | None
    taps: dict[str, Any] | None


@dataclass(frozen=True)
class Snapshot:
    """Everything of a session but the photos' bytes, read in one transaction."""

    id: str
    created_at: datetime
    expires_at: datetime
    join_code: str | None
    join_code_expires_at: datetime | None
    join_code_renewals: int
    version: int
    answer: dict[str, Any] | None
    answer_version: int | None
    members: dict[str, Member]
    photos: dict[str, PhotoInfo]

    @property
    def levelled(self) -> bool:
        """Both photos came with the phone's gravity at the shutter."""
        return len(self.photos) == 2 and all(
            photo.gravity is not None for photo in self.photos.values()
        )


_sessions, _participants, _photos = (
    row.__table__ for row in (SessionRow, ParticipantRow, PhotoRow)
)
# Built once: building a statement costs more than running it on SQLite.
_SNAPSHOT = (
    select(
        _sessions.c.id,
        _sessions.c.created_at,
        _sessions.c.expires_at,
        _sessions.c.join_code,
        _sessions.c.join_code_expires_at,
        _sessions.c.join_code_renewals,
        _sessions.c.version,
        _sessions.c.answer,
        _sessions.c.answer_version,
        _participants.c.role,
        _participants.c.joined_at,
        _participants.c.last_seen_at,
        _participants.c.taps,
        _photos.c.width,
        _photos.c.height,
        _photos.c.scale,
        _photos.c.lens_focal_35mm,
        _photos.c.lens_uncertainty,
        _photos.c.lens_told_by,
        _photos.c.version.label("photo_version"),
        _photos.c.gravity,
        _photos.c.heading,
        _photos.c.heading_sigma_deg,
    )
    .join(_participants, _participants.c.session_id == _sessions.c.id)
    .outerjoin(
        _photos,
        (_photos.c.session_id == _participants.c.session_id)
        & (_photos.c.role == _participants.c.role),
    )
    .where(_sessions.c.id == bindparam("session_id"))
)


def read_snapshot(database: Database, session_id: str) -> Snapshot | None:
    """The session, or None when it is gone."""
    with database.query() as connection:
        rows = connection.execute(_SNAPSHOT, {"session_id": session_id}).all()
    if not rows:
        return None
    first = rows[0]
    return Snapshot(
        id=first.id,
        created_at=first.created_at,
        expires_at=first.expires_at,
        join_code=first.join_code,
        join_code_expires_at=first.join_code_expires_at,
        join_code_renewals=first.join_code_renewals,
        version=first.version,
        answer=None if first.answer is None else json.loads(first.answer),
        answer_version=first.answer_version,
        members={
            row.role: Member(
                row.role,
                row.joined_at,
                row.last_seen_at,
                None if row.taps is None else json.loads(row.taps),
            )
            for row in rows
        },
        photos={
            row.role: PhotoInfo(
                row.width,
                row.height,
                row.scale,
                row.lens_focal_35mm,
                row.lens_uncertainty,
                row.lens_told_by,
                row.photo_version,
                row.gravity,
                row.heading,
                row.heading_sigma_deg,
            )
            for row in rows
            if row.width is not None
        },
    )
