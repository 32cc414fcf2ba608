"""Which phone is told what: a warning goes to the phones of the photo it is about (its code
and parameters), never by its sentence, so rewording a sentence moves it nowhere
(backend.taps.problem; a refusal: test_refusal_routing.py)."""

from __future__ import annotations

from typing import Any

import pytest

from backend.participants import ROLES, Role, other
from backend.taps import problem
from backend.taps.photo_order import PhotoOrder
from backend.taps.schemas import Landmark, Mark, Taps
from shared_solver import SolveResult, SolverWarning, WarningCode, words
from shared_solver.errors import WARNING_OF_ONE_PHOTO, WARNING_PHOTO
from tests.backend.test_sessions import scene

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

    def taps(points: Any) -> list[Landmark]:
        return [Landmark(id=i, x=float(x), y=float(y)) for i, (x, y) in enumerate(points, 1)]

    x, y = s.epipole1
    return {
        marker: Taps(landmarks=taps(s.landmarks1), friend=Mark(x=float(x), y=float(y))),
        other(marker): Taps(landmarks=taps(s.landmarks2)),
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
