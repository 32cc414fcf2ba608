"""A participant's photo: stored, shown back, and cropped around a landmark ("find #3")."""

from __future__ import annotations

from dataclasses import dataclass

from backend.clock import Clock
from backend.errors import ErrorCode, RefusedError
from backend.eventstream.notifier import Notifier
from backend.participants import Participant, Role
from backend.settings import Settings

from .gravity import Gravity
from .heading import Heading
from .intake import store_photo
from .lens import LensFacts, lens
from .pictures import crop_around
from .repository import NeededAfterPhoto, Photos
from .schemas import GravityInfo, LensInfo, PhotoStored


@dataclass(kw_only=True)
class PhotoService:
    photos: Photos
    settings: Settings
    notifier: Notifier
    clock: Clock
    needed: NeededAfterPhoto

    def put(
        self,
        participant: Participant,
        data: bytes,
        told: LensFacts | None = None,
        gravity: Gravity | None = None,
        heading: Heading | None = None,
    ) -> PhotoStored:
        """Store the caller's photo (replacing any earlier one, whose taps go with it), with
        its lens: from the photo's own EXIF, else from what the phone ``told`` of it; and
        which way was down and which way the lens looked at the shutter, when the phone
        read them."""
        photo = store_photo(
            data,
            max_pixels=self.settings.max_photo_pixels,
            max_side=self.settings.stored_photo_side,
        )
        found = lens(photo.lens, "photo") or (None if told is None else lens(told, "phone"))
        stored = PhotoStored(
            width=photo.width,
            height=photo.height,
            scale=photo.scale,
            lens=None
            if found is None
            else LensInfo(focal_35mm=found.focal_35mm, told_by=found.told_by),
            gravity=None if gravity is None else GravityInfo.of(gravity),
            heading=None if heading is None else heading.deg,
            heading_sigma_deg=None if heading is None else heading.sigma_deg,
        )
        self.photos.put(
            participant,
            photo,
            found,
            self.clock(),
            shown=stored,
            needed=self.needed,
            gravity=gravity,
            heading=heading,
        )
        self.notifier.notify(participant.session_id)
        return stored

    def get(self, participant: Participant, role: Role) -> bytes:
        """``role``'s photo as stored (upright JPEG): what that phone taps on."""
        kept = self.photos.get(participant.session_id, role)
        if kept is None:
            raise RefusedError(
                ErrorCode.PHOTO_NOT_FOUND, f"The {role} has not uploaded a photo yet."
            )
        return kept.photo.data

    def crop(
        self, participant: Participant, role: Role, x: float, y: float, version: int | None
    ) -> bytes | None:
        """A small picture around ``(x, y)`` of ``role``'s photo, the one stored at the
        session's ``version`` (None: unknown); None without a photo."""
        kept = self.photos.get(participant.session_id, role, version)
        return None if kept is None else crop_around(kept.photo.data, x, y, rows=kept.rows)
