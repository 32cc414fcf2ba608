"""The participants' photos as stored (upright JPEG, downscaled, no metadata)."""

from __future__ import annotations

import json
from collections.abc import Callable
from datetime import datetime
from typing import Any

from sqlalchemy import insert, select, update

from backend.eventstream.log import EventType, record
from backend.participants import Participant, Role, other
from backend.storage.database import Database
from backend.storage.tables import ParticipantRow, PhotoRow
from backend.storage.versions import bump_version

from .imaging import StoredPhoto
from .lens import Lens
from .schemas import PhotoChanged, PhotoStored

# The landmarks still needed once a phone has a new photo (its taps gone), given the other
# phone's taps as stored: the taps domain counts them (backend.taps.shown).
NeededAfterPhoto = Callable[[Role, dict[str, Any] | None], int]


class Photos:
    def __init__(self, database: Database) -> None:
        self.database = database

    def put(
        self,
        participant: Participant,
        photo: StoredPhoto,
        lens: Lens | None,
        now: datetime,
        *,
        shown: PhotoStored,
        needed: NeededAfterPhoto,
    ) -> int:
        """Store (or replace) a friend's photo, with its lens if known. Its old taps meant
        points of the old photo, so they are cleared, and so is the answer; the event tells
        the other phone the photo as ``shown`` and the landmarks then ``needed``. Returns the
        new version."""
        sid, role = participant.session_id, participant.role
        row = {
            "data": photo.data,
            "width": photo.width,
            "height": photo.height,
            "scale": photo.scale,
            "uploaded_at": now,
            "lens_focal_35mm": None if lens is None else lens.focal_35mm,
            "lens_uncertainty": None if lens is None else lens.uncertainty,
            "lens_told_by": None if lens is None else lens.told_by,
        }
        with self.database.write() as tx:
            # The version first: it locks the session, so a second upload of the same photo
            # waits here and then finds this one's row instead of inserting it twice.
            version = bump_version(tx, sid)
            # Replaced in place, or added: never read (the old bytes are of no use here).
            mine = (PhotoRow.session_id == sid) & (PhotoRow.role == role)
            replaced = tx.execute(update(PhotoRow).where(mine).values(row))
            if not replaced.rowcount:  # type: ignore[attr-defined]
                tx.execute(insert(PhotoRow).values(session_id=sid, role=role, **row))
            tx.execute(
                update(ParticipantRow)
                .where(ParticipantRow.session_id == sid, ParticipantRow.role == role)
                .values(taps=None)
            )
            theirs = tx.scalar(
                select(ParticipantRow.taps).where(
                    ParticipantRow.session_id == sid, ParticipantRow.role == other(role)
                )
            )
            told = PhotoChanged(
                role=role,
                version=version,
                photo=shown,
                landmarks_needed=needed(role, None if theirs is None else json.loads(theirs)),
            )
            record(tx, sid, EventType.PHOTO, told, now, locked=True)
        return version

    def get(self, session_id: str, role: str) -> StoredPhoto | None:
        with self.database.read() as tx:
            row = tx.get(PhotoRow, (session_id, role))
            if row is None:
                return None
            return StoredPhoto(data=row.data, width=row.width, height=row.height, scale=row.scale)
