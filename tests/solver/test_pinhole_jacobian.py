"""The pinhole model's Jacobian is the derivative of its residuals.

The fit converges with any reasonable Jacobian, so a wrong one would only show as a wrong
covariance (the 95 % region): it is checked here directly, against central differences
along each tangent step (rotation, friend 2's direction, both log focal lengths), with each
kind of mark (and both phones' gravity, and their compass headings), with round and with
elongated tap covariances. The batched residuals
(``offsets``, used to score poses and by the bootstrap) must equal the fit's, and the
bootstrap's positions of friend 1 after many steps at once those of the poses each step
makes.
"""

from __future__ import annotations

import numpy as np
import pytest

from shared_solver.estimation.camera import Camera, focal_prior
from shared_solver.estimation.pinhole.model import PinholeModel
from shared_solver.estimation.pinhole.pose import PARAMETERS, Poses
from shared_solver.estimation.pinhole.predictions import friend1_positions
from shared_solver.estimation.taps import Gravity, Heading, Taps
from testbed.phones import gravity_reading, phone_scene
from testbed.scenes import line_through

STEP = 1e-6
# Central differences of order-one residuals at this step are good to about 1e-9; a wrong
# term is off by order one.
TOLERANCE = 1e-6
READING_DEG = np.degrees(0.02)  # each phone's gravity reading: 0.02 rad of noise per axis


def model_and_pose(seed: int, marks: str, elongated: bool) -> tuple[PinholeModel, Poses]:
    """A phone scene's noisy taps, its model under the phone prior, and a pose off the truth."""
    rng = np.random.default_rng(seed)
    scene = phone_scene(rng, 6)
    p = scene.landmarks1 + rng.normal(0.0, 3.0, (6, 2))
    q = scene.landmarks2 + rng.normal(0.0, 3.0, (6, 2))
    if elongated:  # each tap its own tilted ellipse
        axes = rng.uniform(1.0, 6.0, (6, 2))
        angles = rng.uniform(0.0, np.pi, 6)
        turn = np.stack(
            [np.cos(angles), -np.sin(angles), np.sin(angles), np.cos(angles)], axis=1
        ).reshape(6, 2, 2)
        cov = turn @ (axes[:, :, None] ** 2 * np.eye(2)) @ turn.transpose(0, 2, 1)
    else:
        cov = np.broadcast_to(9.0 * np.eye(2), (6, 2, 2)).copy()
    e1 = scene.epipole1 + rng.normal(0.0, 3.0, 2)
    e2 = scene.epipole2 + rng.normal(0.0, 3.0, 2)
    line = line_through(e1, 0.7)
    taps = Taps(
        p,
        q,
        cov,
        cov[::-1].copy(),
        epipole1=None if marks == "line" else e1,
        cov_e1=None if marks == "line" else 4.0 * np.eye(2),
        epipole2=e2 if marks == "both" else None,
        cov_e2=4.0 * np.eye(2) if marks == "both" else None,
        line1=line if marks == "line" else None,
        line_sigma=2.0,
        gravity=None
        if marks not in ("gravity", "compass")
        else Gravity(
            gravity_reading(scene.camera1, READING_DEG, rng),
            gravity_reading(scene.camera2, READING_DEG, rng),
            0.02,
            0.01,
        ),
        heading=None
        if marks != "compass"
        else Heading(
            np.radians(scene.camera1.heading) + 0.1, np.radians(scene.camera2.heading), 0.2, 0.3
        ),
    )
    priors = (
        focal_prior(Camera.phone(), scene.image_size1),
        focal_prior(Camera.phone(), scene.image_size2),
    )
    assert priors[0] is not None
    assert priors[1] is not None
    model = PinholeModel(taps, (priors[0], priors[1]))
    # Start from the true geometry, moved off it so no residual is special.
    one, two = scene.camera1, scene.camera2
    truth = Poses.one(
        two.rotation @ one.rotation.T,
        one.rotation @ (two.centre - one.centre),
        np.log([one.intrinsics[0, 0], two.intrinsics[0, 0]]),
    )
    return model, truth.moved(rng.normal(0.0, 0.02, (1, PARAMETERS)))


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("marks", ["friend2", "both", "line", "gravity", "compass"])
@pytest.mark.parametrize("elongated", [False, True])
def test_jacobian_matches_central_differences(seed: int, marks: str, elongated: bool) -> None:
    model, pose = model_and_pose(seed, marks, elongated)
    r, jacobian = model.residuals(pose)
    assert jacobian.shape == (len(r), PARAMETERS)
    for k in range(PARAMETERS):
        step = np.zeros((1, PARAMETERS))
        step[0, k] = STEP
        ahead, _ = model.residuals(pose.moved(step))
        behind, _ = model.residuals(pose.moved(-step))
        numeric = (ahead - behind) / (2 * STEP)
        np.testing.assert_allclose(jacobian[:, k], numeric, atol=TOLERANCE, rtol=1e-5)


@pytest.mark.parametrize("marks", ["friend2", "both", "line", "gravity"])
def test_batched_residuals_equal_the_fits(marks: str) -> None:
    model, pose = model_and_pose(7, marks, elongated=True)
    r, _ = model.residuals(pose)
    np.testing.assert_allclose(model.offsets(pose)[0], r, atol=1e-12, rtol=1e-10)


def test_poses_after_steps_are_the_moved_poses() -> None:
    model, pose = model_and_pose(11, "friend2", elongated=False)
    steps = np.random.default_rng(3).normal(0.0, 0.05, (20, PARAMETERS))
    steps[0] = 0.0  # no turn at all takes the formula's small-angle branch
    batch = pose.after_steps(steps)
    for k, step in enumerate(steps):
        one = pose.moved(step[None])
        np.testing.assert_allclose(batch.rotation[k], one.rotation[0], atol=1e-14)
        np.testing.assert_allclose(batch.friend2[k], one.friend2[0], atol=1e-14)
        np.testing.assert_allclose(batch.log_focals[k], one.log_focals[0], atol=1e-14)
    one_by_one = [friend1_positions(pose.moved(step[None]), model.centres[1])[0] for step in steps]
    np.testing.assert_allclose(friend1_positions(batch, model.centres[1]), one_by_one, rtol=1e-12)
