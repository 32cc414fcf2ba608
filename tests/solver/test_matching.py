"""Bands, tap checks and suggestions (``shared_solver.matching``).

The band's statistics against the truth are checked with the solver's answers in
``test_fundamental_covariance.py``; here, its geometry on exact input, the tap check, and
the suggestions on rendered halls (``testbed.venue``): a sure match where the landmark is
plain to see, none where the spot is not in the other photo.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Literal

import numpy as np
import pytest

from shared_solver.matching import (
    FLAG_SIGMAS,
    Epipolar,
    LandmarkSearch,
    epipolar_band,
    guide_landmark,
    suggest,
)
from shared_solver.matching.suggestion import RULES, gather, offerable
from shared_solver.result import SolveResult
from testbed.phones import PhoneScene, phone_scene
from testbed.textures import poster
from testbed.venue import RenderedPair, good_answer, rendered_pair

TAP = 3.0**2 * np.eye(2)


def exact_geometry(seed: int, landmarks: int = 8) -> tuple[Epipolar, PhoneScene]:
    """The true F of a phone scene with a small, round uncertainty, oriented by its
    landmarks."""
    scene = phone_scene(np.random.default_rng(seed), landmarks)
    covariance = 1e-14 * np.eye(9)
    epipolar = Epipolar(scene.fundamental, covariance).oriented(scene.landmarks1, scene.landmarks2)
    return epipolar, scene


@pytest.mark.parametrize("seed", range(6))
def test_on_exact_input_the_band_runs_through_the_truth_inside_the_photo(seed: int) -> None:
    epipolar, scene = exact_geometry(seed)
    assert epipolar.sign != 0
    width, height = scene.image_size2
    e_b = epipolar.epipole_b[:2] / epipolar.epipole_b[2]
    for p, q in zip(scene.landmarks1, scene.landmarks2, strict=True):
        band = epipolar_band(epipolar, p, image_size=scene.image_size2, point_covariance=TAP)
        assert band is not None
        assert abs(band.line[:2] @ q + band.line[2]) < 1e-6
        # The centre line starts at the other friend (inside the photo here) and holds q.
        np.testing.assert_allclose(band.start, e_b, atol=1e-6)
        along = (q - band.start) @ (band.end - band.start) / band.length**2
        assert 0.0 <= along <= 1.0
        outline = band.outline()
        assert len(outline) >= 4
        assert (outline >= -1e-9).all()
        assert (outline[:, 0] <= width + 1e-9).all()
        assert (outline[:, 1] <= height + 1e-9).all()
        shape = band.shape()
        assert shape.level == 0.95
        assert min(shape.half_width) > 0


def test_a_landmark_tapped_on_the_other_friend_has_no_band() -> None:
    """On the epipole in A (the friend mark) F p is exactly 0: every line through the other
    friend is its line, and there is no band (found by drawing absurd taps: a division by
    zero answered the tap's PUT with a 500). Beside it, the band is there, and wide."""
    # F = [e]x with the epipole in both photos at (0, 0): F (0, 0, 1) is 0 to the last bit.
    fundamental = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    epipolar = Epipolar(fundamental, 1e-14 * np.eye(9))
    size = (100, 100)
    assert epipolar_band(epipolar, np.zeros(2), image_size=size, point_covariance=TAP) is None
    beside = epipolar_band(epipolar, np.array([5.0, 5.0]), image_size=size, point_covariance=TAP)
    assert beside is not None


def test_the_band_widens_with_the_uncertainty_of_f_and_of_the_tap() -> None:
    epipolar, scene = exact_geometry(3)
    p, q = scene.landmarks1[0], scene.landmarks2[0]
    narrow = epipolar_band(epipolar, p, image_size=scene.image_size2, point_covariance=TAP)
    wide_tap = epipolar_band(epipolar, p, image_size=scene.image_size2, point_covariance=4 * TAP)
    looser = Epipolar(epipolar.fundamental, 100 * epipolar.covariance, epipolar.sign)
    wide_f = epipolar_band(looser, p, image_size=scene.image_size2, point_covariance=TAP)
    assert narrow is not None
    assert wide_tap is not None
    assert wide_f is not None
    at = q[None]
    assert wide_tap.half_width(at)[0] > narrow.half_width(at)[0]
    assert wide_f.half_width(at)[0] > narrow.half_width(at)[0]
    # 1.96 standard deviations on each side at 95 %.
    assert math.isclose(narrow.half_width(at)[0] / narrow.sd(at)[0], 1.959964, rel_tol=1e-5)


def test_from_photo_2_the_band_is_that_of_the_transposed_geometry() -> None:
    epipolar, scene = exact_geometry(4)
    back = epipolar.transposed()
    np.testing.assert_array_equal(back.transposed().covariance, epipolar.covariance)
    np.testing.assert_array_equal(back.fundamental, epipolar.fundamental.T)
    oriented_back = Epipolar(back.fundamental, back.covariance).oriented(
        scene.landmarks2, scene.landmarks1
    )
    assert oriented_back.sign != 0
    for p, q in zip(scene.landmarks1, scene.landmarks2, strict=True):
        band = epipolar_band(oriented_back, q, image_size=scene.image_size1, point_covariance=TAP)
        assert band is not None
        assert abs(band.line[:2] @ p + band.line[2]) < 1e-6


def test_a_tap_on_the_line_fits_and_one_far_across_it_does_not() -> None:
    epipolar, scene = exact_geometry(5)
    p, q = scene.landmarks1[2], scene.landmarks2[2]
    band = epipolar_band(epipolar, p, image_size=scene.image_size2, point_covariance=TAP)
    assert band is not None
    assert band.check(q, TAP).fits
    sd = math.sqrt(band.sd(q[None])[0] ** 2 + 9.0)
    beside = q + (FLAG_SIGMAS + 1.0) * sd * band.line[:2]
    check = band.check(beside, TAP)
    assert not check.fits
    assert math.isclose(check.sigmas, FLAG_SIGMAS + 1.0, rel_tol=1e-6)
    # Along the line, however far, a tap fits: the band cannot tell landmarks apart there.
    along = q + 200.0 * np.array([band.line[1], -band.line[0]])
    assert band.check(along, TAP).sigmas < 1e-6


# --- suggestions on rendered halls ------------------------------------------------------


@pytest.fixture(scope="module")
def hall() -> RenderedPair:
    return rendered_pair(21)


def test_plain_landmarks_get_right_suggestions(hall: RenderedPair) -> None:
    scene = hall.scene
    epipolar = good_answer(hall.scene)
    diagonal = math.hypot(*scene.image_size2)
    shown, right = 0, 0
    for p, q in zip(scene.landmarks1[:12], scene.landmarks2[:12], strict=True):
        band = epipolar_band(epipolar, p, image_size=scene.image_size2, point_covariance=TAP)
        assert band is not None
        found = suggest(
            LandmarkSearch(hall.photo1, hall.photo2, p, epipolar, band, point_covariance=TAP)
        )
        if found is not None:
            shown += 1
            right += math.hypot(found.point[0] - q[0], found.point[1] - q[1]) <= 0.01 * diagonal
    assert shown >= 3
    assert right == shown


def test_no_suggestion_where_the_band_is_far_wider_than_the_rows_searched(
    hall: RenderedPair,
) -> None:
    """The plain landmarks offered a right spot above, with an answer 20 times less sure
    (few landmarks, quick taps): their bands are then far wider than the rows searched
    (more than ``max_across``), and none is offered, though the search still finds a place
    that would lead. On rendered arenas every spot once offered beyond 3 % of the diagonal
    was in such a band (docs/geometry.md)."""
    scene = hall.scene
    sure = good_answer(hall.scene)
    unsure = replace(sure, covariance=400.0 * sure.covariance)
    offered = 0
    for p in scene.landmarks1[:12]:
        searches = [
            LandmarkSearch(hall.photo1, hall.photo2, p, epipolar, band, point_covariance=TAP)
            for epipolar in (sure, unsure)
            if (
                band := epipolar_band(
                    epipolar, p, image_size=scene.image_size2, point_covariance=TAP
                )
            )
        ]
        assert len(searches) == 2
        if suggest(searches[0]) is None:
            continue
        offered += 1
        assert suggest(searches[1]) is None
        evidence = gather(searches[1])
        assert evidence is not None
        assert evidence.match.across > RULES.max_across
        assert offerable(evidence.match, replace(RULES, max_across=math.inf))
    assert offered >= 3


def test_no_suggestion_for_a_patch_the_other_photo_does_not_show(hall: RenderedPair) -> None:
    """Posters put up in photo 1 only, over landmarks: along their bands photo 2 shows
    whatever was there before, never the poster. (How often spots hidden from the other
    photo get a suggestion is measured in docs/suggestions.md.)"""
    scene = hall.scene
    epipolar = good_answer(hall.scene)
    rng = np.random.default_rng(3)
    searched = 0
    for p in scene.landmarks1[:8]:
        photo = hall.photo1.copy()
        x, y = np.round(p).astype(int)
        photo[y - 30 : y + 30, x - 30 : x + 30] = poster(rng, (60, 60))
        band = epipolar_band(epipolar, p, image_size=scene.image_size2, point_covariance=TAP)
        assert band is not None
        searched += 1
        search = LandmarkSearch(photo, hall.photo2, p, epipolar, band, point_covariance=TAP)
        assert suggest(search) is None
    assert searched == 8


def test_guide_landmark_reads_the_answer(hall: RenderedPair) -> None:
    """From a ``SolveResult`` (here built around the true F): the band, and no image work
    when only the band is asked for."""
    scene = hall.scene
    epipolar = good_answer(hall.scene)
    f = tuple(tuple(float(v) for v in row) for row in epipolar.fundamental)
    result = SolveResult.model_validate(
        {
            "method": "pinhole_epipole",
            "landmark_count": len(scene.points),
            "tap_sigma": 3.0,
            "epipole2": None,
            "epipole2_h": None,
            "epipole1": None,
            "epipole1_h": None,
            "fundamental": f,
            "fundamental_covariance": epipolar.covariance.tolist(),
            "quality": "good",
        }
    )
    taps: tuple[tuple[Literal[1, 2], np.ndarray, int], ...] = (
        (1, scene.landmarks1[0], 2),
        (2, scene.landmarks2[0], 1),
    )
    for tapped_in, point, other in taps:
        guide = guide_landmark(
            result,
            hall.photo1,
            hall.photo2,
            point,
            tapped_in=tapped_in,
            tap_sigma=3.0,
            landmarks1=scene.landmarks1,
            landmarks2=scene.landmarks2,
            search=False,
        )
        assert guide is not None
        assert guide.suggestion is None
        truth = (scene.landmarks1 if other == 1 else scene.landmarks2)[0]
        assert abs(guide.band.line[:2] @ truth + guide.band.line[2]) < 1e-6
