"""From two participants' taps to the solver's input, and when there is enough to solve.

Landmarks are matched by id: #3 in the seeker's photo is #3 in the buddy's. Only ids
tapped in both photos count; they are solved in ascending id order. Every photo of a
session is taken by a phone, so the solver is told so (``Camera.phone()``): it then needs
fewer landmarks (docs/geometry.md), and the counts come from the solver itself
(``fewest_landmarks``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from shared_solver import Camera, SolverError, fewest_landmarks, solve

from .schemas import Taps

# Every photo of a session comes from a phone's camera.
PHONE = Camera.phone()


@dataclass(frozen=True)
class Problem:
    """What the solver is asked, in stored-photo pixels."""

    ids: list[int]
    points1: list[tuple[float, float]]
    points2: list[tuple[float, float]]
    epipole1: tuple[float, float] | None
    epipolar_line1: tuple[float, float, float] | None
    epipole2: tuple[float, float] | None

    def fewest(self, *, position: bool, cameras: bool = True) -> int:
        """Landmarks (common to both photos) the solver needs, phone cameras given (or,
        ``cameras=False``, without the camera model)."""
        return fewest_landmarks(
            buddy=self.epipole1 is not None,
            seeker=self.epipole2 is not None,
            line=self.epipolar_line1 is not None,
            cameras=cameras,
            position=position,
        )

    def landmarks_needed(self, result: Mapping[str, Any] | None = None) -> int:
        """How many more common landmarks until a position. Counted for phone cameras,
        unless ``result`` (the answer so far) had to do without the camera model: taps
        that fit no two phone photos are answered as the paper's projective geometry
        counts (four landmarks and the buddy: the curve, and one more for a position)."""
        projective = result is not None and result.get("camera_model") == "projective"
        return max(0, self.fewest(position=True, cameras=not projective) - len(self.ids))

    @property
    def solvable(self) -> bool:
        return len(self.ids) >= self.fewest(position=False)


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
            camera1=PHONE,
            camera2=PHONE,
        )
    except SolverError as error:
        return {"error": {"code": error.code.value, "message": error.message}}
    return {"result": result.model_dump(mode="json"), "landmark_ids": task.ids}
