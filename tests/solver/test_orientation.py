"""Oriented answers: in front of friend 2, behind them, or far off to one side."""

from __future__ import annotations

import numpy as np
import pytest

from shared_solver import draw_overlay
from testbed.scenes import Camera, Scene, facing_scene, in_photo, look_at, solved, tap

INTRINSICS = np.array([[1400.0, 0.0, 800.0], [0.0, 1400.0, 600.0], [0.0, 0.0, 1.0]])
SIZE = (1600, 1200)


def scene_with(centre2: np.ndarray, target2: np.ndarray, points: np.ndarray) -> Scene:
    """Friend 1 at the origin looking at friend 2; friend 2 at ``centre2`` looking at
    ``target2``; the landmarks that both see."""
    camera1 = Camera(INTRINSICS, *look_at(np.zeros(3), centre2 + np.array([2.0, 1.0, 0.0])))
    camera2 = Camera(INTRINSICS, *look_at(centre2, target2))
    seen = in_photo(camera1, points, SIZE) & in_photo(camera2, points, SIZE)
    return Scene(camera1, camera2, points[seen][:8], SIZE, SIZE)


def turned_away(rng: np.random.Generator) -> Scene:
    """Friend 2 photographs the far side: friend 1 is behind friend 2's camera."""
    centre2 = np.array([0.0, 0.0, 40.0])
    points = centre2 + np.column_stack(
        [rng.uniform(-8, 8, 200), rng.uniform(-4, 4, 200), rng.uniform(8, 30, 200)]
    )
    return scene_with(centre2, centre2 + np.array([0.0, 0.0, 40.0]), points)


def sideways(rng: np.random.Generator) -> Scene:
    """Friend 2 looks at right angles to the line between them: friend 1 is at infinity."""
    centre2 = np.array([0.0, 0.0, 40.0])
    points = np.column_stack(
        [rng.uniform(8, 25, 300), rng.uniform(-4, 4, 300), rng.uniform(28, 52, 300)]
    )
    return scene_with(centre2, centre2 + np.array([30.0, 0.0, 0.0]), points)


def true_direction(s: Scene) -> np.ndarray:
    """The oriented epipole P2 C1 (its sign is the truth this module tests)."""
    c = s.camera2
    return c.intrinsics @ (c.rotation @ s.camera1.centre + c.translation)


@pytest.mark.parametrize("seed", range(10))
def test_friend1_behind_friend2_is_reported_as_behind(seed: int) -> None:
    s = turned_away(np.random.default_rng(seed))
    assert len(s.points) == 8
    assert true_direction(s)[2] < 0
    result = solved(s)
    assert result.epipole2 is None  # nowhere in the photo is right
    assert result.epipole2_h is not None
    assert result.epipole2_h[2] < 0
    assert any("behind you" in w.message for w in result.warnings)
    assert result.uncertainty is not None
    assert result.uncertainty.ellipse is None
    assert result.quality != "poor"  # a sure answer: turn around


@pytest.mark.parametrize("seed", range(10))
def test_friend1_at_right_angles_gets_the_right_direction(seed: int) -> None:
    s = sideways(np.random.default_rng(seed))
    truth = true_direction(s)
    assert abs(truth[2]) < 1e-9 * np.linalg.norm(truth)
    result = solved(s)
    assert result.epipole2 is None
    assert result.epipole2_h is not None
    x, y, _ = result.epipole2_h
    assert np.array([x, y]) @ truth[:2] > 0.999 * np.hypot(x, y) * np.linalg.norm(truth[:2])
    assert any("far off" in w.message for w in result.warnings)


def test_facing_friends_are_never_told_to_turn_around() -> None:
    rng = np.random.default_rng(9)
    told = 0
    for trial in range(300):
        n = 5 if trial % 2 else 8
        s = facing_scene(rng, n)
        taps = tap(s, 1.0, rng)
        result = solved(s, taps, tap_sigma=1.0)
        told += any("behind you" in w.message for w in result.warnings)
    assert told == 0


def test_photo_2_says_behind_instead_of_marking_a_spot() -> None:
    s = turned_away(np.random.default_rng(3))
    result = solved(s)
    photo = np.full((SIZE[1], SIZE[0], 3), 90, np.uint8)
    drawn = draw_overlay(photo, result, photo=2)
    changed = np.any(drawn != photo, axis=2)
    rows = np.flatnonzero(changed.any(axis=1))
    assert rows.size > 0
    assert rows.max() < SIZE[1] * 0.15  # only the banner at the top: no star anywhere
    unsure = result.model_copy(update={"quality": "poor"})
    assert not np.array_equal(draw_overlay(photo, unsure, photo=2), drawn)  # other words
