"""Re-anchoring a live view: a frame from where the photo was taken gives how the phone has
turned, and the video's focal length; a frame of somewhere else is refused.

Frames are rendered (``testbed.live``): the hall of the photo, the camera turned, brighter
or darker, with moving figures pasted over it. The marker's error is graded where it
matters, on screen: the direction a photo pixel is drawn in against its true one.
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from shared_solver import SolverError
from shared_solver.matching import reanchor as matching
from shared_solver.matching.reanchor import frame_focal, reanchor
from testbed.live import Hall, live_view, marker_error_deg, rendered_hall


@pytest.fixture(scope="module")
def hall() -> Hall:
    return rendered_hall(3)


def test_the_frame_focal_length_of_a_rotating_camera_is_exact() -> None:
    rng = np.random.default_rng(1)
    for _ in range(20):
        f_photo, f_frame = rng.uniform(1500, 3000), rng.uniform(500, 1200)
        k_photo = np.array([[f_photo, 0, 960], [0, f_photo, 1280], [0, 0, 1.0]])
        k_frame = np.array([[f_frame, 0, 360], [0, f_frame, 480], [0, 0, 1.0]])
        axis = rng.normal(size=3)
        turn = cv2.Rodrigues(axis / np.linalg.norm(axis) * rng.uniform(0.05, 0.6))[0]
        homography = k_frame @ turn @ np.linalg.inv(k_photo) * rng.uniform(0.1, 10)
        found = frame_focal(homography, k_photo, np.array([360.0, 480.0]))
        assert found == pytest.approx(f_frame, rel=1e-9)


@pytest.mark.parametrize(
    ("turn_deg", "gain", "crowd", "zoom"),
    [(20.0, 0.5, 40, 1.2), (30.0, 1.6, 80, 1.0)],
)
def test_a_turned_frame_puts_the_marker_within_a_third_of_a_degree(
    hall: Hall, turn_deg: float, gain: float, crowd: int, zoom: float
) -> None:
    view = live_view(
        hall,
        np.random.default_rng(int(turn_deg)),
        turn_deg=turn_deg,
        gain=gain,
        crowd=crowd,
        zoom=zoom,
    )
    found = reanchor(hall.photo, view.frame, hall.camera.intrinsics[0, 0])
    assert marker_error_deg(hall, view, found.rotation) < 0.3
    assert found.frame_focal_px == pytest.approx(view.camera.intrinsics[0, 0], rel=0.01)
    assert found.degrees == pytest.approx(turn_deg, abs=1.0)
    assert found.residual_px < 1.0


def test_a_frame_blurred_by_a_fast_turn_is_matched_at_half_its_size(hall: Hall) -> None:
    """A 15 px motion blur (a phone turning as the frame is exposed): refused at the
    frame's size, matched once both images are halved, the focal length in the frame's own
    pixels."""
    view = live_view(hall, np.random.default_rng(0), turn_deg=30.0, crowd=40, blur_px=15)
    focal = hall.camera.intrinsics[0, 0]
    grey = np.asarray(cv2.cvtColor(view.frame, cv2.COLOR_BGR2GRAY), np.uint8)
    with pytest.raises(SolverError):
        matching._reanchored(hall.photo, grey, focal, None, 960)  # the first try alone
    found = reanchor(hall.photo, view.frame, focal)
    assert marker_error_deg(hall, view, found.rotation) < 0.3
    assert found.frame_focal_px == pytest.approx(view.camera.intrinsics[0, 0], rel=0.01)


def test_a_frame_of_another_place_is_refused(hall: Hall) -> None:
    """The other end of the hall (where the friend stands): the same hall, no turn of the
    photo's place."""
    view = live_view(hall, np.random.default_rng(0), turn_deg=0.0, place=hall.other)
    with pytest.raises(SolverError) as refused:
        reanchor(hall.photo, view.frame, hall.camera.intrinsics[0, 0])
    assert refused.value.code == "no_solution"
    assert refused.value.refusal.reason == "frame_not_matched"
    assert refused.value.message


def test_a_frame_with_nothing_to_match_is_refused(hall: Hall) -> None:
    blank = np.full((960, 720, 3), 90, np.uint8)
    with pytest.raises(SolverError):
        reanchor(hall.photo, blank, hall.camera.intrinsics[0, 0])


def test_a_frame_that_is_no_rotation_is_refused(hall: Hall) -> None:
    """The photo itself, stretched sideways: a homography fits it, no turn does."""
    stretch = np.array([[0.45, 0.08, 0.0], [0.0, 0.3, 0.0], [0.0, 0.0, 1.0]])
    frame = np.asarray(cv2.warpPerspective(hall.photo, stretch, (720, 960)), np.uint8)
    with pytest.raises(SolverError):
        reanchor(hall.photo, frame, hall.camera.intrinsics[0, 0])
