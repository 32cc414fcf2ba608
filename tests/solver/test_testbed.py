"""The test scenes are what they claim: phone photos as phones take them, and the other kinds."""

from __future__ import annotations

import math

import numpy as np
import pytest

from testbed.kinds import SCENE_KINDS
from testbed.phones import PhoneScene, phone_scene
from testbed.scenes import Scene, in_photo, tap

LANDMARKS = 12
SEEDS = range(40)
FRAME_DIAGONAL_MM = math.hypot(36.0, 24.0)


def phone(seed: int, **options: float) -> PhoneScene:
    return phone_scene(np.random.default_rng(seed), LANDMARKS, **options)


def same(a: Scene, b: Scene) -> bool:
    cameras = [(a.camera1, b.camera1), (a.camera2, b.camera2)]
    arrays = [(x.intrinsics, y.intrinsics) for x, y in cameras]
    arrays += [(x.rotation, y.rotation) for x, y in cameras]
    arrays += [(x.translation, y.translation) for x, y in cameras] + [(a.points, b.points)]
    sizes = (a.image_size1, a.image_size2) == (b.image_size1, b.image_size2)
    return sizes and all(np.array_equal(x, y) for x, y in arrays)


def epipoles_seen(s: Scene) -> tuple[bool, bool]:
    """Whether camera 2 is in photo 1, and camera 1 in photo 2."""
    return (
        bool(in_photo(s.camera1, s.camera2.centre[None], s.image_size1)[0]),
        bool(in_photo(s.camera2, s.camera1.centre[None], s.image_size2)[0]),
    )


def kind_scenes(kind: str, seeds: range = SEEDS) -> list[Scene]:
    return [SCENE_KINDS[kind](np.random.default_rng(seed), LANDMARKS) for seed in seeds]


# --- every kind -------------------------------------------------------------------------------


def test_the_kinds_are_there() -> None:
    assert {"venue", "room", "turntable", "street"} <= set(SCENE_KINDS)


@pytest.mark.parametrize("kind", sorted(SCENE_KINDS))
def test_a_kind_is_reproducible_from_the_seed(kind: str) -> None:
    make = SCENE_KINDS[kind]
    assert same(
        make(np.random.default_rng(7), LANDMARKS), make(np.random.default_rng(7), LANDMARKS)
    )
    assert not same(
        make(np.random.default_rng(7), LANDMARKS), make(np.random.default_rng(8), LANDMARKS)
    )


@pytest.mark.parametrize("kind", sorted(SCENE_KINDS))
def test_every_landmark_is_seen_by_both_cameras(kind: str) -> None:
    for s in kind_scenes(kind):
        assert s.points.shape == (LANDMARKS, 3)
        assert in_photo(s.camera1, s.points, s.image_size1, 0.02).all()
        assert in_photo(s.camera2, s.points, s.image_size2, 0.02).all()


@pytest.mark.parametrize("kind", sorted(SCENE_KINDS))
def test_the_fundamental_matrix_holds_on_the_landmarks(kind: str) -> None:
    for s in kind_scenes(kind):
        x1 = np.hstack([s.landmarks1, np.ones((LANDMARKS, 1))])
        x2 = np.hstack([s.landmarks2, np.ones((LANDMARKS, 1))])
        lines = x1 @ s.fundamental.T
        residual = np.abs(np.sum(x2 * lines, axis=1))
        scale = np.linalg.norm(x2, axis=1) * np.linalg.norm(lines, axis=1)
        assert (residual <= 1e-9 * scale).all()


@pytest.mark.parametrize("kind", sorted(SCENE_KINDS))
def test_principal_points_are_near_the_centres(kind: str) -> None:
    for s in kind_scenes(kind, range(10)):
        for camera, size in ((s.camera1, s.image_size1), (s.camera2, s.image_size2)):
            k = camera.intrinsics
            assert k[0, 0] == k[1, 1]
            assert k[0, 1] == 0
            offset = k[:2, 2] - np.array(size) / 2
            assert np.linalg.norm(offset) < 0.02 * math.hypot(*size)


# --- phone scenes -----------------------------------------------------------------------------


def test_phone_scenes_are_reproducible_from_the_seed() -> None:
    a, b = phone(3, zoom2=2.0), phone(3, zoom2=2.0)
    assert same(a, b)
    assert (a.focal_35mm1, a.focal_35mm2) == (b.focal_35mm1, b.focal_35mm2)


def test_each_phone_sees_the_other() -> None:
    for seed in SEEDS:
        s = phone(seed)
        assert epipoles_seen(s) == (True, True)
        assert 20.0 <= s.distance <= 80.0


def test_a_zoomed_phone_still_sees_the_other() -> None:
    for seed in range(10):
        assert epipoles_seen(phone(seed, zoom1=3.0, zoom2=5.0)) == (True, True)


def test_a_given_distance_is_kept() -> None:
    assert phone(0, distance=33.0).distance == pytest.approx(33.0, rel=1e-12)


def test_photos_are_12_megapixels_in_both_orientations() -> None:
    scenes = [phone(seed) for seed in range(100)]
    both = {(4032, 3024), (3024, 4032)}
    assert {s.image_size1 for s in scenes} == {s.image_size2 for s in scenes} == both


