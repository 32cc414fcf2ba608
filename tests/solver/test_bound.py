"""The Cramér-Rao bound of friend 1's position (testbed/bound.py), against the estimator it
bounds: a maximum-likelihood fit over every unknown reaches it at small tap noise, and the
solver's own fit sits at it."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from shared_solver import Camera, solve
from testbed.bound import CameraPrior, cramer_rao, reference_fit, tap_vector
from testbed.phones import phone_scene

SIGMA = 1.0
TRIALS = 200
EXIF = 0.02  # the log-sd of a known focal length's prior (camera.KNOWN_FOCAL_UNCERTAINTY)


def _errors(
    landmarks: int, priors: tuple[CameraPrior, CameraPrior], seed: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(reference fit's errors (T, 2), solver's errors (T, 2), the bound (2, 2)) on one
    phone scene at SIGMA px, the priors' means drawn from the priors themselves (the bound
    counts them as information: as if measured)."""
    rng = np.random.default_rng(seed)
    scene = phone_scene(rng, landmarks, centre_sd=0.0)
    bound = cramer_rao(scene, landmarks=landmarks, sigma=SIGMA, priors=priors)
    reference, ours = [], []
    for _ in range(TRIALS):
        p = scene.landmarks1 + rng.normal(0.0, SIGMA, (landmarks, 2))
        q = scene.landmarks2 + rng.normal(0.0, SIGMA, (landmarks, 2))
        e1 = scene.epipole1 + rng.normal(0.0, SIGMA, 2)
        offsets = np.array([rng.normal(0.0, prior or 0.0) for prior in priors])
        reference.append(
            reference_fit(
                scene,
                tap_vector(scene, landmarks, p, q, e1),
                landmarks=landmarks,
                sigma=SIGMA,
                priors=priors,
                prior_offsets=offsets,
            )
            - scene.epipole2
        )
        cameras: dict[str, Any] = {}
        if priors[0] is not None:
            true35 = (scene.focal_35mm1, scene.focal_35mm2)
            cameras = {
                f"camera{k + 1}": Camera.with_focal(true35[k] * math.exp(offsets[k]), EXIF)
                for k in range(2)
            }
        result = solve(
            p,
            q,
            epipole1=e1,
            tap_sigma=SIGMA,
            **scene.sizes,
            **cameras,
        )
        assert result.epipole2 is not None
        ours.append(np.array(result.epipole2) - scene.epipole2)
    return np.array(reference), np.array(ours), bound.covariance


@pytest.mark.parametrize(
    ("landmarks", "priors", "seed"),
    [(5, (EXIF, EXIF), 1), (4, (EXIF, EXIF), 2), (6, (None, None), 3)],
    ids=["5 landmarks, focal known", "4 landmarks, focal known", "6 landmarks, no camera model"],
)
def test_a_maximum_likelihood_fit_reaches_the_bound_and_so_does_the_solver(
    landmarks: int, priors: tuple[CameraPrior, CameraPrior], seed: int
) -> None:
    reference, ours, bound = _errors(landmarks, priors, seed)
    inverse = np.linalg.inv(bound)
    # Under the bound the squared Mahalanobis distance is chi-square with 2 dof: mean 2,
    # and the mean of 200 has a standard deviation of 0.14.
    spread = np.einsum("ki,ij,kj->k", reference, inverse, reference).mean()
    assert 1.6 <= spread <= 2.4
    rms = math.sqrt(float(np.trace(bound)))
    assert 0.85 <= math.sqrt(float((reference**2).sum(axis=1).mean())) / rms <= 1.15
    # The solver (Sampson distances, its own priors) sits at the bound too.
    assert math.sqrt(float((ours**2).sum(axis=1).mean())) / rms <= 1.15


def test_four_landmarks_bound_no_point_without_a_camera_model() -> None:
    """The paper's curve: four landmarks and the friend leave a direction free, and the bound
    says so (infinite); the phone model's prior closes it."""
    scene = phone_scene(np.random.default_rng(4), 8)
    unknown = cramer_rao(scene, landmarks=4, sigma=SIGMA, priors=(None, None))
    assert math.isinf(unknown.rms)
    assert math.isinf(unknown.median)
    phone = cramer_rao(scene, landmarks=4, sigma=SIGMA, priors=(0.5, 0.5))
    assert math.isfinite(phone.rms)


def test_more_landmarks_and_known_lenses_lower_the_bound() -> None:
    scene = phone_scene(np.random.default_rng(5), 8)
    rms = [cramer_rao(scene, landmarks=n, sigma=SIGMA, priors=(0.5, 0.5)).rms for n in (3, 4, 5, 8)]
    assert rms == sorted(rms, reverse=True)
    known = cramer_rao(scene, landmarks=3, sigma=SIGMA, priors=(EXIF, EXIF))
    assert known.rms < rms[0]
    both = cramer_rao(scene, landmarks=3, sigma=SIGMA, priors=(0.5, 0.5), marks="both")
    assert both.rms < rms[0]
    # Without a prior, twice the tap noise is twice the error.
    once, twice = (cramer_rao(scene, landmarks=6, sigma=s, priors=(None, None)) for s in (1, 2))
    assert twice.rms == pytest.approx(2 * once.rms, rel=1e-6)


def test_one_landmark_with_gravity_sits_at_the_bound_that_counts_the_readings() -> None:
    """One landmark, the friend, both readings of down and known lenses: as many
    measurements as unknowns, so the solver's exact answer spreads as the bound says (at
    small noise, where first order holds); without the readings the bound has no point."""
    rng = np.random.default_rng(6)
    scene = phone_scene(rng, 1, centre_sd=0.0)
    sigma, gravity_sigma = 0.3, 0.2
    assert math.isinf(cramer_rao(scene, landmarks=1, sigma=sigma, priors=(EXIF, EXIF)).rms)
    bound = cramer_rao(
        scene, landmarks=1, sigma=sigma, priors=(EXIF, EXIF), gravity_sigma_deg=gravity_sigma
    ).covariance
    down = [scene.camera1.down, scene.camera2.down]
    errors = []
    for _ in range(TRIALS):
        readings = [d + rng.normal(0.0, math.radians(gravity_sigma), 3) for d in down]
        offsets = rng.normal(0.0, EXIF, 2)
        true35 = (scene.focal_35mm1, scene.focal_35mm2)
        result = solve(
            scene.landmarks1 + rng.normal(0.0, sigma, (1, 2)),
            scene.landmarks2 + rng.normal(0.0, sigma, (1, 2)),
            epipole1=scene.epipole1 + rng.normal(0.0, sigma, 2),
            tap_sigma=sigma,
            **scene.sizes,
            camera1=Camera.with_focal(true35[0] * math.exp(offsets[0]), EXIF),
            camera2=Camera.with_focal(true35[1] * math.exp(offsets[1]), EXIF),
            gravity1=readings[0],
            gravity2=readings[1],
            gravity_sigma_deg=gravity_sigma,
        )
        assert result.epipole2 is not None
        assert result.used_gravity
        errors.append(np.array(result.epipole2) - scene.epipole2)
    spread = np.einsum("ki,ij,kj->k", errors, np.linalg.inv(bound), errors).mean()
    assert 1.6 <= spread <= 2.4, spread
