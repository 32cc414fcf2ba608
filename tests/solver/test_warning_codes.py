"""An answer's warnings are codes with parameters, each worded by one function
(shared_solver.words.warning): the sentences people read are the ones written down."""

from __future__ import annotations

import pytest

from shared_solver import SolveResult, SolverWarning, WarningCode, words
from shared_solver.errors import WARNING_MEANING, WARNING_OF_ONE_PHOTO, WARNING_PHOTO


@pytest.mark.parametrize(
    ("warning", "sentence"),
    [
        (SolverWarning.of(WarningCode.BEHIND_YOU), words.BEHIND_YOU),
        (SolverWarning.of(WarningCode.MARKS_DISAGREE), words.MARKS_DISAGREE),
        (
            SolverWarning.of(WarningCode.MISTAPPED, landmark=3, distance_px=41.4),
            "Landmark #3 looks mis-tapped (about 41 px from where the others put it), so the "
            "answer leaves it out. Re-check #3 in both photos.",
        ),
        (
            SolverWarning.of(WarningCode.OUTSIDE_PHOTO, distance_px=120.0, side="up"),
            "Your friend is outside this photo, about 120 px beyond its up edge: look up.",
        ),
        (
            SolverWarning.of(WarningCode.MISFIT, photo=1, landmark=4),
            "#4 does not fit the others: check it in both photos.",
        ),
        (
            SolverWarning.of(WarningCode.NO_MARGIN, marked="line"),
            "This position has no reliable error margin; to get one, tap your friend instead "
            "of a line, or add a landmark.",
        ),
    ],
)
def test_a_warning_says_its_sentence(warning: SolverWarning, sentence: str) -> None:
    assert warning.message == sentence


def test_the_photo_a_warning_is_about_comes_with_its_code() -> None:
    assert SolverWarning.of(WarningCode.UNCERTAIN).photo == 2
    assert SolverWarning.of(WarningCode.CAMERA_MODEL_UNSURE).photo is None
    assert SolverWarning.of(WarningCode.MISFIT, photo=1, landmark=2).told_to(1)
    assert not SolverWarning.of(WarningCode.BEHIND_YOU).told_to(1)
    assert not set(WARNING_PHOTO) & WARNING_OF_ONE_PHOTO
    assert set(WARNING_MEANING) == set(WarningCode)


@pytest.mark.parametrize(
    "code", [WarningCode.MISTAPPED, WarningCode.OUTSIDE_PHOTO, WarningCode.AMBIGUOUS]
)
def test_a_sentence_missing_its_parameters_is_refused(code: WarningCode) -> None:
    with pytest.raises(ValueError, match=code.value):
        words.warning(code)


def test_warnings_survive_the_answers_json() -> None:
    warned = [
        SolverWarning.of(WarningCode.OUTSIDE_PHOTO, distance_px=80.0, side="left"),
        SolverWarning.of(WarningCode.AMBIGUOUS, marked="none"),
    ]
    result = SolveResult(
        method="conic", landmark_count=4, tap_sigma=1.0, epipole2=None, epipole2_h=None,
        epipole1=None, epipole1_h=None, quality="poor", warnings=warned,
    )  # fmt: skip
    dumped = result.model_dump(mode="json")
    assert dumped["warnings"][0]["code"] == "outside_photo"
    assert dumped["warnings"][0]["side"] == "left"
    assert SolveResult.model_validate(dumped).warnings == warned
