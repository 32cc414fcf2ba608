"""The real-camera data (``tests/data/real_cameras/``) and its loader (``testbed.real_cameras``):
the truth the solver is measured against must be the calibration's, and what the loader
derives from it (zoomed photos, taps) must move that truth consistently."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from testbed.real_cameras import (
    DATA,
    SETS,
    RealPair,
    load_pairs,
    read_set,
    reversed_pair,
    stored_pairs,
    tap,
    zoomed,
)
from testbed.scenes import inside

PAIRS = load_pairs()
STORED = [pair for name in SETS for pair in stored_pairs(name)]


def test_every_set_names_its_source_authors_and_licence() -> None:
    readme = (DATA / "README.md").read_text()
    for name in SETS:
        document = read_set(name)
        for field in ("title", "authors", "licence", "source", "landmarks"):
            assert document[field].strip(), (name, field)
        assert f"{name}.json" in readme


def test_there_are_facing_arrow_and_long_lens_pairs_with_enough_landmarks() -> None:
    kinds = [pair.kind for pair in PAIRS]
    assert len(PAIRS) >= 10
    assert kinds.count("facing") >= 4
    assert kinds.count("arrow") >= 5
    assert any(max(p.focal_35mm1, p.focal_35mm2) > 60 for p in PAIRS)
    assert all(len(pair.landmarks1) >= 6 for pair in PAIRS)


@pytest.mark.parametrize("pair", STORED, ids=lambda pair: pair.name)
def test_the_true_geometry_fits_the_landmarks_within_their_stated_accuracy(
    pair: RealPair,
) -> None:
    stored = _stored(pair)
    sampson = pair.sampson()
    assert np.allclose(sampson, stored["sampson_px"], atol=2e-3)
    assert sampson.max() <= pair.accuracy + 1e-3
    assert pair.accuracy <= 2.0
    assert pair.in_front().all()
    assert inside(pair.landmarks1, pair.image_size1).all()
    assert inside(pair.landmarks2, pair.image_size2).all()
    # Landmarks a finger can tell apart: no two within 3 px in either photo.
    for points in (pair.landmarks1, pair.landmarks2):
        gaps = np.linalg.norm(points[:, None] - points[None], axis=2)
        assert gaps[np.triu_indices(len(points), 1)].min() > 3.0


@pytest.mark.parametrize("pair", STORED, ids=lambda pair: pair.name)
def test_the_epipoles_are_the_null_vectors_of_the_true_f_and_the_stored_truth(
    pair: RealPair,
) -> None:
    f = pair.fundamental
    assert np.linalg.norm(f @ pair.epipole1_h) < 1e-9
    assert np.linalg.norm(f.T @ pair.epipole2_h) < 1e-9
    truth = _stored(pair)["truth"]
    assert np.allclose(pair.epipole1, truth["epipole1"], atol=0.06)
    assert np.allclose(pair.epipole2, truth["epipole2"], atol=0.06)
    assert (pair.epipole1_h[2] > 0) == truth["camera2_in_front_of_camera1"]
    assert (pair.epipole2_h[2] > 0) == truth["camera1_in_front_of_camera2"]
    assert pair.axes_angle_deg == pytest.approx(truth["axes_angle_deg"], abs=0.06)
    # The oriented epipole is where camera 2's centre projects, in front or behind.
    depth = pair.camera1.depth(pair.camera2.centre[None])[0]
    assert math.copysign(1.0, depth) == math.copysign(1.0, pair.epipole1_h[2])


def test_each_oriented_pair_has_friend_2_inside_photo_1() -> None:
    for pair in PAIRS:
        assert pair.epipole1_h[2] > 0, pair.name
        assert inside(pair.epipole1[None], pair.image_size1)[0], pair.name
    facing = [pair for pair in PAIRS if pair.kind == "facing"]
    assert {pair.name for pair in facing} == {reversed_pair(p).name for p in facing}


@pytest.mark.parametrize("zoom", [2.0, 3.0, 5.0])
def test_a_zoomed_photo_2_moves_the_truth_with_it(zoom: float) -> None:
    for pair in PAIRS:
        crop = zoomed(pair, zoom)
        centre = np.array(pair.image_size2) / 2
        assert crop.image_size2 == pair.image_size2
        assert crop.focal_35mm2 == pytest.approx(zoom * pair.focal_35mm2)
        assert np.allclose(crop.epipole1, pair.epipole1)
        if pair.kind != "behind":
            assert np.allclose(crop.epipole2, zoom * (pair.epipole2 - centre) + centre)
        assert crop.kind == "behind" or pair.kind != "behind"
        # Exactly the landmarks whose zoomed pixel stays in the photo, in the same order.
        moved = zoom * (pair.landmarks2 - centre) + centre
        kept = inside(moved, pair.image_size2)
        assert np.array_equal(crop.landmarks1, pair.landmarks1[kept])
        assert np.allclose(crop.landmarks2, moved[kept])
        # The zoomed geometry still fits them: F' = Z^-T F.
        assert np.all(crop.sampson() <= zoom * pair.accuracy + 1e-3)
        expected = np.linalg.inv(_crop(zoom, centre)).T @ pair.fundamental
        expected /= np.linalg.norm(expected)
        assert (
            min(
                np.linalg.norm(crop.fundamental - expected),
                np.linalg.norm(crop.fundamental + expected),
            )
            < 1e-9
        )


def test_no_zoom_changes_nothing_and_reversing_twice_is_the_pair() -> None:
    pair = PAIRS[0]
    same = zoomed(pair, 1.0)
    assert same.name == pair.name
    assert np.array_equal(same.landmarks2, pair.landmarks2)
    back = reversed_pair(reversed_pair(pair))
    assert back.name == pair.name
    assert np.array_equal(back.landmarks1, pair.landmarks1)
    with pytest.raises(ValueError, match="at least 1"):
        zoomed(pair, 0.5)


def test_taps_are_seeded_nested_and_as_noisy_as_asked() -> None:
    pair = max(PAIRS, key=lambda p: len(p.landmarks1))
    first = tap(pair, np.random.default_rng(7), 3.0)
    again = tap(pair, np.random.default_rng(7), 3.0)
    assert np.array_equal(first.points1, again.points1)
    assert np.array_equal(first.epipole1, again.epipole1)
    three, four = first.first(3), first.first(4)
    assert np.array_equal(four[0][:3], three[0])
    assert np.array_equal(four[1][:3], three[1])
    with pytest.raises(ValueError, match="landmarks asked"):
        first.first(len(pair.landmarks1) + 1)
    rng = np.random.default_rng(8)
    errors = []
    for _ in range(200):
        taps = tap(pair, rng, 3.0)
        errors.append(taps.points1 - pair.landmarks1[taps.order])
        errors.append(taps.points2 - pair.landmarks2[taps.order])
        errors.append((taps.epipole1 - pair.epipole1)[None])
    spread = np.vstack(errors)
    assert spread.std() == pytest.approx(3.0, rel=0.05)
    assert np.abs(spread.mean(axis=0)).max() < 0.1


def _stored(pair: RealPair) -> dict[str, Any]:
    for stored in read_set(pair.set_name)["pairs"]:
        if tuple(stored["cameras"]) == pair.camera_ids:
            return dict(stored)
    raise KeyError(pair.name)


def _crop(zoom: float, centre: np.ndarray) -> np.ndarray:
    return np.array(
        [[zoom, 0.0, (1 - zoom) * centre[0]], [0.0, zoom, (1 - zoom) * centre[1]], [0, 0, 1]]
    )
