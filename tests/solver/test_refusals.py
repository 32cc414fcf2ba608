"""Input that cannot be answered honestly is refused, with a stable code and a sentence."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest

from shared_solver import (
    ErrorCode,
    SolverError,
    epipole_conic,
    epipole_from_five,
    epipoles_from_six,
    fundamental_from_epipoles,
    solve,
)
from testbed.scenes import Scene, facing_scene, line_through, marks


@pytest.fixture
def scene() -> Scene:
    return facing_scene(np.random.default_rng(3), 8)


def refused(code: ErrorCode, call: Callable[[], object]) -> SolverError:
    with pytest.raises(SolverError) as caught:
        call()
    assert caught.value.code == code, caught.value.message
    assert caught.value.message
    assert caught.value.message[0].isupper() or caught.value.message[0].isdigit()
    return caught.value


def test_nan_and_infinity_are_refused(scene: Scene) -> None:
    p, q, e1 = scene.landmarks1.copy(), scene.landmarks2.copy(), scene.epipole1
    p[2, 1] = np.nan
    refused(ErrorCode.NOT_FINITE, lambda: solve(p, q, epipole1=e1))
    refused(ErrorCode.NOT_FINITE, lambda: epipole_from_five(e1, p[:5], q[:5]))
    refused(ErrorCode.NOT_FINITE, lambda: solve(scene.landmarks1, q, epipole1=[np.inf, 3.0]))
    refused(ErrorCode.NOT_FINITE, lambda: epipole_conic([1.0, np.inf], scene.landmarks1[:4], q[:4]))
    refused(ErrorCode.NOT_FINITE, lambda: solve(scene.landmarks1, q, image_size2=[np.nan, 4.0]))


def test_malformed_input_is_refused(scene: Scene) -> None:
    p, q, e1 = scene.landmarks1, scene.landmarks2, scene.epipole1
    refused(ErrorCode.INVALID_SHAPE, lambda: solve(np.hstack([p, p[:, :1]]), q, epipole1=e1))
    refused(ErrorCode.INVALID_SHAPE, lambda: solve(p.ravel(), q, epipole1=e1))
    refused(ErrorCode.INVALID_SHAPE, lambda: solve(p, q, epipole1=[1.0, 2.0, 3.0]))
    refused(ErrorCode.INVALID_SHAPE, lambda: solve([["a", "b"]] * 8, q, epipole1=e1))
    refused(ErrorCode.INVALID_SHAPE, lambda: solve(p[:6], q[:6], epipolar_line1=[0.0, 0.0, 1.0]))
    refused(ErrorCode.INVALID_SHAPE, lambda: solve(p, q, epipole1=e1, image_size1=[-640, 480]))
    refused(ErrorCode.INVALID_SHAPE, lambda: epipole_from_five([0.0, 0.0, 0.0], p[:5], q[:5]))
    refused(ErrorCode.TOO_MANY_LANDMARKS, lambda: epipole_from_five(e1, p[:6], q[:6]))


def test_mismatched_lengths_are_refused(scene: Scene) -> None:
    p, q, e1 = scene.landmarks1, scene.landmarks2, scene.epipole1
    error = refused(ErrorCode.MISMATCHED_LENGTHS, lambda: solve(p, q[:7], epipole1=e1))
    assert "8" in error.message
    assert "7" in error.message
    refused(
        ErrorCode.MISMATCHED_LENGTHS,
        lambda: fundamental_from_epipoles(e1, scene.epipole2, p[:4], q[:3]),
    )
    refused(ErrorCode.MISMATCHED_LENGTHS, lambda: solve(p, q, epipole1=e1, landmark_ids=[1, 2]))


@pytest.mark.parametrize(("given", "landmarks"), [("e1", 3), ("line", 5), ("none", 6), ("both", 2)])
def test_too_few_landmarks_are_refused(scene: Scene, given: str, landmarks: int) -> None:
    kwargs = marks(scene, given, math.atan2(0.5, 1.0))
    error = refused(
        ErrorCode.TOO_FEW_LANDMARKS,
        lambda: solve(scene.landmarks1[:landmarks], scene.landmarks2[:landmarks], **kwargs),
    )
    assert str(landmarks) in error.message


def test_too_many_landmarks_are_refused() -> None:
    many = facing_scene(np.random.default_rng(1), 300)
    refused(
        ErrorCode.TOO_MANY_LANDMARKS,
        lambda: solve(many.landmarks1, many.landmarks2, epipole1=many.epipole1),
    )


@pytest.mark.parametrize("photo", [1, 2])
def test_repeated_landmarks_are_refused(scene: Scene, photo: int) -> None:
    p, q = scene.landmarks1.copy(), scene.landmarks2.copy()
    moved = p if photo == 1 else q
    moved[4] = moved[1] + 0.3  # within a finger's precision (tap_sigma 2 px)
    error = refused(ErrorCode.REPEATED_LANDMARKS, lambda: solve(p, q, epipole1=scene.epipole1))
    assert "#2" in error.message
    assert "#5" in error.message
    assert f"photo {photo}" in error.message
    exact = moved.copy()
    exact[4] = exact[1]
    args = (exact, q) if photo == 1 else (p, exact)
    refused(
        ErrorCode.REPEATED_LANDMARKS,
        lambda: epipole_from_five(scene.epipole1, args[0][:5], args[1][:5]),
    )


def test_landmark_numbers_people_see_are_used_in_messages(scene: Scene) -> None:
    p = scene.landmarks1.copy()
    p[3] = p[0]
    error = refused(
        ErrorCode.REPEATED_LANDMARKS,
        lambda: solve(
            p,
            scene.landmarks2,
            epipole1=scene.epipole1,
            landmark_ids=[10, 11, 12, 13, 14, 15, 16, 17],
        ),
    )
    assert "#10" in error.message
    assert "#13" in error.message


@pytest.mark.parametrize("photo", [1, 2])
def test_collinear_landmarks_are_refused(scene: Scene, photo: int) -> None:
    t = np.linspace(0.0, 1.0, 6)
    row = np.column_stack([100 + 900 * t, 200 + 500 * t]) + np.array(
        [[0, 0.3], [0, -0.2], [0, 0.1], [0, 0.0], [0, -0.3], [0, 0.2]]
    )
    p, q = (row, scene.landmarks2[:6]) if photo == 1 else (scene.landmarks1[:6], row)
    friend2 = np.array([700.0, 900.0])  # well off that row
    refused(ErrorCode.COLLINEAR_LANDMARKS, lambda: solve(p, q, epipole1=friend2))
    exact_row = np.column_stack([100 + 900 * t, 200 + 500 * t])[:5]
    args = (exact_row, q[:5]) if photo == 1 else (p[:5], exact_row)
    refused(ErrorCode.COLLINEAR_LANDMARKS, lambda: epipole_from_five(friend2, *args))


def test_friend2_on_a_landmark_is_refused(scene: Scene) -> None:
    p, q = scene.landmarks1, scene.landmarks2
    error = refused(ErrorCode.EPIPOLE_ON_LANDMARK, lambda: solve(p, q, epipole1=p[2] + 0.4))
    assert "#3" in error.message
    refused(ErrorCode.EPIPOLE_ON_LANDMARK, lambda: epipole_from_five(p[2], p[:5], q[:5]))
    refused(ErrorCode.EPIPOLE_ON_LANDMARK, lambda: epipole_conic(p[0], p[:4], q[:4]))
    refused(
        ErrorCode.EPIPOLE_ON_LANDMARK,
        lambda: solve(p, q, epipole1=scene.epipole1, epipole2=q[5]),
    )


def test_landmarks_all_on_one_line_through_friend2_are_refused(scene: Scene) -> None:
    e1 = scene.epipole1
    along = e1 + np.outer([-400, -250, -100, 80, 200, 320], [0.8, 0.6])
    error = refused(
        ErrorCode.LANDMARKS_ON_EPIPOLAR_LINE,
        lambda: solve(along, scene.landmarks2[:6], epipole1=e1),
    )
    assert "line through your friend" in error.message
    refused(
        ErrorCode.LANDMARKS_ON_EPIPOLAR_LINE,
        lambda: epipole_from_five(e1, along[:5], scene.landmarks2[:5]),
    )


def test_conflicting_and_missing_taps_are_refused(scene: Scene) -> None:
    p, q = scene.landmarks1, scene.landmarks2
    refused(
        ErrorCode.CONFLICTING_INPUTS,
        lambda: solve(
            p, q, epipole1=scene.epipole1, epipolar_line1=line_through(scene.epipole1, 0.0)
        ),
    )
    refused(ErrorCode.MISSING_EPIPOLE1, lambda: solve(p, q, epipole2=scene.epipole2))


@pytest.mark.parametrize("sigma", [0.0, -1.0, float("nan")])
def test_bad_tap_sigma_is_refused(scene: Scene, sigma: float) -> None:
    refused(
        ErrorCode.INVALID_PARAMETER,
        lambda: solve(scene.landmarks1, scene.landmarks2, epipole1=scene.epipole1, tap_sigma=sigma),
    )


def test_unknown_five_point_method_is_refused(scene: Scene) -> None:
    refused(
        ErrorCode.INVALID_PARAMETER,
        lambda: epipole_from_five(
            scene.epipole1,
            scene.landmarks1[:5],
            scene.landmarks2[:5],
            method="magic",  # type: ignore[arg-type]
        ),
    )


def test_landmarks_on_one_plane_without_friend2_are_refused() -> None:
    """Without e1 a plane of landmarks does not fix the geometry: refuse, do not guess."""
    floor = facing_scene(np.random.default_rng(8), 10, planar=True)
    error = refused(
        ErrorCode.DEGENERATE_CONFIGURATION, lambda: solve(floor.landmarks1, floor.landmarks2)
    )
    assert "tap your friend" in error.message
    # With friend 2 marked the same landmarks are enough.
    assert solve(floor.landmarks1, floor.landmarks2, epipole1=floor.epipole1).method == "planar"


def test_both_epipoles_with_landmarks_on_too_few_epipolar_lines_are_refused(scene: Scene) -> None:
    """Three landmarks, two on one epipolar line: the pencil homography is not fixed."""
    e1, e2 = scene.epipole1, scene.epipole2
    p = e1 + np.array([[200.0, 50.0], [400.0, 100.0], [-150.0, 220.0]])
    q = e2 + np.array([[-210.0, 40.0], [-420.0, 80.0], [160.0, 200.0]])
    refused(ErrorCode.DEGENERATE_CONFIGURATION, lambda: fundamental_from_epipoles(e1, e2, p, q))


def test_six_point_refuses_bad_lines(scene: Scene) -> None:
    refused(
        ErrorCode.INVALID_SHAPE,
        lambda: epipoles_from_six([0.0, 0.0, 3.0], scene.landmarks1[:6], scene.landmarks2[:6]),
    )
    refused(
        ErrorCode.TOO_FEW_LANDMARKS,
        lambda: epipoles_from_six(
            line_through(scene.epipole1, 0.0), scene.landmarks1[:5], scene.landmarks2[:5]
        ),
    )