def test_the_35mm_focal_gives_k_by_the_diagonal() -> None:
    orientations = set()
    for seed in SEEDS:
        s = phone(seed)
        for camera, size, focal in (
            (s.camera1, s.image_size1, s.focal_35mm1),
            (s.camera2, s.image_size2, s.focal_35mm2),
        ):
            orientations.add(size)
            expected = focal / FRAME_DIAGONAL_MM * math.hypot(*size)
            assert camera.intrinsics[0, 0] == pytest.approx(expected, rel=1e-12)
            assert camera.intrinsics[1, 1] == pytest.approx(expected, rel=1e-12)
            # The main camera: 26 mm +- 5 % (sd); 5 sd would be a broken draw.
            assert 26.0 * 0.75 < focal < 26.0 * 1.25
    assert len(orientations) == 2


def test_exif_is_the_true_focal_rounded() -> None:
    for seed in SEEDS:
        s = phone(seed, zoom1=2.0)
        for exif, focal in (
            (s.exif_focal_35mm1, s.focal_35mm1),
            (s.exif_focal_35mm2, s.focal_35mm2),
        ):
            assert isinstance(exif, int)
            assert exif == round(focal)
            assert abs(exif - focal) <= 0.5


def test_zoom_multiplies_the_focal() -> None:
    exact = 0
    for seed in SEEDS:
        plain, zoomed = phone(seed), phone(seed, zoom1=1.5, zoom2=3.0)
        assert (zoomed.zoom1, zoomed.zoom2) == (1.5, 3.0)
        assert 26.0 * 0.75 < zoomed.focal_35mm1 / 1.5 < 26.0 * 1.25
        assert 26.0 * 0.75 < zoomed.focal_35mm2 / 3.0 < 26.0 * 1.25
        # When the first draw suits both, the phones are the same but for the zoom.
        if np.array_equal(plain.camera1.centre, zoomed.camera1.centre) and np.array_equal(
            plain.camera2.centre, zoomed.camera2.centre
        ):
            exact += 1
            assert zoomed.focal_35mm1 == pytest.approx(1.5 * plain.focal_35mm1, rel=1e-12)
            assert zoomed.focal_35mm2 == pytest.approx(3.0 * plain.focal_35mm2, rel=1e-12)
    assert exact >= 10


def test_phone_scenes_take_taps() -> None:
    s = phone(1)
    taps = tap(s, 2.0, np.random.default_rng(0))
    assert taps.landmarks1.shape == taps.landmarks2.shape == (LANDMARKS, 2)
    assert np.linalg.norm(taps.epipole1 - s.epipole1) < 20.0


# --- what sets the other kinds apart ----------------------------------------------------------


@pytest.mark.parametrize("kind", ["room", "turntable"])
def test_the_other_camera_is_mostly_out_of_frame(kind: str) -> None:
    seen_pairs = np.array([epipoles_seen(s) for s in kind_scenes(kind, range(60))])
    assert (~seen_pairs).mean(axis=0).min() > 0.5
    if kind == "turntable":
        assert not seen_pairs.any()


def test_room_cameras_are_high_in_a_room_and_look_down() -> None:
    for s in kind_scenes("room"):
        for camera in (s.camera1, s.camera2):
            assert 2.5 <= -camera.centre[1] <= 3.5
            # y is down: the optical axis points down towards the room's centre.
            assert camera.rotation[2, 1] > 0
        assert 6.0 * 0.5 < np.linalg.norm(s.camera1.centre - s.camera2.centre) < 12.0


def test_turntable_views_circle_the_object() -> None:
    for s in kind_scenes("turntable"):
        r1, r2 = np.linalg.norm(s.camera1.centre), np.linalg.norm(s.camera2.centre)
        assert r1 == pytest.approx(r2, rel=1e-9)
        assert 0.5 <= r1 <= 1.5
        # Same height on the circle (y is down: above the object), 20-60 degrees around it.
        assert s.camera1.centre[1] == pytest.approx(s.camera2.centre[1], abs=1e-12)
        assert s.camera1.centre[1] < 0
        a1, a2 = (math.atan2(c.centre[0], c.centre[2]) for c in (s.camera1, s.camera2))
        turn = math.degrees(abs(math.remainder(a2 - a1, 2 * math.pi)))
        assert 20.0 - 1e-9 <= turn <= 60.0 + 1e-9


def test_street_baseline_runs_along_the_view() -> None:
    angles = []
    for s in kind_scenes("street"):
        baseline = s.camera2.centre - s.camera1.centre
        assert 5.0 <= np.linalg.norm(baseline) <= 31.0
        for camera in (s.camera1, s.camera2):
            cosine = abs(baseline @ camera.rotation[2]) / np.linalg.norm(baseline)
            angles.append(math.degrees(math.acos(min(1.0, cosine))))
        # Both look the same way (not facing each other).
        assert s.camera1.rotation[2] @ s.camera2.rotation[2] > math.cos(math.radians(45))
        # Neither sees the other from the front: one is behind the other's camera.
        ahead = s.camera1.depth(s.camera2.centre[None])[0] > 0
        assert ahead != (s.camera2.depth(s.camera1.centre[None])[0] > 0)
    assert max(angles) < 45.0
    assert float(np.median(angles)) < 20.0
