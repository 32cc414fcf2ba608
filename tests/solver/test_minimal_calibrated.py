"""Exact minimal solvers for calibrated cameras: every root fits, the true rotation is a root.

Scenes are the test bed's phone scenes (``testbed.phones``): two phone cameras (focal ~3000
px, 4032x3024 landscape or 3024x4032 portrait) facing each other across a venue, landmarks
between them in front of both. Convention: ``X2 = R X1 + t``; ``b1`` points from friend 1
to friend 2 (frame 1), ``b2`` from friend 2 to friend 1 (frame 2), ``b2 = -R b1``.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
import pytest

from shared_solver.minimal.both_and_one import rotations_from_both
from shared_solver.minimal.epipole_and_three import rotations_from_three
from shared_solver.minimal.gravity_and_one import (
    rotation_about_vertical,
    rotations_from_gravity,
    turns_from_gravity,
)
from testbed.phones import phone_scene
from testbed.scenes import pixel

SCENES = 200
ROOT = 1e-9  # Frobenius distance of the true rotation from the nearest root
ORTHONORMAL = 1e-12
CONSTRAINT = 1e-10  # |q . R (b1 x p)| for unit rays
EXACT_PX = 1e-6


@dataclass(frozen=True)
class Scene:
    k2: np.ndarray  # (3, 3) intrinsics of camera 2
    rotation: np.ndarray  # (3, 3) relative rotation, X2 = R X1 + t
    b1: np.ndarray  # (3,) unit, towards friend 2 in frame 1
    b2: np.ndarray  # (3,) unit, towards friend 1 in frame 2
    rays1: np.ndarray  # (n, 3) rays K1^-1 (x, 1) of the landmarks' pixels
    rays2: np.ndarray
    e2: np.ndarray  # (2,) friend 1's pixel in photo 2
    gravity1: np.ndarray  # (3,) unit, down in frame 1
    gravity2: np.ndarray  # (3,) unit, down in frame 2


def axis_angle(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues: the rotation by ``angle`` about the unit ``axis``."""
    return np.asarray(cv2.Rodrigues(angle * np.asarray(axis, float))[0])


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    axis = rng.normal(size=3)
    return axis_angle(axis / np.linalg.norm(axis), rng.uniform(0.0, np.pi))


def half_turn(axis: np.ndarray) -> np.ndarray:
    return 2.0 * np.outer(axis, axis) - np.eye(3)


def scenes(seed: int, count: int = SCENES, n: int = 3) -> list[Scene]:
    """``count`` phone scenes of ``n`` landmarks, as rays and directions in each frame."""
    rng = np.random.default_rng(seed)
    found = []
    for _ in range(count):
        s = phone_scene(rng, n)
        one, two = s.camera1, s.camera2
        b1, b2 = one.rotation @ (two.centre - one.centre), two.rotation @ (one.centre - two.centre)
        rays1, rays2 = (
            np.column_stack([px, np.ones(n)]) @ np.linalg.inv(camera.intrinsics).T
            for camera, px in ((one, s.landmarks1), (two, s.landmarks2))
        )
        found.append(
            Scene(
                k2=two.intrinsics,
                rotation=two.rotation @ one.rotation.T,
                b1=b1 / np.linalg.norm(b1),
                b2=b2 / np.linalg.norm(b2),
                rays1=rays1,
                rays2=rays2,
                e2=s.epipole2,
                gravity1=one.down,
                gravity2=two.down,
            )
        )
    return found


def unit_rows(rays: np.ndarray) -> np.ndarray:
    return rays / np.linalg.norm(rays, axis=-1, keepdims=True)


def residuals(
    rotation: np.ndarray, b1: np.ndarray, rays1: np.ndarray, rays2: np.ndarray
) -> np.ndarray:
    """|q . R (b1 x p)| per landmark, for unit rays."""
    normals = np.cross(b1, unit_rows(rays1)) @ rotation.T
    return np.abs(np.einsum("ni,ni->n", unit_rows(rays2), normals))


