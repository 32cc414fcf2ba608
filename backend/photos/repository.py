"""The participants' photos as stored (upright JPEG, downscaled, no metadata)."""

from __future__ import annotations

import json
from collections.abc import Callable
from datetime import datetime
from typing import Any

from sqlalchemy import bindparam, select, update
from sqlalchemy.dialects import postgresql, sqlite

from backend.eventstream.log import EventType, record
from backend.participants import Participant, Role, other
from backend.storage.database import Database
from backend.storage.tables import ParticipantRow, PhotoRow, core
from backend.storage.versions import bump_version

from .gravity import Gravity
from .heading import Heading
from .intake import StoredPhoto
from .kept import KeptPhoto, KeptPhotos
from .lens import Lens
from .schemas import PhotoChanged, PhotoStored

# The landmarks still needed once a phone has a new photo (its taps gone), given the other
# phone's taps as stored and whether both photos now have gravity: the taps domain counts
# them (backend.taps.shown).
NeededAfterPhoto = Callable[[Role, dict[str, Any] | None, bool], int]


_photos, _participants = core(PhotoRow), core(ParticipantRow)
# Built once: every crop reads it, every upload writes them.
_PHOTO = select(
    _photos.c.data, _photos.c.width, _photos.c.height, _photos.c.scale, _photos.c.version
).where(_photos.c.session_id == bindparam("of"), _photos.c.role == bindparam("who"))
_KEY = ("session_id", "role")
_UPSERT = {
    name: (insert := dialect.insert(_photos)).on_conflict_do_update(
        index_elements=list(_KEY),
        set_={c.name: insert.excluded[c.name] for c in _photos.columns if c.name not in _KEY},
    )
    for name, dialect in (("postgresql", postgresql), ("sqlite", sqlite))
}
_MINE = (_participants.c.session_id == bindparam("of")) & (_participants.c.role == bindparam("who"))
_CLEAR_TAPS = update(_participants).where(_MINE).values(taps=None)
_TAPS = select(_participants.c.taps).where(_MINE)
_GRAVITY = select(_photos.c.gravity).where(
    (_photos.c.session_id == bindparam("of")) & (_photos.c.role == bindparam("who"))
)


class Photos:
    def __init__(self, database: Database, kept: KeptPhotos | None = None) -> None:
        self.database = database
        self.kept = kept or KeptPhotos()

    def put(
        self,
        participant: Participant,
        photo: StoredPhoto,
        lens: Lens | None,
        now: datetime,
        *,
        shown: PhotoStored,
        needed: NeededAfterPhoto,
        gravity: Gravity | None = None,
        heading: Heading | None = None,
    ) -> int:
        """Store (or replace) a friend's photo, with its lens and its phone's readings if
        known. Its old taps meant
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
            "gravity": None if gravity is None else gravity.as_json(),
            "heading": None if heading is None else heading.deg,
            "heading_sigma_deg": None if heading is None else heading.sigma_deg,
        }
        with self.database.write() as tx:
            # The version first: it locks the session, so a second upload of the same photo
            # waits here and then finds this one's row instead of inserting it twice.
            version = bump_version(tx, sid)
            # Added, or replaced in place: never read (the old bytes are of no use here).
            upsert = _UPSERT[tx.get_bind().dialect.name]
            tx.execute(upsert, {"session_id": sid, "role": role, "version": version, **row})
            tx.execute(_CLEAR_TAPS, {"of": sid, "who": role})
            theirs = tx.scalar(_TAPS, {"of": sid, "who": other(role)})
            levelled = (
                gravity is not None
                and tx.scalar(_GRAVITY, {"of": sid, "who": other(role)}) is not None
            )
            told = PhotoChanged(
                role=role,
                version=version,
                photo=shown,
                landmarks_needed=needed(
                    role, None if theirs is None else json.loads(theirs), levelled
                ),
            )
            record(tx, sid, EventType.PHOTO, told, now, locked=True)
        return version

    def get(self, session_id: str, role: str, version: int | None = None) -> KeptPhoto | None:
        """``role``'s photo; ``version``, the session's version that stored it (the
        snapshot's ``PhotoInfo.version``), names it: then a replica keeps it a minute, and
        a photo replaced since is not that one (None)."""
        if version is None:
            photo = self._read(session_id, role, None)
            return None if photo is None else KeptPhoto(photo, 0.0)
        return self.kept.get(
            (session_id, role, version), lambda: self._read(session_id, role, version)
        )

    def _read(self, session_id: str, role: str, version: int | None) -> StoredPhoto | None:
        """The stored photo (None: none), or only the one ``version`` stored (not None)."""
        with self.database.query() as connection:
            row = connection.execute(_PHOTO, {"of": session_id, "who": role}).first()
        if row is None or (version is not None and row.version != version):
            return None
        return StoredPhoto(data=row.data, width=row.width, height=row.height, scale=row.scale)
