"""The participants' photos as stored (upright JPEG, downscaled, no metadata)."""

from __future__ import annotations

from datetime import datetime

from sqlalchemy import update

from backend.eventstream.log import EventType, record
from backend.participants import Participant
from backend.storage.database import Database
from backend.storage.tables import ParticipantRow, PhotoRow
from backend.storage.versions import bump_version

from .imaging import StoredPhoto
from .lens import Lens


class Photos:
    def __init__(self, database: Database) -> None:
        self.database = database

    def put(
        self, participant: Participant, photo: StoredPhoto, lens: Lens | None, now: datetime
    ) -> int:
        """Store (or replace) a friend's photo, with its lens if known. Its old taps meant
        points of the old photo, so they are cleared, and so is the answer. Returns the new
        version."""
        sid, role = participant.session_id, participant.role
        with self.database.write() as tx:
            # The version first: it locks the session, so a second upload of the same photo
            # waits here and then finds this one's row instead of inserting it twice.
            version = bump_version(tx, sid)
            tx.merge(
                PhotoRow(
                    session_id=sid,
                    role=role,
                    data=photo.data,
                    width=photo.width,
                    height=photo.height,
                    scale=photo.scale,
                    uploaded_at=now,
                    lens_focal_35mm=None if lens is None else lens.focal_35mm,
                    lens_uncertainty=None if lens is None else lens.uncertainty,
                    lens_told_by=None if lens is None else lens.told_by,
                )
            )
            tx.execute(
                update(ParticipantRow)
                .where(ParticipantRow.session_id == sid, ParticipantRow.role == role)
                .values(taps=None)
            )
            record(tx, sid, EventType.PHOTO, {"role": role, "version": version}, now)
        return version

    def get(self, session_id: str, role: str) -> StoredPhoto | None:
        with self.database.read() as tx:
            row = tx.get(PhotoRow, (session_id, role))
            if row is None:
                return None
            return StoredPhoto(data=row.data, width=row.width, height=row.height, scale=row.scale)
