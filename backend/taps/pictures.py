"""The pictures a session's answer and taps give: the answer drawn on a photo, a
landmark's crop ("find #3"), a suggested spot for a landmark (searched in the photos'
pixels), and how a phone has turned since its photo (a live frame matched to it)."""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np

from backend.errors import ErrorCode, RefusedError
from backend.participants import ROLES, Participant, Role, other
from backend.photos.kept import KeptPhoto
from backend.photos.pictures import decode_photo, encode_image, encode_layer
from backend.photos.repository import Photos
from backend.photos.schemas import ImageFormat
from backend.photos.service import PhotoService
from backend.settings import Settings
from backend.storage.snapshot import Snapshot
from shared_solver.drawing.overlay import render as render_drawing
from shared_solver.drawing.shapes import AnswerDrawing
from shared_solver.matching.reanchor import reanchor

from . import guidance
from .answers import AnswerService, solved, tap_sets
from .schemas import LandmarkSuggestion, Reanchored, Spot

# A live frame is matched at most this long side, px (a phone sends about this much: larger
# frames cost matching time and say no more).
LIVE_FRAME_SIDE = 960


@dataclass(kw_only=True)
class PictureService:
    answers: AnswerService
    photos: Photos
    photo_service: PhotoService
    settings: Settings
    suggestions: guidance.Suggestions = field(default_factory=guidance.Suggestions)

    def overlay(
        self, participant: Participant, role: Role, fmt: ImageFormat, layer: bool = False
    ) -> bytes:
        """``role``'s photo with the answer drawn for that phone, drawn for each request and
        never kept (a phone loads each answer's overlay once; its own cache keeps it).
        ``layer``: the drawing alone, a transparent PNG (``fmt`` aside), for a phone that
        has its photo already.

        The shapes are the stored answer's drawing for that photo, the very ones the phone
        draws as SVG (``in_photo[role].drawing``): rendered, not computed again."""
        snapshot = self.answers.due(self.answers.snapshot(participant.session_id))
        stored = solved(snapshot)
        kept = self._photo(snapshot, role)
        view = stored.answer.in_photo.get(role)
        drawing = None if view is None else view.drawing
        if kept is None or drawing is None or not _drawn_for(drawing, kept):
            raise RefusedError(
                ErrorCode.NO_RESULT, "That photo changed; the answer is being renewed."
            )
        pixels = decode_photo(kept.photo.data)
        # The solver's photo 2 is the one it found the friend in. A layer needs the photo as
        # it was beside the drawn one; a picture is drawn on the decoded pixels themselves.
        canvas = pixels.copy() if layer else pixels
        drawn = render_drawing(canvas, drawing, photo=stored.order.number(role))
        return encode_layer(drawn, pixels) if layer else encode_image(drawn, format=fmt)

    def crop(self, participant: Participant, role: Role, landmark_id: int) -> bytes:
        """A small picture around one landmark of ``role``'s photo: "find this"."""
        # The tap and its photo's version alone: a crop is asked for each landmark found,
        # and reading the whole session (its answer parsed, both tap sets validated) was a
        # fifth of its CPU.
        there, found = self.answers.taps.landmark(participant.session_id, role, landmark_id)
        if not there:
            raise RefusedError(ErrorCode.SESSION_NOT_FOUND, "This session has ended.")
        crop = (
            None
            if found is None
            else self.photo_service.crop(participant, role, found.x, found.y, found.photo_version)
        )
        if crop is None:
            raise RefusedError(
                ErrorCode.LANDMARK_NOT_FOUND, f"The {role} has no landmark #{landmark_id}."
            )
        return crop

    def suggestion(
        self, participant: Participant, role: Role, landmark_id: int
    ) -> LandmarkSuggestion:
        """A suggested spot in ``role``'s photo for landmark ``landmark_id``, which the other
        phone tapped: searched along its band once per answer, then kept."""
        snapshot = self.answers.due(self.answers.snapshot(participant.session_id))
        stored = solved(snapshot)
        taps = tap_sets(snapshot)
        theirs = taps[other(role)]
        if theirs is None or all(tap.id != landmark_id for tap in theirs.landmarks):
            raise RefusedError(
                ErrorCode.LANDMARK_NOT_FOUND,
                f"The {other(role)} has no landmark #{landmark_id} to find.",
            )
        version = stored.version

        def search() -> tuple[float, float] | None:
            photos = {r: self._photo(snapshot, r) for r in ROLES}
            if any(photo is None for photo in photos.values()):
                return None
            return guidance.suggested(
                stored.solution,
                stored.order,
                taps,
                {r: decode_photo(kept.photo.data) for r, kept in photos.items() if kept},
                finder=role,
                landmark_id=landmark_id,
                default_sigma=self.settings.tap_sigma,
            )

        spot = self.suggestions.get((snapshot.id, version, role, landmark_id), search)
        return LandmarkSuggestion(
            id=landmark_id,
            answer_version=version,
            spot=None if spot is None else Spot(x=spot[0], y=spot[1]),
        )

    def reanchor(
        self, participant: Participant, frame: bytes, frame_focal_px: float | None = None
    ) -> Reanchored:
        """How ``participant``'s phone has turned since their photo, from ``frame``, a picture
        of its live view: matched to the stored photo, whose focal length is the answer's.
        The frame is decoded, matched and dropped: nothing of it is kept.

        Raises:
            RefusedError: ``no_result`` before an answer (it gives the photo's focal length),
                ``invalid_photo`` when ``frame`` is no picture.
            SolverError: ``no_solution`` (``frame_not_matched``) when the frame does not
                match the photo well enough to tell.
        """
        snapshot = self.answers.snapshot(participant.session_id)
        stored = solved(snapshot)
        kept = self._photo(snapshot, participant.role)
        if kept is None:
            raise RefusedError(ErrorCode.NO_RESULT, "Your photo changed; take the answer again.")
        cameras = stored.solution.get("cameras") or []
        number = stored.order.number(participant.role)
        focal = cameras[number - 1].get("focal_px") if len(cameras) >= number else None
        if focal is None:  # a projective answer (cameras unknown) has no direction to carry
            raise RefusedError(
                ErrorCode.NO_RESULT, "This answer does not know your photo's lens: no live view."
            )
        pixels = decode_photo(frame)
        scale = min(1.0, LIVE_FRAME_SIDE / max(pixels.shape[:2]))
        if scale < 1.0:
            size = (round(pixels.shape[1] * scale), round(pixels.shape[0] * scale))
            pixels = np.asarray(cv2.resize(pixels, size, interpolation=cv2.INTER_AREA), np.uint8)
        found = reanchor(
            decode_photo(kept.photo.data),
            pixels,
            float(focal),
            frame_focal_px=None if frame_focal_px is None else frame_focal_px * scale,
        )
        return Reanchored(
            rotation=found.rotation.tolist(),
            frame_focal_px=found.frame_focal_px / scale,
            inliers=found.inliers,
            degrees=found.degrees,
        )

    def _photo(self, snapshot: Snapshot, role: Role) -> KeptPhoto | None:
        """``role``'s photo as ``snapshot`` has it."""
        info = snapshot.photos.get(role)
        return None if info is None else self.photos.get(snapshot.id, role, info.version)


def _drawn_for(drawing: AnswerDrawing, kept: KeptPhoto) -> bool:
    """Whether ``drawing`` was made for a photo of ``kept``'s size."""
    return (drawing.width, drawing.height) == (kept.photo.width, kept.photo.height)
