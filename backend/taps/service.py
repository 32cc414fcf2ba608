"""Taps and the answer they give: a phone replaces its taps, the answer is computed from
both phones' taps (when there is enough) and recorded with the version it is for; the
answer drawn on a photo, and a landmark's crop ("find #3")."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

from backend.clock import Clock
from backend.errors import ErrorCode, RefusedError
from backend.eventstream.notifier import Notifier
from backend.participants import ROLES, Participant, Role, other
from backend.photos.imaging import decode_photo, encode_image, encode_layer
from backend.photos.kept import KeptPhoto
from backend.photos.repository import Photos
from backend.photos.schemas import ImageFormat
from backend.photos.service import PhotoService
from backend.settings import Settings
from backend.storage.database import Database
from backend.storage.snapshot import Snapshot, read_snapshot
from shared_solver import SolveResult, draw_overlay

from . import guidance
from . import problem as problems
from .photo_order import PhotoOrder
from .repository import TapStore
from .schemas import Answer, LandmarkSuggestion, Spot, StoredAnswer, Taps
from .shown import Shown, shown


class TapService:
    def __init__(
        self,
        *,
        database: Database,
        taps: TapStore,
        photos: Photos,
        photo_service: PhotoService,
        settings: Settings,
        notifier: Notifier,
        clock: Clock,
    ) -> None:
        self.database = database
        self.taps = taps
        self.photos = photos
        self.photo_service = photo_service
        self.settings = settings
        self.notifier = notifier
        self.clock = clock
        self.suggestions = guidance.Suggestions()

    def snapshot(self, session_id: str) -> Snapshot:
        snapshot = read_snapshot(self.database, session_id)
        if snapshot is None:
            raise RefusedError(ErrorCode.SESSION_NOT_FOUND, "This session has ended.")
        return snapshot

    def put(self, participant: Participant, taps: Taps) -> Answered | None:
        """Replace the caller's taps, answering again when both photos allow it: the
        session as it then is (None: overtaken by a newer change, being answered)."""
        snapshot = self.snapshot(participant.session_id)
        photo = snapshot.photos.get(participant.role)
        if photo is None:
            raise RefusedError(ErrorCode.PHOTO_MISSING, "Upload your photo before tapping on it.")
        self._check(taps, (photo.width, photo.height))
        # Answered before writing, so that the taps and their answer are one write; unless
        # another change comes in between, which makes that answer stale.
        stored = taps.model_dump(mode="json")
        member = replace(snapshot.members[participant.role], taps=stored)
        after = replace(snapshot, members=snapshot.members | {member.role: member})
        before = tap_sets(snapshot)
        now = before | {participant.role: Taps.model_validate(stored)}
        found = self._solve(after, now, previous=(snapshot, before))
        unanswered = self._shown(now, None)
        told = None if found is None else self._shown(now, found)
        version, answered = self.taps.put_taps(
            participant,
            taps,
            self.clock(),
            read=snapshot.version,
            needed=unanswered.landmarks_needed,
            answer=None if found is None or told is None else (found, told),
        )
        self.notifier.notify(participant.session_id)
        if version != snapshot.version + 1:  # overtaken: answer the session as it now is
            return self.answer(participant.session_id, version)
        recorded = replace(
            after,
            version=version,
            answer=found.as_json() if answered and found is not None else None,
            answer_version=version if answered else None,
        )
        # Nothing more is due: the answer is recorded, or these taps give none.
        return Answered(recorded, now, told if answered and told else unanswered)

    def answer(self, session_id: str, version: int) -> Answered | None:
        """Solve for this version if there is enough; record it unless overtaken. The
        session as it then is (None: overtaken by a newer change)."""
        snapshot = self.snapshot(session_id)
        if snapshot.version != version:
            return None  # a newer change is being answered
        taps = tap_sets(snapshot)
        found = self._solve(snapshot, taps)
        shown = self._shown(taps, found)
        if found is None:
            return Answered(snapshot, taps, shown)
        if not self.taps.put_answer(session_id, version, found, shown, self.clock()):
            return None
        self.notifier.notify(session_id)
        recorded = replace(snapshot, answer=found.as_json(), answer_version=version)
        return Answered(recorded, taps, shown)

    def _shown(self, taps: dict[Role, Taps | None], answer: StoredAnswer | None) -> Shown:
        """What the phones are shown of ``taps`` with ``answer`` (as stored)."""
        return shown(taps, answer, self.settings.tap_sigma)

    def due(self, snapshot: Snapshot) -> Snapshot:
        """The session with its answer. One may be due but not recorded: a change overtook
        the write that carried it and its writer is answering again, or a migration cleared
        it. Answered here rather than sending a phone away empty."""
        if snapshot.answer is not None:
            return snapshot
        answered = self.answer(snapshot.id, snapshot.version)
        return snapshot if answered is None else answered.snapshot

    def overlay(
        self, participant: Participant, role: Role, fmt: ImageFormat, layer: bool = False
    ) -> bytes:
        """``role``'s photo with the answer drawn for that phone, drawn for each request and
        never kept (a phone loads each answer's overlay once; its own cache keeps it).
        ``layer``: the drawing alone, a transparent PNG (``fmt`` aside), for a phone that
        has its photo already."""
        snapshot = self.due(self.snapshot(participant.session_id))
        stored = _solved(snapshot)
        kept = self._photo(snapshot, role)
        member = snapshot.members.get(role)
        if kept is None or member is None or member.taps is None:
            raise RefusedError(
                ErrorCode.NO_RESULT, "That photo changed; the answer is being renewed."
            )
        taps = {tap.id: (tap.x, tap.y) for tap in Taps.model_validate(member.taps).landmarks}
        ids = stored.answer.landmark_ids
        pixels = decode_photo(kept.photo.data)
        drawn = draw_overlay(
            pixels,
            SolveResult.model_validate(stored.solution),
            # The solver's photo 2 is the one it found the friend in.
            photo=stored.order.number(role),
            points=[taps[i] for i in ids],
            labels=ids,
        )
        return encode_layer(drawn, pixels) if layer else encode_image(drawn, format=fmt)

    def crop(self, participant: Participant, role: Role, landmark_id: int) -> bytes:
        """A small picture around one landmark of ``role``'s photo: "find this"."""
        snapshot = self.snapshot(participant.session_id)
        taps = tap_sets(snapshot)[role]
        tap = next((t for t in taps.landmarks if t.id == landmark_id), None) if taps else None
        info = snapshot.photos.get(role)
        crop = (
            None
            if tap is None or info is None
            else self.photo_service.crop(participant, role, tap.x, tap.y, info.version)
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
        snapshot = self.due(self.snapshot(participant.session_id))
        stored = _solved(snapshot)
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

    def _photo(self, snapshot: Snapshot, role: Role) -> KeptPhoto | None:
        """``role``'s photo as ``snapshot`` has it."""
        info = snapshot.photos.get(role)
        return None if info is None else self.photos.get(snapshot.id, role, info.version)

    def _check(self, taps: Taps, size: tuple[int, int]) -> None:
        if len(taps.landmarks) > self.settings.max_landmarks:
            raise RefusedError(
                ErrorCode.TOO_MANY_LANDMARKS,
                f"{len(taps.landmarks)} landmarks; at most {self.settings.max_landmarks}.",
            )
        ids = [tap.id for tap in taps.landmarks]
        if len(set(ids)) != len(ids):
            repeated = sorted({i for i in ids if ids.count(i) > 1})
            raise RefusedError(
                ErrorCode.DUPLICATE_LANDMARK, f"Landmark #{repeated[0]} is tapped twice; keep one."
            )
        if taps.friend is not None and taps.friend_line is not None:
            raise RefusedError(
                ErrorCode.CONFLICTING_INPUTS,
                "Mark your friend either as a point or as a line, not both.",
            )
        width, height = size
        line = taps.friend_line
        if line is not None and not _crosses(line.a, line.b, line.c, width, height):
            raise RefusedError(
                ErrorCode.INVALID_LINE,
                "The line through your friend must cross your photo: friend_line is "
                "{a, b, c} for a*x + b*y + c = 0, with a or b nonzero.",
            )
        marks = [(f"landmark #{t.id}", t.x, t.y) for t in taps.landmarks]
        if taps.friend is not None:
            marks.append(("the friend mark", taps.friend.x, taps.friend.y))
        for name, x, y in marks:
            if not (0 <= x <= width and 0 <= y <= height):
                raise RefusedError(
                    ErrorCode.OUTSIDE_PHOTO,
                    # :g, not :.0f: 1e308 is shown as such, not as 309 digits.
                    f"{name.capitalize()} at ({x:g}, {y:g}) is outside your photo "
                    f"({width} x {height} px).",
                )

    def _solve(
        self,
        snapshot: Snapshot,
        taps: dict[Role, Taps | None],
        previous: tuple[Snapshot, dict[Role, Taps | None]] | None = None,
    ) -> StoredAnswer | None:
        """The answer for the session as ``snapshot`` has it, with these ``taps``; None
        when there is not enough to answer (a friend or a photo missing, too few taps).
        ``previous``: the session before this change and its taps, whose answer judges the
        landmarks tapped since (misfits) and answers again what it answered already."""
        photos = snapshot.photos
        if set(snapshot.members) != set(ROLES) or set(photos) != set(ROLES):
            return None
        sigma = self.settings.tap_sigma
        task = problems.problem(taps, sigma)
        if not task.solvable:
            return None
        sizes = {role: (photos[role].width, photos[role].height) for role in ROLES}
        cameras = {
            role: problems.camera(photos[role].lens_focal_35mm, photos[role].lens_uncertainty)
            for role in ROLES
        }
        # The photos are the same before and after a change of taps (a new photo is a change
        # of its own): the answer before it answers its problem again.
        earlier = StoredAnswer.read(previous[0].answer if previous else snapshot.answer)
        before = previous[1] if previous else taps
        known = problems.known_fit(earlier, before, sigma)

        def fit(some: dict[Role, Taps | None]) -> tuple[SolveResult, PhotoOrder] | None:
            return problems.fitted(some, sigma, sizes=sizes, cameras=cameras, known=known)

        judged = guidance.misfits(earlier, before, taps, sizes=sizes, default_sigma=sigma, fit=fit)
        return problems.solved(
            task, sizes=sizes, cameras=cameras, taps=taps, misfits=judged, known=known
        )


@dataclass(frozen=True)
class Answered:
    """A session as a change of taps (or its answer) left it, and what its phones are
    shown of it: nothing more is due."""

    snapshot: Snapshot
    taps: dict[Role, Taps | None]
    shown: Shown


@dataclass(frozen=True)
class _Solved:
    """A session's recorded answer that has a solution (not a refusal)."""

    answer: Answer
    solution: dict[str, Any]
    order: PhotoOrder
    version: int


def _solved(snapshot: Snapshot) -> _Solved:
    """``snapshot``'s recorded answer with its solution, or the refusal that there is none."""
    stored = StoredAnswer.read(snapshot.answer)
    if (
        stored is None
        or stored.answer is None
        or stored.solution is None
        or stored.first is None
        or snapshot.answer_version is None
    ):
        raise RefusedError(
            ErrorCode.NO_RESULT, "There is no answer yet; tap more landmarks in both photos."
        )
    return _Solved(
        stored.answer, stored.solution, PhotoOrder(stored.first), snapshot.answer_version
    )


def tap_sets(snapshot: Snapshot) -> dict[Role, Taps | None]:
    """Each friend's taps as the snapshot holds them."""
    members = snapshot.members
    return {
        role: Taps.model_validate(members[role].taps)
        if role in members and members[role].taps is not None
        else None
        for role in ROLES
    }


def _crosses(a: float, b: float, c: float, width: int, height: int) -> bool:
    """Whether a x + b y + c = 0 is a line (a or b nonzero) that crosses the photo."""
    if a == 0.0 and b == 0.0:
        return False
    corners = [a * x + b * y + c for x in (0, width) for y in (0, height)]
    return min(corners) <= 0.0 <= max(corners)