def nearest(roots: list[np.ndarray], rotation: np.ndarray) -> tuple[float, np.ndarray]:
    errors = [float(np.linalg.norm(root - rotation)) for root in roots]
    best = int(np.argmin(errors))
    return errors[best], roots[best]


def assert_rotation(r: np.ndarray) -> None:
    assert np.abs(r.T @ r - np.eye(3)).max() <= ORTHONORMAL
    assert abs(np.linalg.det(r) - 1.0) <= ORTHONORMAL


def assert_one_landmark_roots(
    s: Scene, roots: list[np.ndarray], carried: tuple[np.ndarray, np.ndarray]
) -> None:
    """Every root a rotation that takes ``carried[0]`` to ``carried[1]`` and fits landmark 0;
    the true rotation is one of them, and it puts friend 1 at the exact pixel."""
    for r in roots:
        assert_rotation(r)
        assert np.abs(r @ carried[0] - carried[1]).max() <= 1e-12
        assert residuals(r, s.b1, s.rays1[:1], s.rays2[:1]).max() <= CONSTRAINT
    error, best = nearest(roots, s.rotation)
    assert error <= ROOT
    assert np.abs(pixel(s.k2 @ (-best @ s.b1)) - s.e2).max() <= EXACT_PX


def assert_same_roots(found: list[np.ndarray], expected: list[np.ndarray]) -> None:
    assert len(found) == len(expected)
    for r in expected:
        assert nearest(found, r)[0] <= ROOT
    for r in found:
        assert nearest(expected, r)[0] <= ROOT


def test_scenes_follow_the_convention() -> None:
    for s in scenes(1, count=20):
        assert np.allclose(s.b2, -s.rotation @ s.b1, atol=1e-12)
        assert residuals(s.rotation, s.b1, s.rays1, s.rays2).max() <= 1e-12


# --- friend 2's direction and three landmarks -------------------------------------------


def test_three_true_rotation_is_a_root_and_every_root_fits() -> None:
    counts = []
    for s in scenes(0):
        roots = rotations_from_three(s.b1, s.rays1, s.rays2)
        counts.append(len(roots))
        assert 2 <= len(roots) <= 8
        assert len(roots) % 2 == 0
        for r in roots:
            assert_rotation(r)
            assert residuals(r, s.b1, s.rays1, s.rays2).max() <= CONSTRAINT
        error, best = nearest(roots, s.rotation)
        assert error <= ROOT
        assert np.abs(pixel(s.k2 @ (-best @ s.b1)) - s.e2).max() <= EXACT_PX
    # Both real line pairs of the conic pencil occur: two and four intersection points.
    assert {4, 8} <= set(counts)


@pytest.mark.parametrize("axis", range(3))
@pytest.mark.parametrize("kind", ["identity", "about b1", "half turn", "random"])
def test_three_special_coordinates(axis: int, kind: str) -> None:
    """Axis-aligned baselines and special rotations: no division by a vanishing coordinate."""
    rng = np.random.default_rng(20 + axis)
    b1 = np.eye(3)[axis] * (-1.0) ** axis
    for _ in range(10):
        rotation = {
            "identity": np.eye(3),
            "about b1": axis_angle(b1, rng.uniform(0.0, 2 * np.pi)),
            "half turn": half_turn(np.eye(3)[(axis + 1) % 3]),
            "random": random_rotation(rng),
        }[kind]
        t = -rotation @ b1 * rng.uniform(1.0, 10.0)
        points = rng.normal(size=(3, 3)) * 3.0
        roots = rotations_from_three(b1, points, points @ rotation.T + t)
        assert nearest(roots, rotation)[0] <= ROOT
        for r in roots:
            assert_rotation(r)
            assert residuals(r, b1, points, points @ rotation.T + t).max() <= CONSTRAINT


def test_three_roots_come_in_half_turn_pairs_about_b1() -> None:
    for s in scenes(2, count=50):
        roots = rotations_from_three(s.b1, s.rays1, s.rays2)
        flip = half_turn(s.b1)
        for first, second in zip(roots[::2], roots[1::2], strict=True):
            assert np.abs(first @ flip - second).max() <= 1e-12
            # Same b2 = -R b1 for both members of a pair.
            assert np.abs(first @ s.b1 - second @ s.b1).max() <= 1e-12


