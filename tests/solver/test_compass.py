"""Both phones' compass headings at the shutter (with their gravity): north in a camera's
frame, the turn they measure, the stretch of the level they point to with no landmark, a
point they sharpen with landmarks, and headings the landmarks contradict left out.

Scenes are the test bed's phone venues: world y is down, z north and x east, so a phone's
undisturbed heading is its lens axis's bearing (``testbed.scenes.Camera.heading``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from shared_solver import SolverError, SolveResult, draw_overlay, solve, words
from shared_solver.drawing.layout import answer_drawing
from shared_solver.minimal.gravity_and_one import north, rotation_about_vertical, turn_from_headings
from testbed.curves import distance_to
from testbed.phones import PhoneScene, heading_reading, phone_scene
from testbed.readings import LEVEL, assert_refused, down, exact_scenes, exif_of, phones_of, solved

EXACT_PX = 1e-6


def headed(
    scene: PhoneScene,
    landmarks: int,
    rng: np.random.Generator,
    *,
    compass_deg: float = 0.0,
    off_deg: float = 0.0,
    **options: object,
) -> SolveResult:
    """``testbed.readings.solved`` (noisy taps and gravity) with both phones' headings too,
    ``compass_deg`` of noise each; photo 1's heading ``off_deg`` more (a bent compass)."""
    return solved(
        scene,
        landmarks,
        rng,
        heading1=heading_reading(scene.camera1, compass_deg, rng) + off_deg,
        heading2=heading_reading(scene.camera2, compass_deg, rng),
        heading_sigma_deg=max(compass_deg, 1.0),
        **options,
    )


def test_north_and_the_turn_are_the_worlds() -> None:
    """North in each camera's frame is the world's z there, and the turn the two headings
    give is the one about the vertical that carries camera 1's frame onto camera 2's."""
    for scene in exact_scenes(30):
        for camera in (scene.camera1, scene.camera2):
            found = north(camera.down, math.radians(camera.heading))
            assert np.abs(found - camera.rotation[:, 2]).max() < 1e-12
        g1, g2 = scene.camera1.down, scene.camera2.down
        turn = turn_from_headings(
            g1, g2, math.radians(scene.camera1.heading), math.radians(scene.camera2.heading)
        )
        relative = scene.camera2.rotation @ scene.camera1.rotation.T
        assert np.abs(rotation_about_vertical(g1, g2, turn) - relative).max() < 1e-12


def test_straight_up_has_no_north() -> None:
    assert np.isnan(north(np.array([0.0, 0.0, 1.0]), 0.3)).all()


def test_exact_headings_keep_one_landmark_exact_and_are_used() -> None:
    for scene in exact_scenes(10):
        result = headed(scene, 1, np.random.default_rng(0))
        assert result.used_heading
        assert result.used_gravity
        assert result.epipole2 is not None
        assert np.abs(np.array(result.epipole2) - scene.epipole2).max() <= EXACT_PX


def test_no_landmark_gives_a_stretch_of_the_level_around_the_truth() -> None:
    """Exact taps and headings: the stretch is part of the level, the truth in its middle;
    a compass 10 degrees off moves it along the level, the level itself unchanged."""
    for scene in exact_scenes(10):
        result = headed(scene, 0, np.random.default_rng(0), compass_deg=0.0)
        assert result.method == "pinhole_level"
        assert result.used_heading
        assert result.curve2 is not None
        assert result.curve2_stretch is not None
        assert distance_to(result.curve2_stretch, scene.epipole2) <= 0.3
        for piece in result.curve2_stretch:
            assert max(distance_to(result.curve2, np.asarray(point)) for point in piece) <= 0.3
        ends = [np.array(piece)[[0, -1]] for piece in result.curve2_stretch]
        first, last = ends[0][0], ends[-1][1]
        # The truth halfway (within a few percent: the curve is not a circle in the photo).
        to_first = np.hypot(*(first - scene.epipole2))
        to_last = np.hypot(*(last - scene.epipole2))
        if all(0 < point[0] < scene.image_size2[0] for point in (first, last)):
            assert to_first == pytest.approx(to_last, rel=0.25)
        turned = headed(scene, 0, np.random.default_rng(0), off_deg=10.0)
        assert turned.curve2 == result.curve2
        assert turned.curve2_stretch is not None
        assert distance_to(turned.curve2_stretch, scene.epipole2) > 5.0


