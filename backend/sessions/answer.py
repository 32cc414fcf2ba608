"""From two participants' taps to the solver's input, and when there is enough to solve.

Landmarks are matched by id: #3 in the seeker's photo is #3 in the buddy's. Only ids
tapped in both photos count; they are solved in ascending id order.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from shared_solver import SolverError, solve

from .schemas import Taps

# Fewest common landmarks for a position, by what the friends marked (docs/geometry.md).
_FOR_A_POSITION = {"both": 3, "buddy": 5, "line": 6, "none": 7}
# Fewest for any answer at all: with the buddy marked, 4 give the curve the seeker is on.
_FOR_AN_ANSWER = {"both": 3, "buddy": 4, "line": 6, "none": 7}


@dataclass(frozen=True)
class Problem:
    """What the solver is asked, in stored-photo pixels."""

    ids: list[int]
    points1: list[tuple[float, float]]
    points2: list[tuple[float, float]]
    epipole1: tuple[float, float] | None
    epipolar_line1: tuple[float, float, float] | None
    epipole2: tuple[float, float] | None

    @property
    def given(self) -> str:
        if self.epipole1 is not None:
            return "both" if self.epipole2 is not None else "buddy"
        return "line" if self.epipolar_line1 is not None else "none"

    @property
    def landmarks_needed(self) -> int:
        return max(0, _FOR_A_POSITION[self.given] - len(self.ids))

    @property
    def solvable(self) -> bool:
        return len(self.ids) >= _FOR_AN_ANSWER[self.given]


def problem(seeker: Taps | None, buddy: Taps | None) -> Problem:
    """The common landmarks and the friends' marks. The seeker's photo is photo 1."""
    seeker, buddy = seeker or Taps(), buddy or Taps()
    mine = {tap.id: (tap.x, tap.y) for tap in seeker.landmarks}
    theirs = {tap.id: (tap.x, tap.y) for tap in buddy.landmarks}
    ids = sorted(mine.keys() & theirs.keys())
    return Problem(
        ids=ids,
        points1=[mine[i] for i in ids],
        points2=[theirs[i] for i in ids],
        epipole1=seeker.epipole1,
        epipolar_line1=seeker.epipolar_line1 if seeker.epipole1 is None else None,
        # The seeker's mark in photo 2 only means something with the buddy's in photo 1.
        epipole2=buddy.epipole2 if seeker.epipole1 is not None else None,
    )


def answer(
    task: Problem,
    *,
    tap_sigma: float,
    image_size1: tuple[int, int],
    image_size2: tuple[int, int],
) -> dict[str, Any]:
    """``{"result": ..., "landmark_ids": ...}`` or ``{"error": {"code", "message"}}``."""
    try:
        result = solve(
            task.points1,
            task.points2,
            epipole1=task.epipole1,
            epipole2=task.epipole2,
            epipolar_line1=task.epipolar_line1,
            tap_sigma=tap_sigma,
            image_size1=image_size1,
            image_size2=image_size2,
            landmark_ids=task.ids,
        )
    except SolverError as error:
        return {"error": {"code": error.code.value, "message": error.message}}
    return {"result": result.model_dump(mode="json"), "landmark_ids": task.ids}