def test_three_ignores_the_scale_of_rays() -> None:
    rng = np.random.default_rng(3)
    for s in scenes(3, count=20):
        scaled1 = s.rays1 * rng.uniform(0.01, 100.0, size=(3, 1))
        scaled2 = s.rays2 * rng.uniform(0.01, 100.0, size=(3, 1))
        assert_same_roots(
            rotations_from_three(s.b1, scaled1, scaled2),
            rotations_from_three(s.b1, s.rays1, s.rays2),
        )


def test_three_invariant_under_rotating_either_frame() -> None:
    rng = np.random.default_rng(4)
    for s in scenes(4, count=30):
        roots = rotations_from_three(s.b1, s.rays1, s.rays2)
        q = random_rotation(rng)
        turned1 = rotations_from_three(q @ s.b1, s.rays1 @ q.T, s.rays2)
        assert_same_roots(turned1, [r @ q.T for r in roots])
        turned2 = rotations_from_three(s.b1, s.rays1, s.rays2 @ q.T)
        assert_same_roots(turned2, [q @ r for r in roots])


def test_three_landmark_on_the_baseline_gives_no_roots() -> None:
    for s in scenes(5, count=10):
        rays1 = s.rays1.copy()
        rays1[1] = 2.5 * s.b1  # the landmark is in line with friend 2
        assert rotations_from_three(s.b1, rays1, s.rays2) == []


def test_three_landmarks_on_one_epipolar_plane_give_no_roots() -> None:
    rng = np.random.default_rng(6)
    for _ in range(10):
        r, t_dir = random_rotation(rng), rng.normal(size=3)
        b1 = t_dir / np.linalg.norm(t_dir)
        t = -r @ b1 * rng.uniform(10.0, 50.0)  # camera 2 at 10-50 m along b1
        side = np.cross(b1, rng.normal(size=3))  # the plane through the baseline and `side`
        points = np.array([s * b1 * 30.0 + w * side for s, w in rng.uniform(0.2, 0.8, (3, 2))])
        assert rotations_from_three(b1, points, points @ r.T + t) == []


def test_three_degenerate_inputs_do_not_raise() -> None:
    s = scenes(7, count=1)[0]
    zero = s.rays1.copy()
    zero[0] = 0.0
    assert rotations_from_three(s.b1, zero, s.rays2) == []
    assert rotations_from_three(np.zeros(3), s.rays1, s.rays2) == []
    same = np.repeat(s.rays1[:1], 3, axis=0)
    assert rotations_from_three(s.b1, same, np.repeat(s.rays2[:1], 3, axis=0)) == []


# --- both directions and one landmark ----------------------------------------------------


def test_both_true_rotation_is_one_of_exactly_two() -> None:
    for s in scenes(10):
        roots = rotations_from_both(s.b1, s.b2, s.rays1[0], s.rays2[0])
        assert len(roots) == 2
        assert_one_landmark_roots(s, roots, carried=(s.b1, -s.b2))
        # The two differ by a half turn about b2.
        assert np.abs(half_turn(s.b2) @ roots[0] - roots[1]).max() <= 1e-12


def test_both_invariant_under_rotating_frame_one() -> None:
    rng = np.random.default_rng(11)
    for s in scenes(11, count=30):
        roots = rotations_from_both(s.b1, s.b2, s.rays1[0], s.rays2[0])
        q = random_rotation(rng)
        turned = rotations_from_both(q @ s.b1, s.b2, q @ s.rays1[0], 7.0 * s.rays2[0])
        assert_same_roots(turned, [r @ q.T for r in roots])


@pytest.mark.parametrize("which", [1, 2])
def test_both_ray_along_its_baseline_gives_no_roots(which: int) -> None:
    s = scenes(12, count=1)[0]
    ray1 = 3.0 * s.b1 if which == 1 else s.rays1[0]
    ray2 = 0.5 * s.b2 if which == 2 else s.rays2[0]
    assert rotations_from_both(s.b1, s.b2, ray1, ray2) == []
    assert rotations_from_both(s.b1, s.b2, np.zeros(3), s.rays2[0]) == []


