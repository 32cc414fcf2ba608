"""A phone's taps: checked against its photo, then replaced together with the answer
they give (one write), which the other phone hears of."""

from __future__ import annotations

from dataclasses import dataclass, replace

from backend.clock import Clock
from backend.errors import ErrorCode, RefusedError
from backend.eventstream.notifier import Notifier
from backend.participants import Participant
from backend.settings import Settings

from .answers import Answered, AnswerService, tap_sets
from .repository import TapStore
from .schemas import Taps


@dataclass(kw_only=True)
class TapService:
    answers: AnswerService
    taps: TapStore
    settings: Settings
    notifier: Notifier
    clock: Clock

    def put(self, participant: Participant, taps: Taps) -> Answered | None:
        """Replace the caller's taps, answering again when both photos allow it: the
        session as it then is (None: overtaken by a newer change, being answered)."""
        snapshot = self.answers.snapshot(participant.session_id)
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
        found = self.answers.solve(after, now, previous=(snapshot, before))
        unanswered = self.answers.shown(now, None, levelled=snapshot.levelled)
        told = None if found is None else self.answers.shown(now, found, levelled=snapshot.levelled)
        # Dumped once: stored, and kept as the session's answer below.
        dumped = None if found is None or told is None else found.as_json()
        version, answered = self.taps.put_taps(
            participant,
            taps,
            self.clock(),
            read=snapshot.version,
            needed=unanswered.landmarks_needed,
            answer=None if dumped is None or told is None else (dumped, told),
        )
        self.notifier.notify(participant.session_id)
        if version != snapshot.version + 1:  # overtaken: answer the session as it now is
            return self.answers.answer(participant.session_id, version)
        recorded = replace(
            after,
            version=version,
            answer=dumped if answered else None,
            answer_version=version if answered else None,
        )
        # Nothing more is due: the answer is recorded, or these taps give none.
        return Answered(recorded, now, told if answered and told else unanswered)

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


def _crosses(a: float, b: float, c: float, width: int, height: int) -> bool:
    """Whether a x + b y + c = 0 is a line (a or b nonzero) that crosses the photo."""
    if a == 0.0 and b == 0.0:
        return False
    corners = [a * x + b * y + c for x in (0, width) for y in (0, height)]
    return min(corners) <= 0.0 <= max(corners)
