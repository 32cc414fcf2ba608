"""The session as one phone sees it: who is there and online, both photos and tap sets,
the answer, and how many landmarks are still needed."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import timedelta

from backend.clock import Clock, aware
from backend.pairing.service import PairingService
from backend.participants import ROLES, Participant
from backend.photos.gravity import Gravity
from backend.photos.schemas import GravityInfo, LensInfo, PhotoStored
from backend.settings import Settings
from backend.storage.snapshot import PhotoInfo
from backend.taps.answers import Answered, AnswerService, tap_sets
from backend.taps.schemas import StoredAnswer, Taps
from backend.taps.service import TapService
from backend.taps.shown import shown

from .schemas import ParticipantState, SessionState


@dataclass
class StateService:
    answers: AnswerService
    taps: TapService
    pairing: PairingService
    settings: Settings
    clock: Clock

    def state(self, participant: Participant, base_url: str) -> SessionState:
        """What ``participant``'s phone shows."""
        snapshot = self.answers.due(self.answers.snapshot(participant.session_id))
        taps = tap_sets(snapshot)
        told = shown(
            taps,
            StoredAnswer.read(snapshot.answer),
            self.settings.tap_sigma,
            levelled=snapshot.levelled,
        )
        return self._state(participant, base_url, Answered(snapshot, taps, told))

    def put_taps(self, participant: Participant, taps: Taps, base_url: str) -> SessionState:
        """Replace the caller's taps; the state with the answer they give."""
        answered = self.taps.put(participant, taps)
        if answered is None:  # overtaken by a newer change: the session as it now is
            return self.state(participant, base_url)
        return self._state(participant, base_url, answered)

    def _state(self, participant: Participant, base_url: str, answered: Answered) -> SessionState:
        snapshot, taps, told = answered.snapshot, answered.taps, answered.shown
        now = self.clock()
        online_after = now - timedelta(seconds=self.settings.online_seconds)
        code = snapshot.join_code
        code_valid = (
            code is not None
            and snapshot.join_code_expires_at is not None
            and snapshot.join_code_expires_at > now
            and participant.role == "starter"
        )
        return SessionState(
            session_id=snapshot.id,
            you=participant.role,
            version=snapshot.version,
            expires_at=aware(snapshot.expires_at),
            join_code=code if code_valid else None,
            join_code_expires_at=(
                aware(snapshot.join_code_expires_at)
                if code_valid and snapshot.join_code_expires_at
                else None
            ),
            join_url=self.pairing.join_url(base_url, code) if code_valid and code else None,
            join_code_renewals=snapshot.join_code_renewals if participant.role == "starter" else 0,
            participants={
                role: ParticipantState(
                    joined=role in snapshot.members,
                    online=role in snapshot.members
                    and (seen := snapshot.members[role].last_seen_at) is not None
                    and seen > online_after,
                )
                for role in ROLES
            },
            photos={role: _photo(snapshot.photos.get(role)) for role in ROLES},
            taps=taps,
            landmarks_needed=told.landmarks_needed,
            answer=told.answer,
            answer_version=snapshot.answer_version if told.answer is not None else None,
            answer_error=None if told.answer_error is None else told.answer_error[participant.role],
        )


def _photo(info: PhotoInfo | None) -> PhotoStored | None:
    if info is None:
        return None
    lens = (
        None
        if info.lens_focal_35mm is None or info.lens_told_by not in ("photo", "phone")
        else LensInfo(focal_35mm=info.lens_focal_35mm, told_by=info.lens_told_by)
    )
    gravity = Gravity.read(info.gravity)
    return PhotoStored(
        width=info.width,
        height=info.height,
        scale=info.scale,
        lens=lens,
        gravity=None if gravity is None else GravityInfo.of(gravity),
        heading=info.heading,
        heading_sigma_deg=info.heading_sigma_deg,
    )