# --- friend 2's direction, both gravities and one landmark ---------------------------------


def test_gravity_true_rotation_is_a_root_and_every_root_fits() -> None:
    for s in scenes(20):
        roots = rotations_from_gravity(s.b1, s.gravity1, s.gravity2, s.rays1[0], s.rays2[0])
        assert 1 <= len(roots) <= 2
        assert_one_landmark_roots(s, roots, carried=(s.gravity1, s.gravity2))


def test_gravity_invariant_under_rotating_frame_one_and_scaling_rays() -> None:
    rng = np.random.default_rng(21)
    for s in scenes(21, count=30):
        roots = rotations_from_gravity(s.b1, s.gravity1, s.gravity2, s.rays1[0], s.rays2[0])
        q = random_rotation(rng)
        turned = rotations_from_gravity(
            2.0 * q @ s.b1, q @ s.gravity1, s.gravity2, q @ s.rays1[0], 7.0 * s.rays2[0]
        )
        assert_same_roots(turned, [r @ q.T for r in roots])


def test_gravity_without_a_landmark_leaves_friend_1_on_one_level() -> None:
    """Every turn about the vertical keeps friend 1 at the same angle from down in photo 2:
    the curve of zero landmarks is one level of the venue."""
    for s in scenes(22, count=20):
        turns = np.linspace(-np.pi, np.pi, 37)
        rotations = rotation_about_vertical(s.gravity1, s.gravity2, turns)
        assert rotations.shape == (37, 3, 3)
        assert np.abs(rotations @ s.gravity1 - s.gravity2).max() <= 1e-12
        friend1 = -rotations @ s.b1
        assert np.abs(friend1 @ s.gravity2 + s.b1 @ s.gravity1).max() <= 1e-12
        # The true pose is one of the turns.
        psi = turns_from_gravity(s.b1, s.gravity1, s.gravity2, s.rays1[0], s.rays2[0])
        assert (
            min(
                np.linalg.norm(rotation_about_vertical(s.gravity1, s.gravity2, t) - s.rotation)
                for t in psi
            )
            <= ROOT
        )


def test_gravity_gives_two_turns_or_none() -> None:
    s = scenes(23, count=1)[0]
    psi = turns_from_gravity(s.b1, s.gravity1, s.gravity2, s.rays1[0], s.rays2[0])
    assert len(psi) == 2
    assert all(-np.pi <= t <= np.pi for t in psi)
    # A ray in photo 2 almost straight down meets no turn's epipolar plane of a landmark
    # whose plane is steep: |C| > sqrt(A^2 + B^2).
    normal1 = np.cross(s.b1, s.rays1[0])
    assert abs(normal1 @ s.gravity1) > 0.01 * np.linalg.norm(normal1)
    level = np.cross(s.gravity2, [1.0, 0.0, 0.0])
    steep = s.gravity2 + 1e-6 * level / np.linalg.norm(level)
    assert turns_from_gravity(s.b1, s.gravity1, s.gravity2, s.rays1[0], steep) == []


def test_gravity_degenerate_inputs_give_no_roots() -> None:
    s = scenes(24, count=1)[0]
    # A landmark whose epipolar plane is level (its normal is vertical) fixes no turn.
    level_ray = np.cross(s.gravity1, s.b1)
    assert turns_from_gravity(s.b1, s.gravity1, s.gravity2, level_ray, s.rays2[0]) == []
    # A ray in photo 2 straight down fixes none either.
    assert turns_from_gravity(s.b1, s.gravity1, s.gravity2, s.rays1[0], s.gravity2) == []
    assert turns_from_gravity(s.b1, s.gravity1, s.gravity2, np.zeros(3), s.rays2[0]) == []
    assert turns_from_gravity(s.b1, s.gravity1, s.gravity2, s.b1, s.rays2[0]) == []
