"""A participant's photo: stored, shown back, and cropped around a landmark ("find #3")."""

from __future__ import annotations

from backend.clock import Clock
from backend.errors import ErrorCode, RefusedError
from backend.eventstream.notifier import Notifier
from backend.participants import Participant, Role
from backend.settings import Settings

from .imaging import crop_around, store_photo
from .repository import Photos
from .schemas import PhotoStored


class PhotoService:
    def __init__(
        self, photos: Photos, settings: Settings, notifier: Notifier, clock: Clock
    ) -> None:
        self.photos = photos
        self.settings = settings
        self.notifier = notifier
        self.clock = clock

    def put(self, participant: Participant, data: bytes) -> PhotoStored:
        """Store the caller's photo (replacing any earlier one, whose taps go with it)."""
        photo = store_photo(
            data,
            max_pixels=self.settings.max_photo_pixels,
            max_side=self.settings.stored_photo_side,
        )
        self.photos.put(participant, photo, self.clock())
        self.notifier.notify(participant.session_id)
        return PhotoStored(width=photo.width, height=photo.height, scale=photo.scale)

    def get(self, participant: Participant, role: Role) -> bytes:
        """``role``'s photo as stored (upright JPEG): what that phone taps on."""
        photo = self.photos.get(participant.session_id, role)
        if photo is None:
            raise RefusedError(
                ErrorCode.PHOTO_NOT_FOUND, f"The {role} has not uploaded a photo yet."
            )
        return photo.data

    def crop(self, participant: Participant, role: Role, x: float, y: float) -> bytes | None:
        """A small picture around ``(x, y)`` of ``role``'s photo; None without a photo."""
        photo = self.photos.get(participant.session_id, role)
        return None if photo is None else crop_around(photo.data, x, y)
