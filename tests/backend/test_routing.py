"""Which phone is told what: a warning goes to the phones of the photo it is about (its code
and parameters), never by its sentence, so rewording a sentence moves it nowhere
(backend.taps.problem).

A refusal shown in a session is its code, reason and parameters, worded for each phone:
the photo it is about is "your photo" to that photo's phone and "your friend's photo" to the
other (backend.taps.shown), from its parameters, never by reading its sentence."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest
from phones import scene

from backend.participants import ROLES, Role, other
from backend.taps import problem
from backend.taps.photo_order import PhotoOrder
from backend.taps.schemas import Landmark, Mark, StoredAnswer, Taps
from backend.taps.shown import shown
from shared_solver import Reason, Refusal, SolveResult, SolverWarning, WarningCode, words
from shared_solver.errors import (
    REFUSAL_OF_ONE_PHOTO,
    REFUSAL_PHOTO,
    WARNING_OF_ONE_PHOTO,
    WARNING_PHOTO,
)
from testbed.client import numbered

SIGMA = 2.0
SIZES: dict[Role, tuple[int, int]] = {"starter": (640, 480), "joiner": (640, 480)}
CAMERAS = {role: problem.camera(None) for role in ROLES}
# Two phone photos without gravity.
PHOTOS = problem.PhotoFacts(SIZES, CAMERAS, dict.fromkeys(ROLES))
# Parameters each code's sentence names (made up: only who is told is under test).
PARAMETERS: dict[WarningCode, dict[str, Any]] = {
    WarningCode.MISTAPPED: {"landmark": 3, "distance_px": 41.0},
    WarningCode.OUTSIDE_PHOTO: {"distance_px": 120.0, "side": "left"},
    WarningCode.AMBIGUOUS: {"marked": "point"},
    WarningCode.NO_MARGIN: {"marked": "line"},
}


def tapped(marker: Role) -> dict[Role, Taps | None]:
    """Six landmarks in both photos; ``marker`` marked the other friend (its photo is 1)."""
    s = scene(6, seed=3)
    x, y = s.epipole1.tolist()
    mine = {"landmarks": numbered(s.landmarks1), "friend": {"x": x, "y": y}}
    return {
        marker: Taps.model_validate(mine),
        other(marker): Taps.model_validate({"landmarks": numbered(s.landmarks2)}),
    }


def every_warning() -> list[SolverWarning]:
    """One warning of each code the solver gives (MISFIT is the taps service's)."""
    return [
        SolverWarning.of(code, **PARAMETERS.get(code, {}))
        for code in WarningCode
        if code not in WARNING_OF_ONE_PHOTO
    ]


def told(marker: Role, warnings: list[SolverWarning]) -> dict[Role, list[SolverWarning]]:
    """What each phone is told of ``warnings`` on the answer to ``tapped(marker)``."""
    task = problem.problem(tapped(marker), SIGMA)
    result: SolveResult = problem.fit(task, PHOTOS)
    answer = problem.answer(task, result.model_copy(update={"warnings": warnings}), SIZES)
    return {role: answer.in_photo[role].warnings for role in ROLES}


@pytest.mark.parametrize("marker", ROLES)
def test_where_the_friend_is_in_photo_2_is_told_only_to_photo_2s_phone(marker: Role) -> None:
    warnings = every_warning()
    codes = {role: [w.code for w in said] for role, said in told(marker, warnings).items()}
    everything = [w.code for w in warnings]
    assert codes[marker] == [code for code in everything if code not in WARNING_PHOTO]
    assert codes[other(marker)] == everything
    assert {WarningCode.BEHIND_YOU, WarningCode.OUTSIDE_PHOTO} <= set(WARNING_PHOTO)


def test_a_reworded_sentence_is_told_to_the_same_phones(monkeypatch: pytest.MonkeyPatch) -> None:
    before = told("starter", every_warning())
    # Every sentence reworded into one that the old routing by regular expressions read as
    # "about photo 2": who is told what must not move.
    reworded = "Your friend is outside this photo: photo 2, turn around."
    monkeypatch.setattr(words, "warning", lambda code, **_: reworded)
    after = told("starter", every_warning())
    for role in ROLES:
        assert [w.code for w in after[role]] == [w.code for w in before[role]]
        assert {w.message for w in after[role]} == {reworded}


@pytest.mark.parametrize("marker", ROLES)
def test_a_misfit_is_told_only_to_the_phone_that_tapped_it(marker: Role) -> None:
    taps = tapped(marker)
    task = problem.problem(taps, SIGMA)
    misfits: dict[Role, list[int]] = {marker: [], other(marker): [4]}
    stored = problem.solved(task, PHOTOS, taps=taps, misfits=misfits)
    assert stored.answer is not None
    theirs = stored.answer.in_photo[other(marker)].warnings[0]
    assert (theirs.code, theirs.landmark, theirs.photo) == (WarningCode.MISFIT, 4, 2)
    assert theirs.message == words.misfit(4)
    mine = stored.answer.in_photo[marker].warnings
    assert WarningCode.MISFIT not in {w.code for w in mine}


def test_a_warning_about_one_photo_must_name_it() -> None:
    with pytest.raises(ValueError, match="misfit"):
        SolverWarning.of(WarningCode.MISFIT, landmark=4)


def test_the_photo_order_numbers_the_two_roles_both_ways() -> None:
    for first in ROLES:
        order = PhotoOrder(first)
        assert (order.number(order.first), order.number(order.second)) == (1, 2)
        assert all(order.role(order.number(role)) == role for role in ROLES)
        assert order == problem.problem(tapped(first), SIGMA).order


# --- refusals -------------------------------------------------------------------------


def moved(taps: Taps, where: Callable[[Landmark], tuple[float, float]]) -> Taps:
    """``taps`` with each landmark moved to ``where`` it says."""
    landmarks = [
        tap.model_copy(update=dict(zip("xy", where(tap), strict=True))) for tap in taps.landmarks
    ]
    return taps.model_copy(update={"landmarks": landmarks})


def spoiled(marker: Role, whose: Role, reason: Reason) -> dict[Role, Taps | None]:
    """``tapped(marker)`` with ``whose`` taps made a layout refused for ``reason``."""
    taps = tapped(marker)
    mine = taps[whose]
    assert mine is not None
    if reason is Reason.COLLINEAR_LANDMARKS:
        mine = moved(mine, lambda tap: (40.0 * tap.id, 100.0 + 20.0 * tap.id))
    elif reason is Reason.REPEATED_LANDMARKS:
        fifth = mine.landmarks[4]
        mine = moved(mine, lambda tap: (fifth.x, fifth.y) if tap.id == 2 else (tap.x, tap.y))
    elif reason is Reason.EPIPOLE_ON_LANDMARK:
        third = mine.landmarks[2]
        mine = mine.model_copy(update={"friend": Mark(x=third.x, y=third.y)})
    else:  # landmarks on one line through the friend mark (not on it)
        mine = moved(mine, lambda tap: (300.0 + 30.0 * tap.id, 200.0 + 10.0 * tap.id))
        mine = mine.model_copy(update={"friend": Mark(x=270.0, y=190.0)})
    return taps | {whose: mine}


def refused(taps: dict[Role, Taps | None]) -> StoredAnswer:
    """The refusal of these taps as the sessions table keeps it (read back from its JSON)."""
    task = problem.problem(taps, SIGMA)
    misfits: dict[Role, list[int]] = {role: [] for role in ROLES}
    stored = problem.solved(task, PHOTOS, taps=taps, misfits=misfits)
    again = StoredAnswer.read(stored.as_json())
    assert again is not None
    assert again.error is not None, stored
    return again


# The refusals about one photo a session can meet, and whose photo each can be: the friend
# mark is in photo 1, the marker's (the landmarks of either photo may be repeated or collinear).
LAYOUTS = [
    (Reason.COLLINEAR_LANDMARKS, "either"),
    (Reason.REPEATED_LANDMARKS, "either"),
    (Reason.EPIPOLE_ON_LANDMARK, "marker"),
    (Reason.LANDMARKS_ON_EPIPOLAR_LINE, "marker"),
]


@pytest.mark.parametrize(("reason", "photos"), LAYOUTS)
@pytest.mark.parametrize("marker", ROLES)
def test_a_refusal_names_each_phones_photo_as_its_own(
    reason: Reason, photos: str, marker: Role
) -> None:
    for whose in ROLES if photos == "either" else (marker,):
        taps = spoiled(marker, whose, reason)
        stored = refused(taps)
        assert stored.error is not None
        assert (stored.error.reason, stored.error.photo) == (reason, 1 if whose == marker else 2)
        said = shown(taps, stored, SIGMA).answer_error
        assert said is not None
        for role, whose_photo in ((whose, "your photo"), (other(whose), "your friend's photo")):
            told = said[role]
            assert told.model_dump(exclude={"message", "reader"}) == stored.error.model_dump(
                exclude={"message", "reader"}
            )
            # Its reader, so that the phone can word it in its own language.
            assert told.reader == (told.photo if role == whose else 3 - (told.photo or 0))
            assert whose_photo in told.message, (role, told.message)
            assert "photo 1" not in told.message
            assert "photo 2" not in told.message


def test_every_reason_about_a_photo_is_covered() -> None:
    """The layouts above are every refusal whose photo is a parameter; the rest name a fixed
    photo (words of every reason: tests/solver/test_refusal_words.py)."""
    assert {reason for reason, _ in LAYOUTS} == REFUSAL_OF_ONE_PHOTO
    assert set(REFUSAL_PHOTO) == {Reason.CONFLICTING_INPUTS, Reason.FRIEND_AT_INFINITY}


@pytest.mark.parametrize("first", ROLES)
def test_a_refusal_of_a_fixed_photo_is_said_of_photo_1s_phone_as_its_own(first: Role) -> None:
    stored = StoredAnswer(error=Refusal.of(Reason.FRIEND_AT_INFINITY), first=first)
    said = shown(tapped(first), stored, SIGMA).answer_error
    assert said is not None
    assert said[first].message.endswith("at infinity in your photo; re-check the landmarks.")
    assert "at infinity in your friend's photo" in said[other(first)].message


def test_a_reworded_sentence_is_said_of_the_same_photo(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every sentence reworded into one naming "photo 2", as the old routing by regular
    expressions would have rewritten: each phone reads it as worded for its photo."""
    taps = spoiled("starter", "joiner", Reason.COLLINEAR_LANDMARKS)
    stored = refused(taps)
    monkeypatch.setattr(words, "refusal", lambda reason, _, *, reader=None: f"{reader}: photo 2")
    said = shown(taps, stored, SIGMA).answer_error
    assert said is not None
    assert [said[role].message for role in ("starter", "joiner")] == ["1: photo 2", "2: photo 2"]
    assert {said[role].photo for role in ROLES} == {2}
