"""A refusal is its code, its reason and parameters, and a sentence worded from them by one
function (shared_solver.words.refusal) for its reader: a script reads "photo 1" and "photo
2", the phone of a photo "your photo" and "your friend's photo"."""

from __future__ import annotations

import re
from typing import Literal

import pytest

from shared_solver import ErrorCode, Reason, Refusal, SolverError, words
from shared_solver.errors import (
    CODE,
    REFUSAL_OF_ONE_PHOTO,
    REFUSAL_PARAMETERS,
    REFUSAL_PHOTO,
    Parameters,
)

# A value of each parameter (made up: the wording is under test).
SAMPLE: Parameters = {
    "landmark": 3,
    "landmarks": (2, 5),
    "count": 4,
    "counts": (5, 6),
    "minimum": 5,
    "maximum": 256,
    "marked": "point",
    "field": "points2",
    "shape": (3, 3),
    "finest_px": 1e-6,
    "largest_px": 1e6,
    "most_elongated": 1e4,
    "finest_deg": 0.01,
    "largest_deg": 30.0,
    "detail": "Input should be 'phone'.",
}
PHOTO = re.compile(r"\b[Pp]hoto [12]\b")


def parameters(reason: Reason, photo: Literal[1, 2] = 2) -> Parameters:
    """The parameters ``reason``'s sentence names, about ``photo`` when it is one photo's."""
    given: dict[str, object] = {**SAMPLE, "photo": photo}
    names = REFUSAL_PARAMETERS.get(reason, ())
    return Parameters(**{name: given[name] for name in names})  # type: ignore[typeddict-item]


def test_every_reason_is_one_codes_and_every_code_has_one() -> None:
    assert set(CODE) == set(Reason)
    assert set(CODE.values()) == set(ErrorCode)
    # A code refused one way only is its own reason.
    for code in ErrorCode:
        reasons = [reason for reason, of in CODE.items() if of is code]
        assert len(reasons) > 1 or reasons == [Reason(code.value)]


@pytest.mark.parametrize("reason", Reason)
def test_every_reason_is_worded_for_a_script_and_for_each_phone(reason: Reason) -> None:
    refusal = Refusal.of(reason, **parameters(reason))
    assert refusal.code is CODE[reason]
    said = {reader: refusal.said_to(reader).message for reader in (None, 1, 2)}
    assert said[None] == refusal.message == SolverError(reason, **parameters(reason)).message
    assert "your photo" not in said[None].lower()
    for reader in (1, 2):
        # A phone reads no photo by number: each named photo is "your" or "your friend's".
        assert not PHOTO.search(said[reader]), said[reader]
        for number in (1, 2):
            whose = "your photo" if number == reader else "your friend's photo"
            named = re.search(rf"\b[Pp]hoto {number}\b", said[None]) is not None
            assert (whose in said[reader].lower()) == named, (said[None], said[reader])


@pytest.mark.parametrize("reason", sorted(REFUSAL_OF_ONE_PHOTO))
@pytest.mark.parametrize(("photo", "other"), [(1, 2), (2, 1)])
def test_a_layout_refusal_names_the_photo_it_is_about(
    reason: Reason, photo: Literal[1, 2], other: Literal[1, 2]
) -> None:
    refusal = Refusal.of(reason, **parameters(reason, photo))
    assert refusal.photo == photo
    assert f"photo {photo}" in refusal.message
    assert "your photo" in refusal.said_to(photo).message
    assert "your friend's photo" in refusal.said_to(other).message


def test_a_refusal_about_one_photo_must_name_it() -> None:
    with pytest.raises(ValueError, match=r"'collinear_landmarks' lacks .* 'photo'"):
        Refusal.of(Reason.COLLINEAR_LANDMARKS)
    assert Refusal.of(Reason.FRIEND_AT_INFINITY).photo == REFUSAL_PHOTO[Reason.FRIEND_AT_INFINITY]


@pytest.mark.parametrize("reason", sorted(REFUSAL_PARAMETERS))
def test_each_parameter_a_reason_names_is_needed(reason: Reason) -> None:
    """The declared parameters are the ones its sentence says (docs/api.md lists them)."""
    for name in REFUSAL_PARAMETERS[reason]:
        given = parameters(reason)
        del given[name]  # type: ignore[misc]
        if (reason, name) == (Reason.TOO_FEW_LANDMARKS, "marked"):
            assert words.refusal(reason, given).endswith("are needed here.")
            continue
        with pytest.raises(ValueError, match=f"'{name}'"):
            Refusal.of(reason, **given)


def test_a_parameter_a_reason_does_not_name_is_refused() -> None:
    with pytest.raises(ValueError, match="landmark"):
        Refusal.of(Reason.COLLINEAR_LANDMARKS, photo=1, landmark=3)


def test_the_script_sentences_are_the_ones_written_down() -> None:
    """What POST /api/solve answered before refusals had parameters, word for word."""
    assert Refusal.of(Reason.REPEATED_LANDMARKS, landmarks=(2, 5), photo=2).message == (
        "Landmarks #2 and #5 are at the same place in photo 2; each landmark must be a "
        "different spot."
    )
    assert Refusal.of(Reason.MISMATCHED_LENGTHS, counts=(5, 6)).message == (
        "Photo 1 has 5 landmarks and photo 2 has 6; mark the same ones in both."
    )
    assert Refusal.of(Reason.MISMATCHED_LENGTHS, counts=(5, 6)).said_to(2).message == (
        "Your friend's photo has 5 landmarks and your photo has 6; mark the same ones in both."
    )
    assert Refusal.of(Reason.TOO_FEW_LANDMARKS, count=4, minimum=5).message == (
        "4 landmarks marked; at least 5 are needed here."
    )
