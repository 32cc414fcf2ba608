"""The answer the two phones' taps give: computed when both photos and enough taps are
there, recorded with the session's version it is for (a newer change overtakes it), and
what each phone is shown of it."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

from backend.clock import Clock
from backend.errors import ErrorCode, RefusedError
from backend.eventstream.notifier import Notifier
from backend.participants import ROLES, Role
from backend.photos.gravity import Gravity
from backend.photos.heading import Heading
from backend.settings import Settings
from backend.storage.database import Database
from backend.storage.snapshot import Snapshot, read_snapshot
from shared_solver import SolveResult

from . import guidance
from . import problem as problems
from .photo_order import PhotoOrder
from .repository import TapStore
from .schemas import Answer, StoredAnswer, Taps
from .shown import Shown, shown


@dataclass(kw_only=True)
class AnswerService:
    database: Database
    taps: TapStore
    settings: Settings
    notifier: Notifier
    clock: Clock

    def snapshot(self, session_id: str) -> Snapshot:
        snapshot = read_snapshot(self.database, session_id)
        if snapshot is None:
            raise RefusedError(ErrorCode.SESSION_NOT_FOUND, "This session has ended.")
        return snapshot

    def answer(self, session_id: str, version: int) -> Answered | None:
        """Solve for this version if there is enough; record it unless overtaken. The
        session as it then is (None: overtaken by a newer change)."""
        snapshot = self.snapshot(session_id)
        if snapshot.version != version:
            return None  # a newer change is being answered
        taps = tap_sets(snapshot)
        found = self.solve(snapshot, taps)
        shown = self.shown(taps, found, levelled=snapshot.levelled)
        if found is None:
            return Answered(snapshot, taps, shown)
        dumped = found.as_json()
        if not self.taps.put_answer(session_id, version, dumped, shown, self.clock()):
            return None
        self.notifier.notify(session_id)
        recorded = replace(snapshot, answer=dumped, answer_version=version)
        return Answered(recorded, taps, shown)

    def due(self, snapshot: Snapshot) -> Snapshot:
        """The session with its answer. One may be due but not recorded: a change overtook
        the write that carried it and its writer is answering again, or a migration cleared
        it. Answered here rather than sending a phone away empty."""
        if snapshot.answer is not None:
            return snapshot
        answered = self.answer(snapshot.id, snapshot.version)
        return snapshot if answered is None else answered.snapshot

    def shown(
        self, taps: dict[Role, Taps | None], answer: StoredAnswer | None, *, levelled: bool
    ) -> Shown:
        """What the phones are shown of ``taps`` with ``answer`` (as stored); ``levelled``:
        both photos have gravity."""
        return shown(taps, answer, self.settings.tap_sigma, levelled=levelled)

    def solve(
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
        task = problems.problem(taps, sigma, levelled=snapshot.levelled)
        if not task.solvable:
            return None
        facts = problems.PhotoFacts(
            sizes={role: (photos[role].width, photos[role].height) for role in ROLES},
            cameras={
                role: problems.camera(photos[role].lens_focal_35mm, photos[role].lens_uncertainty)
                for role in ROLES
            },
            readings={role: Gravity.read(photos[role].gravity) for role in ROLES},
            headings={
                role: Heading.read(photos[role].heading, photos[role].heading_sigma_deg)
                for role in ROLES
            },
        )
        # The photos are the same before and after a change of taps (a new photo is a change
        # of its own): the answer before it answers its problem again.
        earlier = StoredAnswer.read(previous[0].answer if previous else snapshot.answer)
        before = previous[1] if previous else taps
        known = problems.known_fit(earlier, before, sigma, levelled=facts.levelled)

        def fit(some: dict[Role, Taps | None]) -> tuple[SolveResult, PhotoOrder] | None:
            return problems.fitted(some, sigma, facts, known=known)

        judged = guidance.misfits(
            earlier, before, taps, sizes=facts.sizes, default_sigma=sigma, fit=fit
        )
        return problems.solved(task, facts, taps=taps, misfits=judged, known=known)


@dataclass(frozen=True)
class Answered:
    """A session as a change of taps (or its answer) left it, and what its phones are
    shown of it: nothing more is due."""

    snapshot: Snapshot
    taps: dict[Role, Taps | None]
    shown: Shown


@dataclass(frozen=True)
class Solved:
    """A session's recorded answer that has a solution (not a refusal)."""

    answer: Answer
    solution: dict[str, Any]
    order: PhotoOrder
    version: int


def solved(snapshot: Snapshot) -> Solved:
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
    return Solved(stored.answer, stored.solution, PhotoOrder(stored.first), snapshot.answer_version)


def tap_sets(snapshot: Snapshot) -> dict[Role, Taps | None]:
    """Each friend's taps as the snapshot holds them."""
    members = snapshot.members
    return {
        role: Taps.model_validate(members[role].taps)
        if role in members and members[role].taps is not None
        else None
        for role in ROLES
    }