def test_without_both_headings_or_gravity_nothing_changes() -> None:
    scene = exact_scenes(1)[0]
    rng = np.random.default_rng(1)
    p = scene.landmarks1[:1]
    q = scene.landmarks2[:1]
    camera1, camera2 = exif_of(scene)
    common: dict[str, Any] = phones_of(scene) | {"camera1": camera1, "camera2": camera2}
    gravity: dict[str, Any] = {
        "gravity1": down(scene, 1, rng, 0.0),
        "gravity2": down(scene, 2, rng, 0.0),
    }
    before = solve(p, q, **common, **gravity).model_dump()
    assert solve(p, q, **common, **gravity, heading1=12.0).model_dump() == before
    # Headings without gravity: nothing says which way is level, so they are not used.
    five = phone_scene(np.random.default_rng(2), 5)
    p5, q5 = five.landmarks1 + 0.5, five.landmarks2 - 0.5
    phones: dict[str, Any] = phones_of(five)
    plain = solve(p5, q5, **phones).model_dump()
    assert solve(p5, q5, **phones, heading1=1.0, heading2=181.0).model_dump() == plain


def test_a_bent_compass_is_left_out_and_said() -> None:
    """Photo 1's heading 60 degrees off (steel beside the phone): three landmarks contradict
    it, and the answer is the one without headings, saying so."""
    rng = np.random.default_rng(47)
    dropped = 0
    for _ in range(10):
        scene = phone_scene(rng, 3)
        seed = int(rng.integers(1 << 30))
        options: dict[str, Any] = {
            "sigma": 2.0,
            "gravity_deg": 1.0,
            "compass_deg": 5.0,
            "cameras": exif_of(scene),
        }
        try:
            bent = headed(scene, 3, np.random.default_rng(seed), off_deg=60.0, **options)
        except SolverError:  # three noisy taps on one line: refused either way
            continue
        if not bent.used_heading:
            dropped += 1
            assert bent.warnings[0].code == "heading_disagrees"
            assert bent.used_gravity
    assert dropped >= 8


def test_headings_that_fit_are_kept_and_the_region_stays_honest() -> None:
    """One landmark, EXIF focal, taps 3 px, gravity 1 degree, compasses at 10 degrees."""
    rng = np.random.default_rng(48)
    held, kept, refused = [], 0, 0
    for _ in range(120):
        scene = phone_scene(rng, 1)
        try:
            result = headed(
                scene, 1, rng, sigma=3.0, gravity_deg=1.0, compass_deg=10.0, cameras=exif_of(scene)
            )
        except SolverError:  # the readings judged to contradict the landmark: a clear refusal
            refused += 1
            continue
        kept += result.used_heading
        if result.epipole2 is None or result.uncertainty is None:
            continue
        if result.uncertainty.covariance is None:
            continue
        offset = np.array(result.epipole2) - scene.epipole2
        covariance = np.array(result.uncertainty.covariance)
        held.append(offset @ np.linalg.solve(covariance, offset) <= 5.991)
    assert refused <= 3
    assert kept >= 114  # the test drops about 1 in 100 honest headings
    assert len(held) >= 100
    assert 0.88 <= np.mean(held) <= 0.995


@pytest.mark.parametrize(
    ("options", "code", "reason"),
    [
        ({"heading1": float("nan")}, "not_finite", "not_finite"),
        ({"heading2": [1.0, 2.0]}, "invalid_shape", "not_a_number"),
        ({"heading2": "north"}, "invalid_shape", "not_a_number"),
        ({"heading_sigma_deg": 0.0}, "invalid_parameter", "not_positive"),
        ({"heading_sigma_deg": 120.0}, "invalid_parameter", "not_an_angle"),
        ({"heading1_sigma_deg": 0.001}, "invalid_parameter", "not_an_angle"),
    ],
)
def test_bad_headings_are_refused_with_a_code(
    options: dict[str, Any], code: str, reason: str
) -> None:
    assert_refused(code, reason, **(LEVEL | {"heading1": 0.0, "heading2": 180.0} | options))


def test_the_stretch_is_drawn_bolder_on_the_band() -> None:
    scene = exact_scenes(1)[0]
    result = headed(scene, 0, np.random.default_rng(0), sigma=2.0, gravity_deg=1.0, compass_deg=5.0)
    assert result.curve2_stretch
    width, height = scene.image_size2
    drawing = answer_drawing(result, photo=2, size=(width, height))
    assert drawing.curve is not None
    assert drawing.curve.stretch == result.curve2_stretch
    assert drawing.curve.text == words.DRAWN_COMPASS_HINT
    plain = result.model_copy(update={"curve2_stretch": None})
    grey = np.full((height, width, 3), 128, np.uint8)
    with_stretch = draw_overlay(grey.copy(), result)
    without = draw_overlay(grey.copy(), plain)
    differs = np.any(with_stretch != without, axis=2)
    # Only near the stretch (its thicker line, and the label that moves to its middle).
    middle = np.array(result.curve2_stretch[0][len(result.curve2_stretch[0]) // 2])
    x, y = np.round(middle).astype(int)
    assert differs[y, x] or differs[max(y - 3, 0) : y + 4, max(x - 3, 0) : x + 4].any()
