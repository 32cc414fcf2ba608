"""What the phones are shown of the taps and the answer: the part of a phone's state
(``backend.sessions.state``) that a change of taps or an answer makes. Computed here for
both the state a phone reads and the events that bring a change to the other phone
(``TapsChanged``, ``AnswerChanged``, ``PhotoChanged``), so that the two always agree and a
phone shows an event's change without reading the state again."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from backend.participants import ROLES, Role, other
from shared_solver import Refusal

from . import problem as problems
from .schemas import Answer, AnswerChanged, StoredAnswer, Taps


@dataclass(frozen=True)
class Shown:
    """The answer as the phones show it, and the landmarks still needed with it."""

    answer: Answer | None
    answer_error: dict[Role, Refusal] | None  # by the phone it is said to
    landmarks_needed: int

    def changed(self, version: int) -> AnswerChanged:
        """Event ``answer``'s data, for the answer of ``version``."""
        return AnswerChanged(
            version=version,
            answer=self.answer,
            answer_error=self.answer_error,
            landmarks_needed=self.landmarks_needed,
        )


def shown(
    taps: dict[Role, Taps | None],
    stored: StoredAnswer | None,
    sigma: float,
    *,
    levelled: bool = False,
) -> Shown:
    """What ``stored`` (None: no answer yet) shows, with these taps (``levelled``: both
    photos have gravity). A refusal is worded again for each phone from its reason and
    parameters: its photo is "your photo", the other "your friend's photo"."""
    task = problems.problem(taps, sigma, levelled=levelled)
    answer: Answer | None = None if stored is None else stored.answer
    error = None if stored is None else stored.error
    errors = None
    if stored is not None and error is not None:
        order = stored.order or task.order
        errors = {role: error.said_to(order.number(role)) for role in ROLES}
    return Shown(answer, errors, task.landmarks_needed(answer))


def needed_after_photo(role: Role, theirs: dict[str, Any] | None, levelled: bool) -> int:
    """Landmarks needed once ``role`` has a new photo: its taps are gone, the other phone's
    (``theirs``, as stored) stay; ``levelled``: both photos now have gravity. A count: the
    taps' precision plays no part."""
    kept = None if theirs is None else Taps.model_validate(theirs)
    task = problems.problem({role: None, other(role): kept}, 1.0, levelled=levelled)
    return task.landmarks_needed()
