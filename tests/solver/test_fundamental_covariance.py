"""The answer's ``fundamental_covariance``: the uncertainty of F that epipolar bands need,
returned when asked (``solve(..., fundamental_covariance=True)``).

It is first order (F's derivatives through the fit's covariance), so it is checked two
ways: the pinhole model's derivatives of F against central differences, and, for every
route that claims it, the band it gives (:mod:`shared_solver.matching`) against the truth:
at 95 % the true landmark must be inside its band about 95 % of the time.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from shared_solver import SolverError, solve
from shared_solver.estimation.pinhole.pose import PARAMETERS, Poses, tangent_basis
from shared_solver.estimation.pinhole.predictions import fundamental_stack
from shared_solver.matching import Epipolar, epipolar_band
from testbed.phones import phone_scene
from testbed.scenes import facing_scene

SIGMA = 3.0
TRIALS = 150
TESTED = 4  # landmarks per trial that the answer did not use, each checked against its band
STEP = 1e-6


def test_pinhole_derivatives_of_f_match_central_differences() -> None:
    rng = np.random.default_rng(5)
    scene = phone_scene(rng, 3)
    one, two = scene.camera1, scene.camera2
    pose = Poses.one(
        two.rotation @ one.rotation.T,
        one.rotation @ (two.centre - one.centre),
        np.log([one.intrinsics[0, 0], two.intrinsics[0, 0]]),
    ).moved(rng.normal(0.0, 0.02, (1, PARAMETERS)))
    centres = ((2016.0, 1512.0), (1512.0, 2016.0))

    def f_at(moved: Poses) -> np.ndarray:
        return fundamental_stack(
            moved, centres, np.array(tangent_basis(*moved.friend2[0].tolist()))
        )

    stack = f_at(pose)
    scale = np.abs(stack[0]).max()
    for k in range(PARAMETERS):
        step = np.zeros((1, PARAMETERS))
        step[0, k] = STEP
        numeric = (f_at(pose.moved(step))[0] - f_at(pose.moved(-step))[0]) / (2 * STEP)
        np.testing.assert_allclose(stack[1 + k] / scale, numeric / scale, atol=1e-6)


def _coverage(route: str) -> tuple[float, int]:
    """Fraction of untapped landmarks inside their 95 % band, over TRIALS scenes."""
    rng = np.random.default_rng({"phone 3": 1, "phone 5": 2, "projective 8": 3}.get(route, 4))
    inside, count = 0, 0
    for _ in range(TRIALS):
        used = {"phone 3": 3, "phone 5": 5, "projective 8": 8, "projective both 3": 3}[route]
        scene = phone_scene(rng, used + TESTED)
        n = used + TESTED
        p = scene.landmarks1 + rng.normal(0.0, SIGMA, (n, 2))
        q = scene.landmarks2 + rng.normal(0.0, SIGMA, (n, 2))
        marks: dict[str, Any] = {"epipole1": scene.epipole1 + rng.normal(0.0, SIGMA, 2)}
        if route == "projective both 3":
            marks["epipole2"] = scene.epipole2 + rng.normal(0.0, SIGMA, 2)
        cameras: dict[str, Any] = (
            {"camera1": "phone", "camera2": "phone"} if route.startswith("phone") else {}
        )
        try:
            result = solve(
                p[:used],
                q[:used],
                tap_sigma=SIGMA,
                **scene.sizes,
                **marks,
                **cameras,
                fundamental_covariance=True,
            )
        except SolverError:
            continue
        expected = {
            "phone 3": "pinhole_epipole",
            "phone 5": "pinhole_epipole",
            "projective 8": "least_squares_epipole",
            "projective both 3": "two_epipoles",
        }[route]
        if result.method != expected or result.candidates:
            continue  # another route answered, or several geometries: no band is claimed
        epipolar = Epipolar.from_result(
            result, tapped_in=1, landmarks1=p[:used], landmarks2=q[:used]
        )
        assert epipolar is not None
        for k in range(used, n):
            band = epipolar_band(
                epipolar,
                p[k],
                image_size=scene.image_size2,
                point_covariance=SIGMA**2 * np.eye(2),
            )
            assert band is not None  # every landmark is inside photo 2
            truth = scene.landmarks2[k]
            offset = abs(band.line[:2] @ truth + band.line[2])
            inside += bool(offset <= band.half_width(truth[None])[0])
            count += 1
    return inside / count, count


@pytest.mark.parametrize("route", ["phone 3", "phone 5", "projective 8", "projective both 3"])
def test_the_truth_is_inside_its_band_at_the_stated_level(route: str) -> None:
    fraction, count = _coverage(route)
    assert count >= 0.8 * TRIALS * TESTED
    # 600 landmarks: a binomial 95 % has an sd of 0.9 %; correlated within a trial, a bit more.
    assert 0.92 <= fraction <= 0.98, (route, fraction)


def test_exact_taps_give_a_band_through_the_truth() -> None:
    rng = np.random.default_rng(8)
    scene = phone_scene(rng, 9, centre_sd=0.0)
    result = solve(
        scene.landmarks1[:5],
        scene.landmarks2[:5],
        epipole1=scene.epipole1,
        tap_sigma=1.0,
        **scene.sizes,
        camera1={"kind": "known_focal", "focal_35mm": scene.focal_35mm1},
        camera2={"kind": "known_focal", "focal_35mm": scene.focal_35mm2},
        fundamental_covariance=True,
    )
    epipolar = Epipolar.from_result(
        result, tapped_in=1, landmarks1=scene.landmarks1[:5], landmarks2=scene.landmarks2[:5]
    )
    assert epipolar is not None
    for k in range(5, 9):
        band = epipolar_band(
            epipolar, scene.landmarks1[k], image_size=scene.image_size2, point_covariance=np.eye(2)
        )
        assert band is not None
        truth = scene.landmarks2[k]
        assert abs(band.line[:2] @ truth + band.line[2]) < 1e-6
        assert 0 < band.half_width(truth[None])[0] < 100


def test_no_covariance_where_no_single_geometry_is_claimed() -> None:
    rng = np.random.default_rng(9)
    scene = facing_scene(rng, 7)
    sizes = scene.sizes | {"fundamental_covariance": True}
    seven = solve(scene.landmarks1, scene.landmarks2, tap_sigma=1.0, **sizes)
    assert seven.candidates
    assert seven.fundamental_covariance is None
    curve = solve(
        scene.landmarks1[:4], scene.landmarks2[:4], epipole1=scene.epipole1, tap_sigma=1.0, **sizes
    )
    assert curve.method == "conic"
    assert curve.fundamental_covariance is None
    floor = facing_scene(rng, 6, planar=True)
    planar = solve(
        floor.landmarks1, floor.landmarks2, epipole1=floor.epipole1, tap_sigma=1.0, **sizes
    )
    assert planar.method == "planar"
    assert planar.fundamental_covariance is None


def test_the_covariance_is_symmetric_positive_and_flat_along_f() -> None:
    rng = np.random.default_rng(10)
    scene = phone_scene(rng, 6)
    both: tuple[dict[str, Any], ...] = ({"camera1": "phone", "camera2": "phone"}, {})
    for cameras in both:
        result = solve(
            scene.landmarks1 + rng.normal(0.0, SIGMA, (6, 2)),
            scene.landmarks2 + rng.normal(0.0, SIGMA, (6, 2)),
            epipole1=scene.epipole1,
            tap_sigma=SIGMA,
            **scene.sizes,
            **cameras,
            fundamental_covariance=True,
        )
        assert result.fundamental is not None
        assert result.fundamental_covariance is not None
        covariance = np.array(result.fundamental_covariance)
        f = np.array(result.fundamental).reshape(9)
        np.testing.assert_allclose(covariance, covariance.T, atol=1e-15)
        assert np.linalg.eigvalsh(covariance).min() > -1e-15
        # F stays at unit norm: no variance along F itself.
        assert f @ covariance @ f < 1e-12 * np.trace(covariance)


def test_only_when_asked() -> None:
    """Without the flag the answer is what it was: no covariance, the same numbers."""
    rng = np.random.default_rng(11)
    scene = phone_scene(rng, 5)
    taps = (
        scene.landmarks1 + rng.normal(0.0, SIGMA, (5, 2)),
        scene.landmarks2 + rng.normal(0.0, SIGMA, (5, 2)),
    )
    for cameras in ({"camera1": "phone", "camera2": "phone"}, {}):
        options = {
            "epipole1": scene.epipole1,
            "tap_sigma": SIGMA,
            **scene.sizes,
            **cameras,
        }
        plain = solve(*taps, **options)
        asked = solve(*taps, **options, fundamental_covariance=True)
        assert plain.fundamental_covariance is None
        assert asked.fundamental_covariance is not None
        assert asked.model_copy(update={"fundamental_covariance": None}) == plain
